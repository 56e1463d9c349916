"""The course's exercises and their lettered parts.

Each part is one function the student writes: its name, its arguments and what it
returns, in the course's symbols and units. The lettering follows the course's four
exercises: 1a-d the sliding bar as a truss, 1e-j as a rigid beam; 2 the slider-crank's
kinematics; 3 its rigid dynamics; 4 the flexible slider-crank, part 1 with one beam and
part 2 with ``nbeams`` beams and an optionally flexible elongation.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ArgumentError


@dataclass(frozen=True)
class Part:
    """One part of an exercise.

    Attributes:
        letter: ``"a"``, ``"b"``, ...
        function: the name of the function the student writes.
        arguments: its arguments, as written in its signature.
        returns: what it returns, with shapes and units.
    """

    letter: str
    function: str
    arguments: str
    returns: str


@dataclass(frozen=True)
class Exercise:
    """One exercise: its number, command name, title, the model it is about and parts."""

    number: int
    name: str
    title: str
    model: str
    parts: tuple[Part, ...]

    def part(self, letter: str) -> Part:
        """The part with ``letter``."""
        for part in self.parts:
            if part.letter == letter:
                return part
        raise ArgumentError("part", f"exercise {self.number} has parts "
                                    f"{', '.join(p.letter for p in self.parts)}, not {letter!r}")


def _parts(*rows: tuple[str, str, str]) -> tuple[Part, ...]:
    """Parts lettered a, b, ... in order from ``(function, arguments, returns)`` rows."""
    return tuple(Part(chr(ord("a") + k), *row) for k, row in enumerate(rows))


SLIDING_BAR = Exercise(
    1, "sliding-bar", "Sliding bar: a truss (1a-d), then a rigid beam (1e-j)",
    "a bar of length l0 = 2, end p on the x axis, end q on the y axis",
    _parts(
        ("truss_elongation", "x", "e1 = l - l0 [m] of the truss p-q at x = [x_p, y_p, x_q, "
                                  "y_q]"),
        ("truss_jacobian", "x", "D_x (1, 4): de1/dx"),
        ("truss_position", "x_p", "y_q [m] by Newton-Raphson from y_q = 1"),
        ("truss_motion", "x_p, xd_p, xdd_p",
         "(yd_q, ydd_q) [m/s, m/s^2] from the partitioned Jacobian and the quadratic "
         "velocity term"),
        ("rigid_beam_deformations", "x",
         "(e1, e2) [m] of the rigid beam at x = [x_p, y_p, phi_p, x_q, y_q], beta0 = 0"),
        ("rigid_beam_jacobian", "x", "D_x (2, 5)"),
        ("rigid_beam_position", "phi_p", "(x_p, y_q) [m] by Newton-Raphson"),
        ("rigid_beam_velocities", "phi_p, omega", "(xd_p, yd_q) [m/s]"),
        ("rigid_beam_quadratic", "x, xd", "(D_xx xd) xd (2,) [m/s^2]"),
        ("rigid_beam_accelerations", "phi_p, omega, omegad", "(xdd_p, ydd_q) [m/s^2]"),
    ))

SLIDER_CRANK_KINEMATICS = Exercise(
    2, "slider-crank-kinematics", "Slider-crank kinematics: two rigid beams",
    "crank O-A (l1 = 1) and rod A-B (l2 = sqrt(3)); x = [x1, y1, phi2, x3, y3, phi4, x5, "
    "y5]; phi2 the input",
    _parts(
        ("deformations", "x", "e (4,) [m]: the two rigid beams' elongations and bendings"),
        ("jacobian", "x", "D (4, 8): D_x, columns in the order of x"),
        ("positions", "phi2", "(x3, y3, phi4, x5) by Newton-Raphson"),
        ("velocities", "phi2, phi2d", "xd (8,) from the partitioned Jacobian"),
        ("first_order_transfer", "phi2", "F_q (8, 1) = dx/dphi2"),
        ("deformation_transfer", "phi2", "E_q (4, 1) = D_x F_q (zero: all rigid)"),
        ("second_order_transfer", "phi2", "F_qq (8, 1): d^2x/dphi2^2"),
        ("deformation_second_order", "phi2", "E_qq (4, 1)"),
        ("accelerations", "phi2, phi2d, phi2dd", "xdd (8,) = F_q phi2dd + F_qq phi2d^2"),
    ))

SLIDER_CRANK_DYNAMICS = Exercise(
    3, "slider-crank-dynamics", "Slider-crank dynamics: the rigid mechanism with masses",
    "the slider-crank of exercise 2 with the rod's mass m2 spread over it and m5 at the "
    "slider",
    _parts(
        ("rod_mass_lumped", "x, m2", "M (5, 5) [kg, kg m^2]: lumped rod mass over [x3, y3, "
                                     "phi4, x5, y5]"),
        ("rod_mass_consistent", "x, m2", "M (5, 5): consistent rod mass"),
        ("reduced_mass_lumped", "phi2, m2, m5", "Mbar (1, 1) [kg m^2] with the lumped rod"),
        ("reduced_mass_consistent", "phi2, m2, m5", "Mbar (1, 1) with the consistent rod"),
        ("driving_torque", "phi2, phi2d, phi2dd, m2, m5", "tau2 [N m] (inverse dynamics)"),
        ("constraint_stresses", "phi2, phi2d, phi2dd, m2, m5",
         "sigma(o) (4,) [N, N m]: the rigid deformations' stresses"),
        ("reactions", "phi2, phi2d, phi2dd, m2, m5", "f(o) [N]: the support reactions at O "
                                                    "and the slider's y"),
        ("pd_simulation", "t_end, kp, kd", "(t, phi2, tau2): the crank driven by a PD "
                                           "controller that tracks a reference angle"),
    ))

SLIDER_CRANK_FLEX = Exercise(
    4, "slider-crank-flex", "Flexible slider-crank: one beam (4a-d), then nbeams (4e-g)",
    "l1 = 0.15, l2 = 0.30, crank at 150 rad/s, m2 = 0.06676, m5 = m2/2, EI = 12.72",
    _parts(
        ("transfer", "phi2, e2, e3", "F_q (nx, 3) of the one-beam rod, q = [phi2, e2, e3]"),
        ("beam_mass", "x, xd", "(M (6, 6), h (6,)): the beam's consistent mass and its "
                               "velocity term"),
        ("reduced_equations", "q, qd, qdd_r",
         "(Mbar_dd, f_d): Mbar_dd qdd_d = f_d - Mbar_dr qdd_r"),
        ("simulate_one_beam", "t_end", "(t, v_over_l2): the rod's mid-point deflection"),
        ("positions", "q, nbeams, eps1flex", "x by Newton-Raphson for n beams"),
        ("quadratic_terms", "x, xd, nbeams", "(D_xx xd) xd of every element"),
        ("simulate", "t_end, nbeams, eps1flex", "(t, v_over_l2) for n beams"),
    ))

#: the exercises by name, in the course's order
EXERCISES = {e.name: e for e in (SLIDING_BAR, SLIDER_CRANK_KINEMATICS, SLIDER_CRANK_DYNAMICS,
                                 SLIDER_CRANK_FLEX)}


def exercise(name: str | int) -> Exercise:
    """The exercise by name (``"sliding-bar"``) or number (``1``)."""
    for candidate in EXERCISES.values():
        if name in (candidate.name, candidate.number, str(candidate.number)):
            return candidate
    raise ArgumentError("exercise", f"unknown exercise {name!r}; choose from "
                                    f"{', '.join(EXERCISES)} (or 1 to {len(EXERCISES)})")
