"""Whether a SPACAR Light model's numbers fit their units.

SPACAR Light, and so :mod:`flexmbd.light`, takes SI units throughout: m, Pa, kg/m^3,
rad. A number given in another unit (a width in mm, a modulus in GPa, an angle in
degrees) runs without complaint and gives results off by powers of ten (a stroke of
2e-14 m, stresses of 2.7e12 Pa). What can be checked is checked here, each field once:
a value whose size points at another unit is named, with the SI value meant, as a
:class:`~flexmbd.errors.ModelWarning` (shown also in silent runs) and in the run's notes.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import ModelWarning
from ..sections import SOFTEST_MODULUS, material_doubts

__all__ = ["LARGEST_STRESS", "SOFTEST_MODULUS", "check_displacements", "check_material",
           "check_rotation", "check_section", "check_stress"]

#: above this a stress [Pa] is beyond any material's strength (the strongest fibres stay
#: below 1e10 Pa): a unit is off somewhere
LARGEST_STRESS = 1e11


def say(message: str, notes: list[str]) -> None:
    """A number's unit looks wrong: warn (once, also when silent) and note it."""
    warnings.warn(f"flexmbd.light: {message}", ModelWarning, stacklevel=4)
    notes.append(message)


def check_material(where: str, emod: float | None, smod: float | None,
                   dens: float | None, notes: list[str]) -> None:
    """``emod``, ``smod`` [Pa] and ``dens`` [kg/m^3] of set ``where``
    (:func:`flexmbd.sections.material_doubts`, in SPACAR Light's field names)."""
    for doubt in material_doubts(emod, smod, dens, ("emod", "smod", "dens")):
        field = doubt.split(" = ", 1)[0]          # "emod" of one field, or a ratio of two
        say(f"{where}.{doubt}" if field in ("emod", "smod", "dens") else f"{where}: {doubt}",
            notes)


def check_section(where: str, dim, length: float, element: int, notes: list[str]) -> None:
    """A set's section ``dim`` [m] against the length [m] of an element it is given to."""
    if dim and max(dim) > length:
        say(f"{where}.dim = {list(dim)} m is larger than element {element}, {length:.4g} m "
            f"long: dimensions are in m ({max(dim):g} mm is {max(dim) / 1e3:g})", notes)


def check_displacements(props: dict, positions: np.ndarray, notes: list[str]) -> None:
    """Prescribed displacements (``displ_*``, ``displ_initial_*``) [m] of the node
    properties ``props`` (by user node) larger than the whole model, whose size comes from
    ``positions`` ``(n, 3)`` [m]: mm, likely."""
    size = float(np.max(np.ptp(positions, axis=0)))
    for j, p in sorted(props.items()):
        for name, moved in (("displ", p.displ), ("displ_initial", p.displ_initial)):
            for k, value in sorted(moved.items()):
                if size > 0 and abs(value) > size:
                    say(f"nprops({j}).{name}_{'xyz'[k - 1]} = {value:g} m is larger than the "
                        f"whole model ({size:.4g} m across): displacements are in m ({value:g} "
                        f"mm is {value / 1e3:g})", notes)


def check_rotation(where: str, name: str, angle: float) -> None:
    """An input rotation [rad] of more than a turn: degrees, likely."""
    if abs(angle) > 2 * math.pi:
        warnings.warn(f"flexmbd.light: {where}.{name} = {angle:g} rad is more than a turn: "
                      f"rotations are in rad ({angle:g} degrees is "
                      f"{math.radians(angle):.6g})", ModelWarning, stacklevel=5)


def check_stress(stress: np.ndarray, notes: list[str]) -> None:
    """The largest stress [Pa] of the run, beyond any material's strength."""
    largest = float(np.nanmax(stress, initial=0.0))
    if largest > LARGEST_STRESS:
        say(f"the largest stress, {largest:.3g} Pa, is beyond any material's strength: "
            f"check the units of dim (m), emod (Pa), loads (N, N m) and rotations (rad)",
            notes)
