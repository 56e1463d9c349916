"""Exercise 2, slider-crank kinematics: its parts and flexmbd's answers (EXERCISES 2).

Crank O-A (``l1 = 1``) and rod A-B (``l2 = sqrt(3)``), two rigid beams;
``x = [x1, y1, phi2, x3, y3, phi4, x5, y5]`` with ``phi2`` the input.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..analysis import kinematics as kin
from .parts import (
    Exercise,
    Mistake,
    Probe,
    lettered,
    model_answer,
    model_reference,
    negated_rows,
)

DRAWN = math.pi / 3  #: the drawn configuration, phi2 = 60 degrees


@functools.cache
def model():
    """The slider-crank of ``flexmbd.examples.slider_crank_kinematics``."""
    from ..examples.slider_crank_kinematics import build_model

    return build_model()


def configuration(phi2: float) -> np.ndarray:
    """``x`` at crank angle ``phi2`` [rad], slider to the right of O."""
    from ..examples.slider_crank_kinematics import closed_form

    guess = np.array(model().x0, dtype=float)
    guess[2] = phi2
    for label, (value, _, _) in closed_form(phi2).items():
        guess[model().coordinate_index(label)] = value
    return kin.solve_position(model(), np.array([phi2]), guess)


def other_branch(phi2):
    """``(x3, y3, phi4, x5)`` of the other assembly branch: the slider left of the crank pin,
    the rod turned to ``pi - phi4``."""
    x3, y3, phi4, _ = configuration(phi2)[[3, 4, 5, 6]]
    turned = math.pi - phi4
    return np.array([x3, y3, turned, x3 + math.sqrt(3.0) * math.cos(turned)])


def accelerations(phi2, phi2d, phi2dd, quadratic=True):
    x = configuration(phi2)
    xd = kin.velocities(model(), x, np.array([phi2d]))
    return kin.accelerations(model(), x, xd if quadratic else 0 * xd, np.array([phi2dd]))


def _second_order(phi2):
    return kin.second_order_transfer(model(), configuration(phi2))


def _x(rng):
    return [(configuration(DRAWN),)] + [(rng.uniform(-2, 2, 8),) for _ in range(3)]


def _phi(rng, rates: int = 0):
    return [(DRAWN, 2 * math.pi, 2 * math.pi)[:1 + rates]] + [
        (rng.uniform(-math.pi, math.pi), *rng.uniform(-10, 10, rates)) for _ in range(3)]


_BENDING = ("the rigid beams' bending is e2 = n_p . d with n_p = (-sin(beta0 + phi), "
            "cos(beta0 + phi)) and d = r_q - r_p; your rows e1.2, e2.2 have the opposite sign")
_QUADRATIC = ("accelerations need the quadratic velocity term: xdd = F_q phi2dd + F_qq "
              "phi2d^2, i.e. D_c xdd_c = -D_m phi2dd - (D_xx xd) xd")


def _probes(rng, second: bool) -> list[Probe]:
    """E_q and E_qq are zero at every consistent state of the rigid slider-crank, so a
    formula shows only with other F_q (and F_qq): the student's part is called while its
    first_order_transfer (and velocities, second_order_transfer) return random ones."""
    probes = []
    for phi2 in (DRAWN, rng.uniform(-math.pi, math.pi)):
        x = configuration(phi2)
        F, F2 = rng.normal(size=(2, 8, 1))
        D = kin.jacobian(model(), x)
        substitutes = {"first_order_transfer": F, "velocities": F[:, 0]}
        if second:
            substitutes["second_order_transfer"] = F2
            expected = D @ F2 + kin.quadratic_velocity(model(), x, F[:, 0])[:, None]
            uses = ("E_qq = D_x F_qq + (D_xx F_q) F_q made of your parts b, e and g "
                    "(jacobian, first_order_transfer, second_order_transfer)")
        else:
            expected, uses = D @ F, ("E_q = D_x F_q made of your parts b and e (jacobian, "
                                     "first_order_transfer)")
        probes.append(Probe((phi2,), substitutes, expected, uses))
    return probes


_deformations = model_answer(model, "deformations")
_jacobian = model_answer(model, "jacobian")


EXERCISE = Exercise(
    2, "slider-crank-kinematics", "Slider-crank kinematics: two rigid beams",
    "crank O-A (l1 = 1) and rod A-B (l2 = sqrt(3)); x = [x1, y1, phi2, x3, y3, phi4, x5, "
    "y5]; phi2 the input", lettered(
        dict(function="deformations", arguments="x",
             returns="e (4,) [m]: the two rigid beams' elongations and bendings",
             hint="per rigid beam: e1 = |d| - l0, e2 = n_p . d (beta0 = 0 for both)",
             answer=_deformations, cases=_x, symbolic=model_reference(model, "deformations"),
             mistakes=(Mistake(_BENDING, negated_rows(_deformations, [1, 3])),)),
        dict(function="jacobian", arguments="x", returns="D (4, 8): D_x, columns in the "
                                                          "order of x",
             hint="one row per deformation, one column per coordinate of x",
             answer=_jacobian, cases=_x, symbolic=model_reference(model, "jacobian"),
             mistakes=(Mistake(_BENDING, negated_rows(_jacobian, [1, 3])),)),
        dict(function="positions", iterative=True, arguments="phi2",
             returns="(x3, y3, phi4, x5) by Newton-Raphson",
             hint="Newton on e = 0 for the dependent coordinates, from the drawn "
                  "configuration",
             answer=lambda phi2: configuration(phi2)[[3, 4, 5, 6]], cases=_phi, angles=(0,),
             wrapped=lambda phi2: (2,),
             mistakes=(Mistake("your Newton-Raphson converged to the other assembly branch "
                               "(the slider left of the crank pin): start it from the drawn "
                               "configuration, drawn_guess(phi2)", other_branch),)),
        dict(function="velocities", arguments="phi2, phi2d",
             returns="xd (8,) from the partitioned Jacobian",
             hint="D_c xd_c = -D_m phi2d; the fixed rates are 0",
             answer=lambda phi2, phi2d: kin.velocities(model(), configuration(phi2),
                                                       np.array([phi2d])),
             cases=lambda rng: _phi(rng, 1), angles=(0,)),
        dict(function="first_order_transfer", arguments="phi2",
             returns="F_q (8, 1) = dx/dphi2",
             hint="the velocities for phi2d = 1",
             answer=lambda phi2: kin.first_order_transfer(model(), configuration(phi2)),
             cases=_phi, angles=(0,)),
        dict(function="deformation_transfer", arguments="phi2",
             returns="E_q (4, 1) = D_x F_q (zero: all rigid)",
             hint="E_q = D_x F_q, from your parts b and e",
             answer=lambda phi2: kin.deformation_transfer(model(), configuration(phi2)),
             cases=_phi, angles=(0,), probes=lambda rng: _probes(rng, second=False)),
        dict(function="second_order_transfer", arguments="phi2",
             returns="F_qq (8, 1): d^2x/dphi2^2",
             hint="the accelerations for phi2d = 1, phi2dd = 0",
             answer=lambda phi2: _second_order(phi2)[0][:, :, 0], cases=_phi, angles=(0,),
             mistakes=(Mistake("F_qq is the derivative of F_q along phi2, not F_q itself",
                               lambda phi2: kin.first_order_transfer(
                                   model(), configuration(phi2))),
                       Mistake("F_qq is not zero: the crank turning at a constant rate still "
                               "accelerates the rod and the slider (D_c F_qq_c = -(D_xx F_q) "
                               "F_q)", lambda phi2: np.zeros((8, 1))))),
        dict(function="deformation_second_order", arguments="phi2", returns="E_qq (4, 1)",
             hint="E_qq = D_x F_qq + (D_xx F_q) F_q, from your parts b, e and g",
             answer=lambda phi2: _second_order(phi2)[1][:, :, 0], cases=_phi, angles=(0,),
             probes=lambda rng: _probes(rng, second=True)),
        dict(function="accelerations", arguments="phi2, phi2d, phi2dd",
             returns="xdd (8,) = F_q phi2dd + F_qq phi2d^2",
             hint="xdd = F_q phi2dd + F_qq phi2d^2",
             answer=accelerations, cases=lambda rng: _phi(rng, 2), angles=(0,),
             mistakes=(Mistake(_QUADRATIC, functools.partial(accelerations, quadratic=False)),)),
    ), module="slider_crank_kinematics")
