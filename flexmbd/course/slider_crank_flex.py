"""Exercise 4, the flexible slider-crank: its parts and flexmbd's answers (EXERCISES 4).

The model of ``flexmbd.examples.slider_crank_flex``: crank ``l1 = 0.15 m`` (rigid,
massless), rod ``l2 = 0.30 m`` of ``nbeams`` beams (``EI = 12.72 N m^2``, mass
``m2 = 0.06676 kg``), slider ``m5 = m2/2``, crank at 150 rad/s. Part 1 (4a-f): one
beam, ``x = [x1, y1, phi2, x3, y3, phi3, x5, y5, phi5]`` (the rod's end rotations are
nodes 4 and 6), ``q = [phi2, e2, e3]``. Part 2 (4g-h): ``nbeams`` beams, the elongation
optionally flexible (``eps1flex``).
"""

from __future__ import annotations

import functools

import numpy as np

from ..analysis import kinematics as kin
from ..analysis.dynamics import inverse_dynamics, reduced_mass_matrix
from ..engine import Workspace
from ..motion import Polynomial
from .parts import Exercise, Mistake, lettered, negated_rows, without_nodal_masses

BEAM = [3, 4, 5, 6, 7, 8]  #: the one-beam rod's coordinates in x
STRAIN = [2, 3, 4]  #: its deformations e2.1, e2.2, e2.3 in e
M2, L2 = 0.06676, 0.30  #: rod mass [kg] and length [m]


@functools.cache
def model(nbeams: int = 1, eps1flex: bool = False):
    """The flexible slider-crank of ``flexmbd.examples.slider_crank_flex``."""
    from ..examples.slider_crank_flex import build_model

    return build_model(nbeams, eps1flex)


@functools.cache
def rod_only():
    return without_nodal_masses(model())


def _with_beam(xe, at=None) -> np.ndarray:
    x = np.array(model().x0 if at is None else at, dtype=float)
    x[BEAM] = xe
    return x


def beam_deformations(xe):
    return kin.deformations(model(), _with_beam(xe))[STRAIN]


def beam_jacobian(xe):
    return kin.jacobian(model(), _with_beam(xe))[np.ix_(STRAIN, BEAM)]


def beam_quadratic(xe, xed):
    return kin.quadratic_velocity(model(), _with_beam(xe), _with_beam(xed, np.zeros(9)))[STRAIN]


def beam_mass(xe, xed, velocity_term=True):
    M, h, _ = Workspace(rod_only()).mass(_with_beam(xe), _with_beam(xed, np.zeros(9)))
    return M[np.ix_(BEAM, BEAM)], h[BEAM] if velocity_term else np.zeros(6)


def configuration(q, nbeams: int = 1, eps1flex: bool = False) -> np.ndarray:
    """``x`` for ``q`` [rad, m] from the straight rod."""
    return kin.solve_position(model(nbeams, eps1flex), np.asarray(q, dtype=float))


def dynamic_accelerations(x, qd, quadratic=True):
    """``[e2dd, e3dd]`` at constant crank speed: ``Mbar_dd qdd_d = f_d`` (THEORY 7)."""
    x = np.asarray(x, dtype=float)
    q = np.array([x[2], *kin.deformations(model(), x)[[3, 4]]])
    rates = np.asarray(qd, dtype=float) if quadratic else np.zeros(3)
    run = inverse_dynamics(model(), [0.0], inputs={
        label: Polynomial(q[j], rates[j], 0.0) for j, label in enumerate(model().q_labels)})
    Mbar = reduced_mass_matrix(model(), x)
    return np.linalg.solve(Mbar[1:, 1:], -run.driving[0, 1:])


