"""The course's symbolic steps (EXERCISES 1-4) on flexmbd's symbolic path.

The course derived its formulas with a symbolic toolbox and generated numeric
functions for its simulations. Each step here comes from the same element
definitions as the compiled engine (:mod:`flexmbd.analysis.symbolic`) and is checked
against it:

1. the sliding bar's ``ydot_q`` from the truss's ``F_q``;
2. ``F_q`` and ``F_qq`` of the slider-crank's slider as functions of ``phi2``, on
   the closed-form path, against differentiating ``x_B(phi2)``;
3. the reduced mass ``Mbar`` with a lumped and with a consistent rod mass
   (symbols ``m2``, ``m5``): their difference simplifies to exactly 0;
4. the driving torque ``tau2(phi2, phi2', phi2'')`` (inverse dynamics);
5. EXERCISES 4 part 1, the 3-DOF flexible slider-crank, generated symbolically
   and simulated with ``solve_ivp``, against the engine's ``v/l2``.

Run: ``flexmbd example symbolic-course --plot v.png`` (about 10 s: SymPy derives and
simplifies).
"""

from __future__ import annotations

import functools
import math
import sys

import numpy as np
from flexmbd.examples import slider_crank_dynamics, slider_crank_flex, sliding_bar
from flexmbd.examples._support import (
    Check,
    add_output_options,
    example_parser,
    finish_outputs,
    parse,
    print_checks,
)

import flexmbd as fm
from flexmbd import plot


def _sympy():
    from flexmbd.analysis.symbolic import _sympy as load

    return load()


def sliding_bar_velocity():
    """``ydot_q`` of the sliding truss in the symbols ``x_p, y_q, xdot_p``: ``-x_p xdot_p /
    y_q`` (end p on the x axis, q on the y axis)."""
    from flexmbd.analysis import symbolic

    sp = _sympy()
    model = sliding_bar.truss_model()
    x = symbolic.coordinate_symbols(model)
    x_p, y_q, xd_p = sp.symbols("x_p y_q xdot_p", real=True)
    on_axes = {x[1]: 0, x[2]: 0, x[0]: x_p, x[3]: y_q}
    F_q = symbolic.first_order_transfer(model)
    return sp.simplify(F_q[3, 0].xreplace(on_axes) * xd_p)


def slider_crank_path(model: fm.Model, phi2):
    """The slider-crank's dependent coordinates as SymPy functions of ``phi2``."""
    sp = _sympy()
    l1, l2 = (sp.nsimplify(model.elements[k].reference[0]) for k in (1, 2))
    return {"x1.1": 0, "x1.2": 0, "x2.1": phi2, "x3.1": l1 * sp.cos(phi2),
            "x3.2": l1 * sp.sin(phi2), "x4.1": -sp.asin(l1 * sp.sin(phi2) / l2),
            "x5.1": l1 * sp.cos(phi2) + sp.sqrt(l2**2 - l1**2 * sp.sin(phi2)**2),
            "x5.2": 0}


@functools.cache
def slider_transfer(model: fm.Model | None = None):
    """``(phi2, F_q, F_qq)``: the first and second-order transfer functions of the slider
    ``x5.1`` along ``phi2`` on the closed-form path, simplified."""
    from flexmbd.analysis import symbolic

    sp = _sympy()
    model = model or slider_crank_dynamics.build_model()
    phi2 = sp.Symbol("phi2", real=True)
    path = slider_crank_path(model, phi2)
    i = model.coordinate_index("x5.1")
    F_q = symbolic.first_order_transfer(model, simplify=False)[i, 0]
    F_qq = symbolic.second_order_transfer(model)[0][i, 0, 0]
    return phi2, *(sp.simplify(symbolic.substitute(f, model, path)) for f in (F_q, F_qq))


