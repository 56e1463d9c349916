"""EXERCISES 2: slider-crank kinematics with two rigid beams (one degree of freedom).

Nodes: 1 crank pivot O (fixed), 2 crank angle ``phi2`` (input), 3 crank pin A,
4 rod angle ``phi4``, 5 slider B (``y`` fixed). Elements: rigid beam 1 (O-A,
rotational node 2) and rigid beam 2 (A-B, rotational node 4); all four
deformations rigid, dependent coordinates ``x3, y3, phi4, x5``. The mechanism
starts stretched along the x axis (``phi2 = 0``) and the crank turns with
initial speed ``omega0`` and constant acceleration ``alpha``. In the drawn
configuration ``phi2 = 60 deg``, ``phi4 = -30 deg`` because ``l2 = sqrt(3) l1``.

Printed: the partitioned Jacobian, ``F_q`` and ``E_q`` (zero on the rigid rows;
with ``--symbolic`` also as SymPy expressions),
velocities and accelerations (directly and through ``F_qq``), each against the
closed-form slider-crank ``x_B = l1 cos phi + sqrt(l2^2 - l1^2 sin^2 phi)``, and
the largest deviation from it over the first revolution.

Run: ``flexmbd example slider-crank-kin --movie crank.gif``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    FINITE,
    Check,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    format_matrix,
    parse,
    print_checks,
)

import flexmbd as fm
from flexmbd import plot

L1 = 1.0  #: crank length [m]
L2 = math.sqrt(3.0) * L1  #: rod length [m]
OMEGA0 = 2.0 * math.pi  #: initial crank speed [rad/s]
ALPHA = 2.0 * math.pi  #: crank angular acceleration [rad/s^2]
DRAWN = math.radians(60.0)  #: crank angle of the drawn configuration


def build_model(l1: float = L1, l2: float = L2, omega0: float = OMEGA0,
                alpha: float = ALPHA) -> fm.Model:
    """The slider-crank stretched along the x axis; crank ``phi2 = omega0 t + alpha t^2 / 2``."""
    b = fm.ModelBuilder("slider-crank")
    b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)  # crank O-A
    b.add_rigid_beam(2, 3, 4, 5)  # rod A-B
    b.fix(1).fix(5, "y")
    b.input_coordinate(2, law=fm.Polynomial(0.0, omega0, alpha))
    return b.build()


def closed_form(phi, l1: float = L1, l2: float = L2) -> dict[str, tuple]:
    """Closed-form positions and first and second derivatives with respect to ``phi``.

    Returns ``{label: (value, d/dphi, d2/dphi2)}`` for ``x3.1, x3.2, x4.1, x5.1``
    (the rod angle ``psi = x4.1`` follows from ``l1 sin phi + l2 sin psi = 0``).
    """
    s, c = np.sin(phi), np.cos(phi)
    psi = -np.arcsin(l1 * s / l2)
    dpsi = -l1 * c / (l2 * np.cos(psi))
    ddpsi = (l1 * s + l2 * np.sin(psi) * dpsi**2) / (l2 * np.cos(psi))
    x5 = l1 * c + l2 * np.cos(psi)
    dx5 = -l1 * s - l2 * np.sin(psi) * dpsi
    ddx5 = -l1 * c - l2 * np.cos(psi) * dpsi**2 - l2 * np.sin(psi) * ddpsi
    return {
        "x3.1": (l1 * c, -l1 * s, -l1 * c),
        "x3.2": (l1 * s, l1 * c, -l1 * s),
        "x4.1": (psi, dpsi, ddpsi),
        "x5.1": (x5, dx5, ddx5),
    }


def drawn_configuration(model: fm.Model, omega: float = OMEGA0, alpha: float = ALPHA):
    """Configuration, velocities and accelerations at ``phi2 = 60 deg`` (``phi2dot = omega``)."""
    return fm.kinematic_analysis(model, [0.0], inputs={"x2.1": fm.Polynomial(DRAWN, omega, alpha)})


def checks(model: fm.Model, omega: float = OMEGA0, alpha: float = ALPHA) -> list[Check]:
    """Drawn configuration against the closed form, through both acceleration routes."""
    r = drawn_configuration(model, omega, alpha)
    x = r.x[0]
    F_qq, E_qq = fm.second_order_transfer(model, x)
    F_q = fm.first_order_transfer(model, x)
    via_transfer = F_q[:, 0] * alpha + F_qq[:, 0, 0] * omega**2
    exact = closed_form(DRAWN)
    out = [Check("phi4 [deg] (-30)", math.degrees(x[model.coordinate_index("x4.1")]), -30.0),
           Check("x5 [m] (2)", x[model.coordinate_index("x5.1")], exact["x5.1"][0])]
    for label, (_, d1, d2) in exact.items():
        i = model.coordinate_index(label)
        out.append(Check(f"xd{label[1:]}", r.xd[0, i], d1 * omega, scale=L1 * omega))
        out.append(Check(f"xdd{label[1:]}", r.xdd[0, i], d1 * alpha + d2 * omega**2,
                         scale=L1 * omega**2))
        out.append(Check(f"xdd{label[1:]} via F_qq", via_transfer[i], d1 * alpha + d2 * omega**2,
                         scale=L1 * omega**2))
    out.append(Check("max |E_q|, |E_qq| (rigid rows)", float(max(np.abs(
        fm.deformation_transfer(model, x, F_q)).max(), np.abs(E_qq).max())), 0.0))
    return out


def revolution_error(result: fm.KinematicResult, omega0: float = OMEGA0,
                     alpha: float = ALPHA) -> float:
    """Largest deviation of x, xd, xdd from the closed form, relative to each one's range."""
    model = result.model
    phi = result["x2.1"]
    phid, phidd = omega0 + alpha * result.t, np.full_like(result.t, alpha)
    worst = 0.0
    for label, (v, d1, d2) in closed_form(phi).items():
        i = model.coordinate_index(label)
        for computed, exact in ((result.x[:, i], v), (result.xd[:, i], d1 * phid),
                                (result.xdd[:, i], d1 * phidd + d2 * phid**2)):
            worst = max(worst, float(np.max(np.abs(computed - exact)) / np.max(np.abs(exact))))
    return worst