def half_velocity_terms(x, qd, keep: str):
    """:func:`dynamic_accelerations` with one of the two velocity terms of ``f_d`` left out:
    ``keep="h"`` drops ``-F_q^T M (F_qq qd) qd``, ``keep="F_qq"`` drops ``-F_q^T h``."""
    x, qd = np.asarray(x, dtype=float), np.asarray(qd, dtype=float)
    m = model()
    F_q = kin.first_order_transfer(m, x)
    F_qq = kin.second_order_transfer(m, x)[0]
    M, h, _ = Workspace(m).mass(x, F_q @ qd)
    term = {"h": F_q.T @ (M @ np.einsum("ijk,j,k->i", F_qq, qd, qd)),
            "F_qq": F_q.T @ h}[keep]
    Mbar = reduced_mass_matrix(m, x)
    full = Mbar[1:, 1:] @ dynamic_accelerations(x, qd)
    return np.linalg.solve(Mbar[1:, 1:], full + term[1:])


def _angles(q, nbeams=1, eps1flex=False) -> list[int]:
    """The coordinates of the rotational nodes in ``x`` of ``nbeams`` beams."""
    m = model(int(nbeams), bool(eps1flex))
    return [i for node in m.nodes.values() if node.kind == "rotational"
            for i in node.coordinates]


def midpoint(x, nbeams):
    from ..examples.slider_crank_flex import midpoint_deflection

    return midpoint_deflection(model(int(nbeams)), np.asarray(x, dtype=float))[0]


def _beam_states(rng, rates: bool = False):
    drawn = np.array([0.15, 0.0, 0.0, 0.45, 0.0, 0.0])
    states = [drawn] + [drawn + rng.uniform(-0.02, 0.02, 6) * [1, 1, 5, 1, 1, 5]
                        for _ in range(3)]
    if not rates:
        return [(s,) for s in states]
    return [(s, rng.uniform(-20, 20, 6) * [1, 1, 100, 1, 1, 100]) for s in states]


def _q(rng):
    return [np.array([0.0, 0.0, 0.0])] + [np.array([rng.uniform(-1, 1),
                                                   *rng.uniform(-2e-3, 2e-3, 2)])
                                          for _ in range(3)]


_BENDING = ("the beam's bending deformations are e2 = -n_p . d and e3 = n_q . d (n = the "
            "left normal of the end tangent, d = r_q - r_p): e2 ~ l theta_p, e3 ~ -l theta_q")
_QUADRATIC = ("the right-hand side needs the velocity terms: f_d = F_q^T (f - h - M (F_qq "
              "qd) qd) - E_q^T sigma")


def _bending_mistakes(function) -> tuple[Mistake, ...]:
    """The answer with the sign of e2, of e3 or of both reversed."""
    return tuple(Mistake(_BENDING, negated_rows(function, rows)) for rows in ([1], [2], [1, 2]))


def _symbolic_beam(function: str):
    def reference():
        import sympy as sp

        from ..analysis import symbolic

        names = [str(symbolic.coordinate_symbols(model())[i]) for i in BEAM]
        expr = getattr(symbolic, function)(model())
        if function == "jacobian":
            return [names], sp.Matrix(expr.extract(STRAIN, BEAM))
        return [names], sp.Matrix(expr.extract(STRAIN, [0]))
    return reference


def _positions_cases(rng):
    cases = [(np.array([0.0, 0.0, 0.0]), 1, False)]
    for nbeams, eps1flex in ((1, False), (2, False), (3, True)):
        per = 3 if eps1flex else 2
        q = np.concatenate([[rng.uniform(-1, 1)], rng.uniform(-1e-3, 1e-3, per * nbeams)])
        cases.append((q, nbeams, eps1flex))
    return cases


def _midpoint_cases(rng):
    return [(configuration(q, n, flex), n) for q, n, flex in _positions_cases(rng)]