@functools.cache
def mass_difference():
    """``Mbar`` lumped minus consistent for rod mass ``m2`` and slider mass ``m5``
    (symbols), simplified: exactly 0 for a rigid rod (THEORY 5)."""
    from flexmbd.analysis import symbolic

    sp = _sympy()
    m2, m5, phi2 = sp.symbols("m2 m5 phi2", positive=True)
    reduced = []
    for formulation in ("lumped", "consistent"):
        model = slider_crank_dynamics.build_model(formulation)
        Mbar = symbolic.reduced_mass_matrix(model, element_masses={2: m2},
                                            nodal_masses={5: m5})
        reduced.append(symbolic.substitute(Mbar, model, slider_crank_path(model, phi2)))
    return sp.simplify(reduced[0] - reduced[1])


@functools.cache
def driving_torque():
    """``(inertia, velocity)``: the driving torque ``tau2 = inertia phi2'' + velocity
    phi2'^2`` for rod mass ``m2`` and slider mass ``m5`` (symbols), consistent rod mass, no
    gravity, as rational functions of ``s = sin(phi2)``, ``c = cos(phi2)`` and ``r =
    sqrt(l2^2 - l1^2 s^2)`` (THEORY 7: ``tau = Mbar qddot - rhs``).

    On the path the crank pin is ``l1 (c, s)``, the slider ``l1 c + r`` and the rod angle
    has ``cos = r / l2``, ``sin = -l1 s / l2``; numerator and denominator are then reduced
    modulo ``s^2 + c^2 = 1`` and ``r^2 = l2^2 - l1^2 s^2``, which keeps SymPy fast where
    ``simplify`` of the ``asin`` form takes minutes.
    """
    from flexmbd.analysis import symbolic

    sp = _sympy()
    model = slider_crank_dynamics.build_model()
    m2, m5 = sp.symbols("m2 m5", positive=True)
    s, c, r = sp.symbols("s c r", real=True)
    l1, l2 = (sp.nsimplify(model.elements[k].reference[0]) for k in (1, 2))
    x = symbolic.coordinate_symbols(model)
    tau = symbolic.driving_forces(model, element_masses={2: m2}, nodal_masses={5: m5})[0]
    tau = tau.subs({sp.cos(x[2]): c, sp.sin(x[2]): s, sp.cos(x[5]): r / l2,
                    sp.sin(x[5]): -l1 * s / l2})
    tau = sp.expand(symbolic.substitute(tau, model, {
        "x1.1": 0, "x1.2": 0, "x3.1": l1 * c, "x3.2": l1 * s, "x5.1": l1 * c + r, "x5.2": 0}))
    relations = [s**2 + c**2 - 1, r**2 - l2**2 + l1**2 * s**2]

    def reduce(expr):
        numerator, denominator = sp.fraction(sp.cancel(sp.together(expr)))
        numerator, denominator = (sp.reduced(sp.expand(e), relations, r, s, c)[1]
                                  for e in (numerator, denominator))
        return sp.factor(sp.cancel(numerator / denominator))

    qd, qdd = (symbolic.generalized_symbols(model, k)[0] for k in ("d", "dd"))
    return reduce(tau.coeff(qdd)), reduce(tau.coeff(qd, 2))


def torque_at(phi2: float, phi2d: float, phi2dd: float, m2: float, m5: float) -> float:
    """:func:`driving_torque`'s formula at a state [rad, rad/s, rad/s^2] and masses [kg]."""
    inertia, velocity = driving_torque()
    l1, l2 = slider_crank_dynamics.L1, slider_crank_dynamics.L2
    values = {"s": math.sin(phi2), "c": math.cos(phi2), "m2": m2, "m5": m5,
              "r": math.sqrt(l2**2 - (l1 * math.sin(phi2))**2)}
    return _at(inertia, values) * phi2dd + _at(velocity, values) * phi2d**2


def _at(expr, values: dict[str, float]) -> float:
    """``expr`` at numbers given by symbol name."""
    return float(expr.xreplace({s: values[s.name] for s in expr.free_symbols}))


