"""Physical properties of a model: masses, stiffness, damping, loads (SPACAR block 2).

All values are SI: masses in kg, mass per length in kg/m, rotary inertia in
kg m^2, axial stiffness ``EA`` in N, bending stiffness ``EI`` in N m^2, shear
stiffness ``GA_s`` in N, hinge stiffness in N m/rad, forces in N, torques in N m.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

MassFormulation = Literal["consistent", "lumped"]


@dataclass(frozen=True)
class ElementProperties:
    """Properties of one element; every field defaults to 'none'.

    Attributes:
        mass_per_length: ``rhoA`` [kg/m]; the element mass is ``rhoA * l0``.
        mass_formulation: ``"consistent"`` or ``"lumped"`` (THEORY section 5).
        axial_stiffness: ``EA`` [N]; elongation stress ``EA / l0 * e1``.
        bending_stiffness: ``EI`` [N m^2] of a beam.
        shear_stiffness: ``G A_s`` [N] for Timoshenko shear correction; ``None``
            for Euler-Bernoulli bending.
        hinge_stiffness: torsional spring of a hinge [N m/rad].
        axial_damping: ``c_A`` [N s]; elongation stress ``c_A / l0 * e1dot``
            (the viscous twin of ``EA``).
        bending_damping: ``c_I`` [N m^2 s]; bending stress with the matrix of
            ``EI`` (Euler-Bernoulli form) and ``c_I`` in place of ``EI``.
        hinge_damping: rotational damper of a hinge [N m s/rad].
        prestress: ``sigma0`` per deformation (tuple of the element's length).
    """

    mass_per_length: float = 0.0
    mass_formulation: MassFormulation = "consistent"
    axial_stiffness: float = 0.0
    bending_stiffness: float = 0.0
    shear_stiffness: float | None = None
    hinge_stiffness: float = 0.0
    axial_damping: float = 0.0
    bending_damping: float = 0.0
    hinge_damping: float = 0.0
    prestress: tuple[float, ...] | None = None


@dataclass(frozen=True, eq=False)
class GroupProperties:
    """The properties of one element group as arrays of shape ``(n,)``, for the kernels."""

    mass: np.ndarray  #: element mass ``rhoA * l0`` [kg]
    lumped: np.ndarray  #: bool, lumped mass formulation
    axial_stiffness: np.ndarray
    bending_stiffness: np.ndarray
    shear_stiffness: np.ndarray  #: 0 where Euler-Bernoulli
    hinge_stiffness: np.ndarray
    axial_damping: np.ndarray
    bending_damping: np.ndarray
    hinge_damping: np.ndarray
    prestress: np.ndarray  #: shape ``(n, nd)``


def group_properties(group, properties: dict[int, ElementProperties]) -> GroupProperties:
    """Collect the properties of the elements of ``group`` into arrays."""
    props = [properties.get(int(n), ElementProperties()) for n in group.numbers]
    nd = group.type.n_deformations()

    def column(name):
        return np.array([getattr(p, name) or 0.0 for p in props], dtype=float)

    prestress = np.array([p.prestress if p.prestress is not None else (0.0,) * nd
                          for p in props], dtype=float).reshape(len(props), nd)
    return GroupProperties(
        mass=column("mass_per_length") * group.reference.length,
        lumped=np.array([p.mass_formulation == "lumped" for p in props]),
        axial_stiffness=column("axial_stiffness"),
        bending_stiffness=column("bending_stiffness"),
        shear_stiffness=column("shear_stiffness"),
        hinge_stiffness=column("hinge_stiffness"),
        axial_damping=column("axial_damping"),
        bending_damping=column("bending_damping"),
        hinge_damping=column("hinge_damping"),
        prestress=prestress,
    )