EXERCISE = Exercise(
    4, "slider-crank-flex", "Flexible slider-crank: one beam (4a-f), then nbeams (4g-h)",
    "l1 = 0.15, l2 = 0.30, crank at 150 rad/s, m2 = 0.06676, m5 = m2/2, EI = 12.72", lettered(
        dict(function="beam_deformations", arguments="xe",
             returns="(e1, e2, e3) [m] of the rod beam at xe = [x_p, y_p, phi_p, x_q, y_q, "
                     "phi_q] (l0 = 0.30, beta0 = 0)",
             hint="e1 = |d| - l0, e2 = -n_p . d, e3 = n_q . d",
             answer=beam_deformations, cases=_beam_states,
             symbolic=_symbolic_beam("deformations"),
             mistakes=_bending_mistakes(beam_deformations)),
        dict(function="beam_jacobian", arguments="xe", returns="D_x (3, 6) of the beam",
             hint="differentiate (e1, e2, e3) with respect to the six element coordinates",
             answer=beam_jacobian, cases=_beam_states, symbolic=_symbolic_beam("jacobian"),
             mistakes=_bending_mistakes(beam_jacobian)),
        dict(function="beam_quadratic", arguments="xe, xed",
             returns="(D_xx xed) xed (3,) [m/s^2] of the beam",
             hint="e2: w_p^2 (n_p . d) + 2 w_p (e_p . dv); e3: -w_q^2 (n_q . d) - 2 w_q "
                  "(e_q . dv)",
             answer=beam_quadratic, cases=lambda rng: _beam_states(rng, True),
             mistakes=_bending_mistakes(beam_quadratic)),
        dict(function="beam_mass", arguments="xe, xed",
             returns="(M (6, 6) [kg, kg m, kg m^2], h (6,) [N]): the rod's consistent mass and "
                     "its velocity term (Hermite interpolation)",
             hint="M = m int N^T N dxi, h = m int N^T a dxi with N = [H1 I, H2 l0 n_p, H3 I, "
                  "H4 l0 n_q]",
             answer=beam_mass, cases=lambda rng: _beam_states(rng, True),
             mistakes=(Mistake("h is not zero: the rotating end tangents give a = -l0 (w_p^2 "
                               "H2 e_p + w_q^2 H4 e_q)",
                               functools.partial(beam_mass, velocity_term=False)),)),
        dict(function="transfer", arguments="x",
             returns="F_q (9, 3) of the one-beam rod at x, q = [phi2, e2, e3]",
             hint="D_c F_c = [-D_m | 0; 0 | I] over the rows [e(o); e2, e3]",
             answer=lambda x: kin.first_order_transfer(model(), np.asarray(x, dtype=float)),
             cases=lambda rng: [(configuration(q),) for q in _q(rng)]),
        dict(function="dynamic_accelerations", arguments="x, qd",
             returns="(e2dd, e3dd) [m/s^2] at constant crank speed: Mbar_dd qdd_d = f_d",
             hint="Mbar = F_q^T M F_q; f = F_q^T (-h - M (F_qq qd) qd) - E_q^T S e",
             answer=dynamic_accelerations,
             cases=lambda rng: [(configuration(q), np.array([150.0, *rng.uniform(-5, 5, 2)]))
                                for q in _q(rng)],
             mistakes=(Mistake(_QUADRATIC, functools.partial(dynamic_accelerations,
                                                             quadratic=False)),
                       Mistake("half of the velocity terms: f_d needs both -F_q^T h (the "
                               "beam's own) and -F_q^T M (F_qq qd) qd (from the motion of "
                               "the coordinates); yours has only the first",
                               functools.partial(half_velocity_terms, keep="h")),
                       Mistake("half of the velocity terms: f_d needs both -F_q^T h (the "
                               "beam's own) and -F_q^T M (F_qq qd) qd (from the motion of "
                               "the coordinates); yours has only the second",
                               functools.partial(half_velocity_terms, keep="F_qq")))),
        dict(function="positions", iterative=True, arguments="q, nbeams, eps1flex",
             returns="x [m, rad] for nbeams beams by Newton-Raphson, q = [phi2, the beams' "
                     "(e1,) e2, e3]",
             hint="Newton on [e(o); e(m) - q_e] = 0 for the dependent coordinates, from the "
                  "straight rod",
             answer=configuration, cases=_positions_cases, angles=(0,), wrapped=_angles),
        dict(function="midpoint_deflection", arguments="x, nbeams",
             returns="v/l2 [-] at the rod's middle (a node for even nbeams, the middle beam's "
                     "Hermite point for odd)",
             hint="v = (M - A) . n_AB with n_AB the left normal of B - A",
             answer=midpoint, cases=_midpoint_cases),
    ), module="slider_crank_flex")