@functools.cache
def flexible_generated(revolutions: float = 0.25, points: int = 41):
    """``(crank angle, v/l2 generated, v/l2 engine, engine result)`` of EXERCISES 4 part 1
    (one beam) at ``points`` times over ``revolutions``."""
    from flexmbd.analysis.generated import GeneratedEquations

    model = slider_crank_flex.build_model(1)
    times = np.linspace(0.0, slider_crank_flex.turn_time(revolutions), points)
    run = GeneratedEquations(model).simulate(times)
    engine = fm.simulate(model, times, method="DOP853", rtol=1e-10, atol=1e-12)
    return (slider_crank_flex.OMEGA * times, slider_crank_flex.midpoint_deflection(model, run.x),
            slider_crank_flex.midpoint_deflection(model, np.asarray(engine.x)), engine)


def checks(points: int = 41) -> list[Check]:
    """Each symbolic step evaluated against the engine at a configuration."""
    sp = _sympy()
    out = []
    truss = sliding_bar.truss_model()
    x_p = -math.sqrt(3.0)
    ydot = _at(sliding_bar_velocity(), {"x_p": x_p, "y_q": 1.0, "xdot_p": 4.0})
    engine = fm.kinematic_analysis(truss, [(x_p + 2.0) / 4.0])
    out.append(Check("1: ydot_q [m/s] (4 sqrt 3)", ydot, float(engine["xd2.2"][0])))
    model = slider_crank_dynamics.build_model()
    phi2, F_q, F_qq = slider_transfer()   # of this model, worked out once (cached)
    x = fm.solve_position(model, np.array([0.7]))
    i = model.coordinate_index("x5.1")
    out.append(Check("2: F_q of x5 at 0.7 rad [m]", float(F_q.subs(phi2, 0.7)),
                     fm.first_order_transfer(model, x)[i, 0]))
    out.append(Check("2: F_qq of x5 at 0.7 rad [m]", float(F_qq.subs(phi2, 0.7)),
                     fm.second_order_transfer(model, x)[0][i, 0, 0], rtol=1e-8))
    difference = mass_difference()
    out.append(Check("3: Mbar lumped - consistent", float(sp.Abs(difference[0])), 0.0))
    state = (0.7, 150.0, 30.0)
    engine = fm.inverse_dynamics(model, [0.0], inputs={"x2.1": fm.Polynomial(*state)})
    out.append(Check("4: tau2 [N m] at (0.7, 150, 30)",
                     torque_at(*state, slider_crank_dynamics.M2, slider_crank_dynamics.M5),
                     float(np.asarray(engine.driving)[0, 0])))
    _, generated, engine, _ = flexible_generated(points=points)
    out.append(Check("5: generated v/l2 max |difference|", float(np.abs(generated - engine).max()),
                     0.0, rtol=1e-8))
    return out


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Print the course's symbolic results and check them against the engine."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--points", type=int, default=41,
                        help="output times of the generated simulation (a quarter turn)")
    add_output_options(parser)
    args = parse(parser, argv)
    print("1  sliding bar: ydot_q =", sliding_bar_velocity())
    _, F_q, F_qq = slider_transfer()
    print("2  slider-crank (l1 = 0.15, l2 = 0.30): F_q of x5 =", F_q)
    print("   F_qq of x5 =", F_qq)
    print("3  Mbar lumped - Mbar consistent =", mass_difference())
    inertia, velocity = driving_torque()
    print("4  tau2 = A phi2'' + B phi2'^2 with s = sin(phi2), c = cos(phi2), "
          "r = sqrt(l2^2 - l1^2 s^2):")
    print("   A =", inertia)
    print("   B =", velocity)
    ok = print_checks("\nagainst the engine:", checks(args.points))
    angle, generated, engine, result = flexible_generated(points=args.points)

    def draw(filename, window):
        plot.plot_curves(np.degrees(angle), {"generated (SymPy + solve_ivp)": generated,
                                             "engine": engine},
                         xlabel="crank angle [deg]", ylabel="mid-point deflection v/l2 [-]",
                         title="EXERCISES 4 part 1, generated symbolically",
                         filename=filename, window=window)

    finish_outputs(args, result, draw, movie_title="flexible slider-crank (deflection x 10)",
                   exaggeration=10.0)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
