"""The course's exercises and their lettered parts.

Each part is one function the student writes: its name, its arguments and what it
returns, in the course's symbols and units. The lettering follows the course's four
exercises: 1a-d the sliding bar as a truss, 1e-j as a rigid beam; 2 the slider-crank's
kinematics; 3 its rigid dynamics; 4 the flexible slider-crank, part 1 with one beam and
part 2 with ``nbeams`` beams and an optionally flexible elongation. Each exercise's
parts, with flexmbd's answers and the typical mistakes, are in its own module.
"""

from __future__ import annotations

from ..errors import ArgumentError
from . import slider_crank_dynamics, slider_crank_flex, slider_crank_kinematics, sliding_bar
from .parts import Exercise, Part

__all__ = ["EXERCISES", "Exercise", "Part", "exercise"]

#: the exercises by name, in the course's order
EXERCISES = {module.EXERCISE.name: module.EXERCISE for module in (
    sliding_bar, slider_crank_kinematics, slider_crank_dynamics, slider_crank_flex)}


def exercise(name: str | int) -> Exercise:
    """The exercise by name (``"sliding-bar"``) or number (``1``)."""
    for candidate in EXERCISES.values():
        if name in (candidate.name, candidate.number, str(candidate.number)):
            return candidate
    raise ArgumentError("exercise", f"unknown exercise {name!r}; choose from "
                                    f"{', '.join(EXERCISES)} (or 1 to {len(EXERCISES)})")
