"""Stresses in spatial beams built with a cross-section (``ModelBuilder.set_section``): the
section resultants at both ends of each beam and the largest von Mises stress, at one
state or at every row of a result.

The resultants are the beam's own share of ``D_x^T sigma``, exact at large rotations: at q
the force ``f_q`` and the moment ``1/2 E(lam_q) f_lam_q`` the beam takes from its end
nodes, at p the negatives of p's, each in the local axes ``R(lam) R0`` of its end node:
the normal force ``N``, the shear forces ``Qy``, ``Qz``, the torque ``T`` and the bending
moments ``My``, ``Mz`` of the q side acting on the p side of a section. Moments vary
linearly and forces are constant along a beam, so the largest stress is at an end; the
section gives it (:meth:`flexmbd.sections.Section.largest_stress`). A warping beam's
torque is the whole (St Venant's and the warping's), and its bimoments ``B_p = -l0^2
sigma_7``, ``B_q = -l0^2 sigma_8`` add the warping's normal stress ``B omega / Cw``
(FLEXURES 4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..elements.base import SPATIAL_ROTATIONAL
from ..elements.warping_beam import BEAM_COLUMNS
from ..engine import element_kernel
from ..errors import ArgumentError
from ..model import Model
from ..orientation import moment_of, rotation_matrix
from ..results import KinematicResult
from ..summary import dataclass_repr

__all__ = ["BeamStress", "StressHistory", "beam_resultants", "beam_stresses", "stress_history"]


@dataclass(frozen=True)
class BeamStress:
    """The stress state of one beam.

    Attributes:
        element: the beam's number.
        resultants: ``(2, 6)``: at p and at q, ``(N, Qy, Qz, T, My, Mz)`` [N, N m] in the end
            node's local axes; a warping beam's ``(2, 7)``, its bimoment ``B`` [N m^2]
            after them.
        von_mises: the largest von Mises stress over the beam [Pa].
        where: the end (``"p"`` or ``"q"``) and the point of the section where it is.
        ends: the largest von Mises stress over the section at p and at q [Pa].
    """

    __repr__ = dataclass_repr

    element: int
    resultants: np.ndarray
    von_mises: float
    where: str
    ends: tuple[float, float] = (0.0, 0.0)


def element_jacobian(element, x: np.ndarray) -> np.ndarray:
    """One element's ``D_x`` ``(nd, nc)`` at ``x`` ``(nx,)``, from its compiled kernel (no
    workspace of the whole model)."""
    nc, nd = len(element.coordinates), len(element.deformations)
    return element_kernel(element, "deform_jac", x, nd * (1 + nc))[nd:].reshape(nd, nc)


def _sectioned(model: Model) -> list[int]:
    return [k for k, element in model.elements.items()
            if element.type.keyword in ("BEAM", "BEAMW")
            and (props := model.element_properties.get(k)) is not None
            and props.section is not None]


def beam_stresses(model: Model, x, sigma, elements=None) -> dict[int, BeamStress]:
    """The stresses of every spatial beam built with a section (or of those numbered in
    ``elements``) at coordinates ``x`` ``(nx,)`` [m, -] and generalized stresses
    ``sigma`` ``(ne,)`` (a result row), by element number.

    Raises:
        ArgumentError: the model has no beam with a section (``set_section``: a ``.dat``
            file carries none), or ``elements`` names another element.
    """
    beams = _sectioned(model)
    if elements is not None:
        others = [k for k in elements if k not in beams]
        if others:
            raise ArgumentError("elements", f"{others} are not spatial beams with a section")
        beams = [k for k in beams if k in set(elements)]
    if not beams:
        raise ArgumentError("model", "no spatial beam has a cross-section: give one with "
                                     "ModelBuilder.set_section (a .dat file carries none)")
    x = np.asarray(x, dtype=float)
    sigma = np.asarray(sigma, dtype=float)
    if x.shape != (model.n_coordinates,) or sigma.shape != (model.n_deformations,):
        raise ArgumentError("x", f"x and sigma must have shapes ({model.n_coordinates},) and "
                                 f"({model.n_deformations},), got {x.shape} and {sigma.shape}")
    out = {}
    for k in beams:
        resultants = beam_resultants(model, x, sigma, k)
        section = model.element_properties[k].section
        assert section is not None
        (stress_p, point_p), (stress_q, point_q) = (section.largest_stress(r)
                                                    for r in resultants)
        von_mises, where = max((stress_p, f"p, {point_p}"), (stress_q, f"q, {point_q}"))
        out[k] = BeamStress(k, resultants, von_mises, where, (stress_p, stress_q))
    return out


def beam_resultants(model: Model, x: np.ndarray, sigma: np.ndarray, k: int) -> np.ndarray:
    """The section resultants of spatial beam ``k`` at both ends ``(2, 6)`` (a warping
    beam's ``(2, 7)``): at p and at q, ``(N, Qy, Qz, T, My, Mz[, B])`` [N, N m, N m^2] in
    the end node's local axes (module docstring), at coordinates ``x`` ``(nx,)`` and
    generalized stresses ``sigma`` ``(ne,)``."""
    element = model.elements[k]
    assert model.nodes[element.nodes[1]].kind == SPATIAL_ROTATIONAL
    coords, defs = list(element.coordinates), list(element.deformations)
    D = element_jacobian(element, x)
    loads = D.T @ sigma[defs]
    warping = element.type.keyword == "BEAMW"
    if warping:   # the beam's columns; the warping nodes' loads are the bimoments
        coords, loads = [coords[j] for j in BEAM_COLUMNS], loads[list(BEAM_COLUMNS)]
    # loads (14,): p, lam_p, q, lam_q
    frame0 = np.array(element.reference[1:10]).reshape(3, 3).T   # columns ex0, ey0, ez0
    ends = []
    for sign, at in ((-1.0, 0), (1.0, 7)):
        lam = x[coords[at + 3:at + 7]]
        axes = rotation_matrix(lam) @ frame0
        force = sign * loads[at:at + 3]
        moment = sign * moment_of(lam, loads[at + 3:at + 7])
        ends.append(np.concatenate([axes.T @ force, axes.T @ moment]))
    if warping:
        l0 = element.reference[0]
        bimoments = -l0**2 * sigma[defs[6:8]]
        ends = [np.append(end, b) for end, b in zip(ends, bimoments, strict=True)]
    return np.array(ends)


@dataclass(frozen=True)
class StressHistory:
    """The largest stresses at every row of a result.

    Attributes:
        t: the rows' times [s] (or load factors).
        elements: the beams with a section, in order.
        von_mises: ``(nt, n_beams)``: each beam's largest von Mises stress [Pa].
        maximum: ``(nt,)``: the model's largest [Pa].
        ends: ``(nt, n_beams, 2)``: each beam's largest at p and at q [Pa] (for pictures,
            :func:`flexmbd.plot.plot_sections`).
    """

    __repr__ = dataclass_repr

    t: np.ndarray
    elements: tuple[int, ...]
    von_mises: np.ndarray
    maximum: np.ndarray
    ends: np.ndarray


def stress_history(result: KinematicResult) -> StressHistory:
    """:func:`beam_stresses` at every row of a result that recorded its stresses (a static
    equilibrium, a simulation, inverse dynamics)."""
    sigma = getattr(result, "sigma", None)
    if sigma is None:
        raise ArgumentError("result", "records no stresses: use a static, simulation or "
                                      "inverse-dynamics result")
    rows = [beam_stresses(result.model, x, s) for x, s in zip(result.x, sigma, strict=True)]
    elements = tuple(_sectioned(result.model))
    values = np.array([[row[k].von_mises for k in elements] for row in rows]).reshape(
        len(rows), len(elements))
    ends = np.array([[row[k].ends for k in elements] for row in rows]).reshape(
        len(rows), len(elements), 2)
    return StressHistory(np.asarray(result.t).copy(), elements, values,
                         values.max(axis=1) if len(elements) else np.zeros(len(rows)), ends)
