"""Exercise 1, the sliding bar: its parts and flexmbd's answers (EXERCISES 1a-j).

A bar of length ``l0 = 2 m``, end p on the x axis and end q on the y axis. As a truss
(1a-d) ``x = [x_p, y_p, x_q, y_q]`` with ``x_p`` prescribed; as a rigid beam with a
rotational node at p (1e-j) ``x = [x_p, y_p, phi_p, x_q, y_q]`` with ``phi_p``
prescribed, horizontal at ``phi_p = 0``.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..analysis import kinematics as kin
from .parts import Exercise, Mistake, lettered, model_answer, model_reference, negated_rows

L0 = 2.0  #: bar length [m]
DRAWN = math.radians(30.0)  #: the drawn configuration's angle


@functools.cache
def truss():
    """The truss model (``flexmbd.examples.sliding_bar``)."""
    from ..examples.sliding_bar import truss_model

    return truss_model()


@functools.cache
def rigid_beam():
    """The rigid-beam model (``flexmbd.examples.sliding_bar``)."""
    from ..examples.sliding_bar import rigid_beam_model

    return rigid_beam_model()


def _truss_x(x_p: float) -> np.ndarray:
    return kin.solve_position(truss(), np.array([x_p]), np.array([x_p, 0.0, 0.0, 1.0]))


def _beam_x(phi_p: float) -> np.ndarray:
    return kin.solve_position(rigid_beam(), np.array([phi_p]))


def truss_motion(x_p, xd_p, xdd_p, quadratic=True):
    x = _truss_x(x_p)
    xd = kin.velocities(truss(), x, np.array([xd_p]))
    xdd = kin.accelerations(truss(), x, xd if quadratic else 0 * xd, np.array([xdd_p]))
    return np.array([xd[3], xdd[3]])


def beam_motion(phi_p, omega, omegad, quadratic=True):
    x = _beam_x(phi_p)
    xd = kin.velocities(rigid_beam(), x, np.array([omega]))
    xdd = kin.accelerations(rigid_beam(), x, xd if quadratic else 0 * xd, np.array([omegad]))
    return np.array([xdd[0], xdd[4]])


def _any_truss_x(rng):
    return [(np.array([-math.sqrt(3.0), 0.0, 0.0, 1.0]),)] + [
        (rng.uniform(-2.0, 2.0, 4),) for _ in range(3)]


def _any_beam_x(rng):
    return [(np.array([-math.sqrt(3.0), 0.0, DRAWN, 0.0, 1.0]),)] + [
        (rng.uniform(-2.0, 2.0, 5),) for _ in range(3)]


def _x_p(rng):
    return [(-math.sqrt(3.0),)] + [(v,) for v in rng.uniform(-1.9, -0.2, 3)]


def _phi(rng, rates: int = 0):
    """``phi_p`` (and ``rates`` of its derivatives): 30 degrees, omega = 4, omegad =
    -16 sqrt(3) first, then random."""
    drawn = (DRAWN, 4.0, -16.0 * math.sqrt(3.0))[:1 + rates]
    return [drawn] + [(rng.uniform(0.1, 1.4), *rng.uniform(-5, 5, rates)) for _ in range(3)]


_BENDING = ("the rigid beam's bending is e2 = n_p . d with n_p = (-sin(beta0 + phi_p), "
            "cos(beta0 + phi_p)) and d = r_q - r_p; you have the opposite sign")
_QUADRATIC = ("the acceleration needs the quadratic velocity term: D_c xdd_c = -D_m xdd_m "
              "- (D_xx xd) xd")
_ELONGATION = "the elongation is the length minus l0, e1 = |r_q - r_p| - l0"


_elongation = model_answer(truss, "deformations")
_beam_deformations = model_answer(rigid_beam, "deformations")
_beam_jacobian = model_answer(rigid_beam, "jacobian")


EXERCISE = Exercise(
    1, "sliding-bar", "Sliding bar: a truss (1a-d), then a rigid beam (1e-j)",
    "a bar of length l0 = 2, end p on the x axis, end q on the y axis", lettered(
        dict(function="truss_elongation", arguments="x",
             returns="e1 = l - l0 [m] of the truss p-q at x = [x_p, y_p, x_q, y_q]",
             hint="e1 = |r_q - r_p| - l0",
             answer=_elongation, cases=_any_truss_x,
             symbolic=model_reference(truss, "deformations"),
             mistakes=(Mistake(_ELONGATION, lambda x: _elongation(x) + L0),)),
        dict(function="truss_jacobian", arguments="x", returns="D_x (1, 4): de1/dx",
             hint="differentiate e1 with respect to each of x_p, y_p, x_q, y_q: a row "
                  "(1, 4)",
             answer=model_answer(truss, "jacobian"),
             cases=_any_truss_x, symbolic=model_reference(truss, "jacobian")),
        dict(function="truss_position", iterative=True, arguments="x_p",
             returns="y_q [m] by Newton-Raphson from y_q = 1",
             hint="iterate y_q -= e1 / (de1/dy_q) from y_q = 1 until |e1| < 1e-12",
             answer=lambda x_p: _truss_x(x_p)[3], cases=_x_p),
        dict(function="truss_motion", arguments="x_p, xd_p, xdd_p",
             returns="(yd_q, ydd_q) [m/s, m/s^2] from the partitioned Jacobian and the "
                     "quadratic velocity term",
             hint="D_c yd_q = -D_m xd_p; D_c ydd_q = -D_m xdd_p - (D_xx xd) xd",
             answer=truss_motion,
             cases=lambda rng: [(-math.sqrt(3.0), 4.0, 0.0)] + [
                 (rng.uniform(-1.9, -0.2), *rng.uniform(-5, 5, 2)) for _ in range(3)],
             mistakes=(Mistake(_QUADRATIC, functools.partial(truss_motion, quadratic=False)),)),
        dict(function="rigid_beam_deformations", arguments="x",
             returns="(e1, e2) [m] of the rigid beam at x = [x_p, y_p, phi_p, x_q, y_q], "
                     "beta0 = 0",
             hint="e1 = |d| - l0, e2 = n_p . d with d = r_q - r_p, n_p = (-sin phi_p, "
                  "cos phi_p)",
             answer=_beam_deformations, cases=_any_beam_x,
             symbolic=model_reference(rigid_beam, "deformations"),
             mistakes=(Mistake(_BENDING, negated_rows(_beam_deformations, [1])),)),
        dict(function="rigid_beam_jacobian", arguments="x", returns="D_x (2, 5)",
             hint="rows e1, e2; columns x_p, y_p, phi_p, x_q, y_q",
             answer=_beam_jacobian, cases=_any_beam_x,
             symbolic=model_reference(rigid_beam, "jacobian"),
             mistakes=(Mistake(_BENDING, negated_rows(_beam_jacobian, [1])),)),
        dict(function="rigid_beam_position", iterative=True, arguments="phi_p",
             returns="(x_p, y_q) [m] by Newton-Raphson",
             hint="Newton on (e1, e2) = 0 for the dependent x_p, y_q",
             answer=lambda phi: _beam_x(phi)[[0, 4]], cases=_phi, angles=(0,)),
        dict(function="rigid_beam_velocities", arguments="phi_p, omega",
             returns="(xd_p, yd_q) [m/s]",
             hint="D_c [xd_p, yd_q] = -D_m omega",
             answer=lambda phi, omega: kin.velocities(rigid_beam(), _beam_x(phi),
                                                      np.array([omega]))[[0, 4]],
             cases=lambda rng: _phi(rng, 1), angles=(0,)),
        dict(function="rigid_beam_quadratic", arguments="x, xd",
             returns="(D_xx xd) xd (2,) [m/s^2]",
             hint="e1: (dv.dv - (e_l.dv)^2)/l; e2: -w^2 (n_p . d) - 2 w (e_p . dv)",
             answer=lambda x, xd: kin.quadratic_velocity(rigid_beam(), np.asarray(x, float),
                                                         np.asarray(xd, float)),
             cases=lambda rng: [(np.array([-math.sqrt(3.0), 0.0, DRAWN, 0.0, 1.0]),
                                 np.array([4.0, 0.0, 4.0, 0.0, 4 * math.sqrt(3.0)]))] + [
                 (rng.uniform(-2, 2, 5), rng.uniform(-5, 5, 5)) for _ in range(3)],
             symbolic=model_reference(rigid_beam, "quadratic_velocity")),
        dict(function="rigid_beam_accelerations", arguments="phi_p, omega, omegad",
             returns="(xdd_p, ydd_q) [m/s^2]",
             hint="D_c xdd_c = -D_m omegad - (D_xx xd) xd",
             answer=beam_motion, cases=lambda rng: _phi(rng, 2), angles=(0,),
             mistakes=(Mistake(_QUADRATIC, functools.partial(beam_motion, quadratic=False)),)),
    ), module="sliding_bar")
