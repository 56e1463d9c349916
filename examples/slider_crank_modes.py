"""EXERCISES 4's flexible rod: its eigenfrequencies along a crank revolution.

The slider-crank of ``slider-crank-flex`` (crank 0.15 m at 150 rad/s, rod 0.30 m
of ``--nbeams`` beams, ``EI = 12.72 N m^2``, slider mass ``m2/2``) is linearized at
``--points`` configurations of one revolution and its first ``--count``
frequencies [Hz] are tabulated against the crank angle. By default it follows the
nominal motion (the rod undeformed, the crank at constant speed: SPACAR's
linearization along a prescribed trajectory); with ``--simulated`` the simulated
motion of the flexible rod instead.

At rest the rod is a beam pinned at the crank pin and the slider, in every
configuration: its frequencies are ``(k pi)^2 sqrt(EI / (rho A L^4)) / (2 pi)``,
which ``nbeams`` Hermite beams reach as ``n^-4`` (for one beam exactly ``sqrt(120)``
instead of ``pi^2``, from its consistent mass). In motion the inertia of the
slider and the rod stretches the rod around the outer dead centre (0 deg) and
compresses it around the inner one (180 deg), so the first frequency rises above
and falls below its value at rest; at constant speed the frequencies are
symmetric about the half turn (the motion reversed in time is the mirrored
motion).

The course's beams measure the elongation along the chord. One such beam misses
the effect of the axial force on the bending (its rotations do not change its
chord), and several beams catch it only through their kinks; with
``--second-order`` the beams' elongation includes the arc length of the bending
(PLBEAM2) and one beam already swings by 14 %.

Run: ``flexmbd example slider-crank-modes --nbeams 4 --plot f.png``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    POSITIVE,
    Check,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    parse,
    print_checks,
)
from flexmbd.examples.slider_crank_flex import EI, L2, M2, OMEGA, build_model, run

import flexmbd as fm
from flexmbd import plot, results

RHO_A = M2 / L2  #: rod mass per length [kg/m]


def pinned_frequencies(nbeams: int, count: int) -> np.ndarray:
    """The rod's frequencies at rest [Hz]: pinned-pinned, ``(k pi)^2 sqrt(EI/(rho A L^4))``
    for the continuous rod; one Hermite beam gives ``sqrt(120)`` and ``sqrt(2520)`` in
    place of ``pi^2`` and ``4 pi^2`` (its stiffness and consistent mass for the rotations:
    ``EI/L [[4, 2], [2, 4]]``, ``rho A L^3/420 [[4, -3], [-3, 4]]``)."""
    scale = math.sqrt(EI / (RHO_A * L2**4)) / (2 * math.pi)
    if nbeams == 1:
        return scale * np.sqrt([120.0, 2520.0])[:count]
    return scale * (np.pi * np.arange(1, count + 1)) ** 2


def rest_tolerance(nbeams: int, k: int) -> float:
    """How close ``nbeams`` beams come to the continuous rod's ``k``-th frequency: Hermite
    beams converge as ``(k/n)^4``, from the one beam's ``sqrt(120)/pi^2 - 1 = 0.11``."""
    return 1e-9 if nbeams == 1 else 0.11 * (k / nbeams) ** 4


def motion(model: fm.Model, points: int, simulated: bool, omega: float) -> fm.KinematicResult:
    """One crank revolution at ``points`` configurations: the nominal motion (inverse
    dynamics, rod undeformed) or the simulated flexible motion."""
    times = np.linspace(0.0, 2 * math.pi / omega, points)
    if not simulated:
        return fm.inverse_dynamics(model, times)
    return run(model, 1.0, omega=omega, on_failure="return", progress=True, times=times)


def frequencies_at_rest(model: fm.Model, times: np.ndarray, count: int) -> np.ndarray:
    """The first ``count`` frequencies [Hz] of the mechanism at rest in the undeformed
    configurations of ``times`` ``(n, count)``. With a flexible elongation only the dead
    centres count: elsewhere the slider's motion has a component across the rod, and
    its mass and the axial stiffness take part in the bending."""
    x = fm.kinematic_analysis(model, times).x
    if "e2.1" in model.q_labels:
        x = x[np.isclose(np.sin(x[:, model.coordinate_index("x2.1")]), 0.0, atol=1e-9)]
    zero = np.zeros(len(model.q_labels))
    return np.array([fm.vibration_modes(fm.linearize(model, row, zero, zero), count).frequencies
                     for row in x])