def print_partitions(model: fm.Model, x: np.ndarray) -> None:
    """The partitioned Jacobian and the transfer functions at ``x``."""
    jac = fm.partition_jacobian(model, x)
    rows = [model.deformation_labels[i] for i in range(model.n_deformations)]
    for title, columns, block in (
        ("x(o) fixed", model.fixed, jac.fixed),
        ("x(c) dependent", model.dependent, jac.dependent),
        ("x(m) input", model.independent_coordinates, jac.independent),
    ):
        names = [model.coordinate_labels[i] for i in columns]
        print(f"D_x, {title} columns:\n{format_matrix(block, rows, names)}")
    F_q = fm.first_order_transfer(model, x)
    print("F_q = dx/dq:\n" + format_matrix(F_q, list(model.coordinate_labels),
                                           list(model.q_labels)))
    print("E_q = D_x F_q (rigid deformations do not move):\n"
          + format_matrix(fm.deformation_transfer(model, x, F_q), rows, list(model.q_labels)))


def print_symbolic(model: fm.Model) -> None:
    """The deformation functions and ``F_q`` as simplified SymPy expressions."""
    from flexmbd.analysis import symbolic

    print("\nsymbolic deformation functions e = D(x):")
    for label, expr in zip(model.deformation_labels, symbolic.deformations(model), strict=True):
        print(f"  {label} = {expr}")
    print("symbolic F_q (column x2.1), valid on the constraint manifold:")
    F_q = symbolic.first_order_transfer(model)
    for i in model.dependent:
        print(f"  d{model.coordinate_labels[i]}/dphi2 = {F_q[i, 0]}")


def revolution_time(omega0: float, alpha: float) -> float | None:
    """The first ``t > 0`` [s] with ``omega0 t + alpha t^2 / 2 = 2 pi``, or ``None``."""
    if alpha == 0:
        return 2 * math.pi / omega0 if omega0 > 0 else None
    discriminant = omega0**2 + 4 * math.pi * alpha
    if discriminant < 0:
        return None
    roots = [(-omega0 + sign * math.sqrt(discriminant)) / alpha for sign in (1, -1)]
    positive = [t for t in roots if t > 0 and math.isfinite(t)]
    return min(positive) if positive else None


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--omega0", type=FINITE, default=OMEGA0, help="initial crank speed [rad/s]")
    parser.add_argument("--alpha", type=FINITE, default=ALPHA,
                        help="crank angular acceleration [rad/s^2]")
    parser.add_argument("--points", type=count(2), default=400, help="output times")
    parser.add_argument("--symbolic", action="store_true",
                        help="also print D(x) and F_q as SymPy expressions")
    add_output_options(parser)
    args = parse(parser, argv)
    t_rev = revolution_time(args.omega0, args.alpha)
    if t_rev is None:
        parser.error(f"the crank (--omega0 {args.omega0:g}, --alpha {args.alpha:g}) never "
                     f"completes a forward revolution")

    model = build_model(omega0=args.omega0, alpha=args.alpha)
    print(model.summary())
    drawn = drawn_configuration(model, args.omega0, args.alpha)
    print(f"\ndrawn configuration phi2 = 60 deg, phi2dot = {args.omega0:.6g} rad/s, "
          f"phi2ddot = {args.alpha:.6g} rad/s^2")
    print_partitions(model, drawn.x[0])
    ok = print_checks("\nchecks against the closed-form slider-crank:",
                      checks(model, args.omega0, args.alpha))
    if args.symbolic:
        print_symbolic(model)

    result = fm.kinematic_analysis(model, np.linspace(0.0, t_rev, args.points),
                                   on_failure="return")
    print(f"\nrevolution: {result.message}")
    error = revolution_error(result, args.omega0, args.alpha)
    print(f"largest deviation from the closed form over the revolution: {error:.2e} (relative)")
    ok = ok and error < 1e-9

    def draw(filename, window):
        plot.plot_motion(result, ["x5.1", "x4.1"], labels=["x_B (x5) [m]", "phi4 [rad]"],
                         filename=filename, window=window, title="slider-crank kinematics")

    finish_outputs(args, result, draw, movie_title="slider-crank")
    return 0 if ok and result.success else 1


if __name__ == "__main__":
    sys.exit(main())