def checked_count(nbeams: int, count: int) -> int:
    """How many frequencies are checked at rest: one beam's two (closed form), else those
    resolved by at least two beams per half wave (``k <= n/2``, within 0.7 %), at most 3."""
    return min(count, 2 if nbeams == 1 else max(1, min(3, nbeams // 2)))


def checks(nbeams: int, along: fm.ModesAlong, rest: np.ndarray, nominal: bool) -> list[Check]:
    """At rest (``rest``: :func:`frequencies_at_rest`), in every configuration:
    pinned-pinned; in nominal motion: symmetric about the half turn."""
    expected = pinned_frequencies(nbeams, rest.shape[1])
    out = [Check(f"f{k + 1} at rest, worst of {len(rest)} configurations [Hz]",
                 rest[np.argmax(np.abs(rest[:, k] - expected[k])), k], expected[k],
                 rtol=rest_tolerance(nbeams, k + 1)) for k in range(rest.shape[1])]
    if nominal:
        f = along.frequencies
        out.append(Check("max |f(phi) - f(360 deg - phi)| / max f", float(
            np.max(np.abs(f - f[::-1])) / np.max(f)), 0.0, rtol=1e-8))
    return out


def table(along: fm.ModesAlong) -> dict[str, np.ndarray]:
    """The columns ``t, phi`` [s, rad] and ``f1, f2, ...`` [Hz]."""
    columns = along.columns()
    return {"t": columns.pop("t"), "phi": along.result["x2.1"], **columns}


def plot_frequencies(model: fm.Model, columns: dict[str, np.ndarray], *,
                     filename: str | None = None, window: bool = False):
    """One panel per frequency [Hz] of :func:`table`'s ``columns`` against the crank angle
    (each swings by a few per cent, too little to share an axis). Returns the figure."""
    names = [k for k in columns if k not in ("t", "phi")]
    return plot.plot_panels(np.degrees(columns["phi"]), [{k: columns[k]} for k in names],
                            xlabel="crank angle [deg]", ylabels=[f"{k} [Hz]" for k in names],
                            title=f"{model.name}: frequencies along a revolution",
                            filename=filename, window=window)


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--nbeams", type=count(1), default=4, help="beams along the rod "
                                                                   "(default 4)")
    parser.add_argument("--eps1flex", action="store_true", help="flexible elongation")
    parser.add_argument("--second-order", action="store_true",
                        help="second-order beams: the axial force stiffens the bending")
    parser.add_argument("--count", type=count(1), default=3, help="frequencies (default 3)")
    parser.add_argument("--points", type=count(3), default=73,
                        help="configurations along the revolution (default 73: every 5 deg)")
    parser.add_argument("--omega", type=POSITIVE, default=OMEGA, help="crank speed [rad/s]")
    parser.add_argument("--simulated", action="store_true",
                        help="linearize along the simulated motion of the flexible rod")
    add_output_options(parser, table=True)
    args = parse(parser, argv)

    model = build_model(args.nbeams, args.eps1flex, args.omega, second_order=args.second_order)
    print(model.summary())
    path = motion(model, args.points, args.simulated, args.omega)
    along = fm.modes_along(path, args.count, progress=True)
    columns = table(along)
    if args.out:
        results.write_csv(args.out, columns)
        print(f"{len(along.t)} rows written to {args.out}")
    shown = slice(None, None, max(1, (len(along.t) - 1) // 12))
    print(f"\nfrequencies [Hz] along the {'simulated' if args.simulated else 'nominal'} "
          "motion:")
    print(f"  {'crank [deg]':>11}" + "".join(f"{f'f{k + 1}':>11}" for k in range(args.count)))
    for phi, row in zip(np.degrees(columns["phi"][shown]), along.frequencies[shown],
                        strict=True):
        print(f"  {phi:>11.1f}" + "".join(f"{f:>11.5g}" for f in row))
    rest = frequencies_at_rest(model, along.t, checked_count(args.nbeams, args.count))
    first = along.frequencies[:, 0]
    print(f"f1 from {first.min():.5g} to {first.max():.5g} Hz; at rest {rest[0, 0]:.5g} Hz")
    ok = print_checks("\nchecks:", checks(args.nbeams, along, rest, not args.simulated))

    def draw(filename, window):
        plot_frequencies(model, columns, filename=filename, window=window)

    finish_outputs(args, path, draw, movie_title=model.name)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
