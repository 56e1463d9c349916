"""EXERCISES 4: slider-crank with a flexible connecting rod of ``nbeams`` beams.

Rigid crank ``l1 = 0.15 m`` driven at a constant 150 rad/s from ``phi2 = 0``;
rod ``l2 = 0.30 m`` of ``nbeams`` equal beams (mass ``m2 = 0.06676 kg`` spread
uniformly, consistent Hermite mass, ``EI = 12.72 N m^2``); slider mass
``m2/2``; no gravity, no damping. The bending deformations of every beam are
dynamic degrees of freedom; with ``--eps1flex`` the elongations too
(``EA = 2e11 * pi * 0.003^2 N``), otherwise they are rigid. The run starts with
the rod undeformed and the rigid-body velocities.

Nodes: 1 crank pivot O, 2 crank angle, 3 crank pin A, 4 rod angle at A, 5
slider B, 6 rod angle at B; inner rod nodes 7, 9, ... (positions) and 8, 10,
... (angles) from A to B. Elements: rigid beam 1 (crank), beams 2 ..
``nbeams + 1`` (rod, from A to B).

Printed and written: the mid-point deflection ``v/l2`` of the rod (THEORY
section 10: ``v = (M - A) . n_AB`` with ``M`` the middle node or, for odd
``nbeams``, the Hermite mid-point of the middle beam) against the crank angle;
``--out`` writes ``t, phi, v_over_l2`` and all result columns at 400 points per
revolution. A rod that "breaks" (try ``--alpha 2e6``) ends the run with the
time of failure; the points before it are still written.

Several beam counts (``--nbeams 1..10`` or ``1,2,4,8``) run EXERCISES 4 part 2's
convergence study as a parameter study on Dask (:func:`flexmbd.sweep`; a local
cluster, or ``--scheduler ADDRESS``): ``--plot`` draws the ``v/l2`` histories
together beside the peak ``|v/l2|`` against the number of beams, ``--out
FILE.parquet`` keeps the table (resumed when run again).

Run: ``flexmbd example slider-crank-flex --nbeams 4 --plot v.png --movie rod.gif``, or
``flexmbd example slider-crank-flex --nbeams 1..10 --plot study.png``.
"""

from __future__ import annotations

import argparse
import functools
import math
import sys

import numpy as np
from flexmbd.examples._support import (
    FINITE,
    POSITIVE,
    Check,
    add_file_option,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    number,
    parse,
    print_checks,
)

import flexmbd as fm
from flexmbd import plot, results
from flexmbd.analysis.integrate import METHODS
from flexmbd.checks import LARGEST_RTOL, SMALLEST_RTOL

L1 = 0.15  #: crank length [m]
L2 = 0.30  #: rod length [m]
M2 = 0.06676  #: rod mass [kg]
EI = 12.72  #: rod bending stiffness [N m^2]
EA = 2e11 * math.pi * 0.003**2  #: axial stiffness of the 6 mm steel rod [N]
OMEGA = 150.0  #: crank speed [rad/s]
POINTS_PER_REVOLUTION = 400
#: fixed steps of the generalized-alpha method per crank turn, chosen by accuracy: v/l2
#: within about 2e-4 of the step-converged history (1.3e-4 to 1.4e-4 for 2 to 8 beams,
#: 2.1e-4 for one beam; 350 steps: 1.7e-4 for 8 beams; 800 steps: 3e-5 to 8e-5)
STEPS_PER_REVOLUTION = 400
EXAGGERATION = 10.0  #: deflection scale of the movie


def rod_nodes(nbeams: int) -> tuple[list[int], list[int]]:
    """Translational and rotational node numbers along the rod, from A to B."""
    inner = range(nbeams - 1)
    return [3, *(7 + 2 * k for k in inner), 5], [4, *(8 + 2 * k for k in inner), 6]


def build_model(nbeams: int = 1, eps1flex: bool = False, omega: float = OMEGA,
                alpha: float = 0.0, second_order: bool = False,
                bending: float = EI) -> fm.Model:
    """The flexible slider-crank; crank angle ``phi2 = omega t + alpha t^2 / 2`` [rad], rod
    bending stiffness ``bending`` [N m^2] (the course's EI by default).

    With ``second_order`` the rod's beams are :class:`~flexmbd.SecondOrderBeam`: their
    elongation includes the arc length of the bending, so the rod's axial force changes
    its bending stiffness (the course's beams measure the chord)."""
    if nbeams < 1:
        raise fm.ModelError(f"nbeams must be at least 1, got {nbeams}")
    b = fm.ModelBuilder(f"flexible slider-crank, {nbeams} beam{'s' * (nbeams > 1)}")
    b.add_node(1, 0.0, 0.0).add_node(3, L1, 0.0).add_node(5, L1 + L2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)
    positions, angles = rod_nodes(nbeams)
    for k in range(1, nbeams):
        b.add_node(positions[k], L1 + L2 * k / nbeams, 0.0)
    for k in range(nbeams):
        element = k + 2
        b.add_beam(element, positions[k], angles[k], positions[k + 1], angles[k + 1],
                   second_order=second_order)
        b.set_mass(element, M2 / L2)
        b.set_stiffness(element, axial=EA, bending=bending)
        b.dynamic_deformation(element, *((1, 2, 3) if eps1flex else (2, 3)))
    b.fix(1).fix(5, "y")
    b.add_point_mass(5, M2 / 2)
    b.input_coordinate(2, law=fm.Polynomial(0.0, omega, alpha))
    return b.build()


def nbeams_of(model: fm.Model) -> int:
    """Number of beams along the rod."""
    return sum(element.type in (fm.Beam, fm.SecondOrderBeam)
               for element in model.elements.values())


def midpoint_deflection(model: fm.Model, x: np.ndarray) -> np.ndarray:
    """``v/l2`` (THEORY section 10) for coordinates ``x`` of shape ``(nt, nx)``."""
    x = np.atleast_2d(x)
    nbeams = nbeams_of(model)
    a = x[:, list(model.nodes[3].coordinates)]
    d = x[:, list(model.nodes[5].coordinates)] - a
    normal = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.hypot(d[:, 0], d[:, 1])[:, None]
    if nbeams % 2 == 0:
        middle = x[:, list(model.nodes[rod_nodes(nbeams)[0][nbeams // 2]].coordinates)]
    else:  # the Hermite mid-point of the middle beam: the beam's own material point
        beam = model.elements[2 + nbeams // 2]
        xe = x[:, list(beam.coordinates)].T
        middle = np.stack(fm.Beam.material_point(list(xe), list(beam.reference), 0.5, np), axis=1)
    return np.einsum("ij,ij->i", middle - a, normal) / L2


def turn_time(revolutions: float, omega: float = OMEGA, alpha: float = 0.0) -> float:
    """Time [s] at which the crank ``omega t + alpha t^2 / 2`` has made ``revolutions`` turns."""
    angle = 2 * math.pi * revolutions
    if alpha == 0.0:
        return angle / omega
    return (-omega + math.sqrt(omega**2 + 2 * alpha * angle)) / alpha


def output_times(revolutions: float, omega: float = OMEGA, alpha: float = 0.0) -> np.ndarray:
    """400 points per revolution, equally spaced in time, from 0 to ``revolutions`` turns."""
    n = max(round(POINTS_PER_REVOLUTION * revolutions), 1)
    return np.linspace(0.0, turn_time(revolutions, omega, alpha), n + 1)


def simulate(nbeams: int = 1, eps1flex: bool = False, revolutions: float = 2.0, *,
             omega: float = OMEGA, alpha: float = 0.0, **options) -> fm.SimulationResult:
    """Build the model and simulate ``revolutions`` crank turns (see :func:`run`)."""
    return run(build_model(nbeams, eps1flex, omega, alpha), revolutions, omega=omega,
               alpha=alpha, **options)


def run(model: fm.Model, revolutions: float = 2.0, *, omega: float = OMEGA, alpha: float = 0.0,
        method: str = "GeneralizedAlpha", steps_per_revolution: int = STEPS_PER_REVOLUTION,
        rtol: float = 1e-6, iterations: int | None = 1, renew_every: int = 2,
        progress: bool | None = None, on_failure: str = "raise",
        times: np.ndarray | None = None) -> fm.SimulationResult:
    """Simulate ``revolutions`` crank turns of ``model``; output at 400 points per turn
    (or at ``times`` [s]).

    The default generalized-alpha method takes ``steps_per_revolution`` fixed steps
    per turn, linearly implicit (``iterations=1``, a Newton matrix every
    ``renew_every`` steps): at the default 400, ``v/l2`` is within about 2e-4 of the
    step-converged history (:data:`STEPS_PER_REVOLUTION`), as with Newton iterated to
    convergence (``iterations=None``) at a higher cost. The error-controlled methods
    (``"RK45"``, ...) use ``rtol`` instead.
    """
    times = output_times(revolutions, omega, alpha) if times is None else times
    options = {"rtol": rtol, "atol": rtol * 1e-3}
    if method == "GeneralizedAlpha":  # damped: the axial modes are far from resolved
        options.update(step=turn_time(1.0, omega, alpha) / steps_per_revolution,
                       iterations=iterations, renew_every=renew_every, rho_inf=0.8)
    return fm.simulate(model, times, method=method, progress=progress,
                       on_failure=on_failure, **options)


def deflection_table(result: fm.SimulationResult) -> dict[str, np.ndarray]:
    """The columns ``t, phi, v_over_l2`` followed by all result columns."""
    v = midpoint_deflection(result.model, result.x) if len(result.t) else np.empty(0)
    return {"t": result.t, "phi": result["x2.1"], "v_over_l2": v,
            **{k: c for k, c in result.columns().items() if k != "t"}}


def write_csv(result: fm.SimulationResult, path: str) -> None:
    """Write :func:`deflection_table` as CSV with a header row."""
    results.write_csv(path, deflection_table(result))


def energy_balance(result: fm.SimulationResult) -> float:
    """Largest ``|T + U - T(0) - W|`` over the run, relative to the largest ``T``:
    :func:`flexmbd.energy`'s ``balance``, with ``W`` the work of the crank drive (its
    driving torque times the crank speed, integrated over the output rows). No damping,
    no other loads: the drive's work is all that changes the energy."""
    energy = fm.energy(result)
    return float(np.max(np.abs(energy["balance"])) / np.max(energy["kinetic"]))


def checks(result: fm.SimulationResult) -> list[Check]:
    """Energy balance of the run; for one beam also ``v/l2`` through the Hermite mid-point
    against ``l0 (e2 + e3) / (8 l l2)`` (THEORY section 10, ``l = l0 + e1``)."""
    # at 400 fixed steps per turn the balance closes to about 3e-5 of the kinetic energy
    # (the steps' numerical damping); the axial vibrations of a flexible elongation are
    # sampled coarsely by 400 rows per turn, so their work is uncertain to about 1e-2
    # (fm.energy warns)
    flexible = model_has_flexible_elongation(result.model)
    out = [Check("energy balance |T + U - T0 - W| / max T", energy_balance(result), 0.0,
                 rtol=1e-2 if flexible else 1e-3)]
    if nbeams_of(result.model) == 1:
        v = midpoint_deflection(result.model, result.x)
        closed = (result["e2.2"] + result["e2.3"]) / 8 / (L2 + result["e2.1"])
        out.append(Check("max |v/l2 - l0 (e2+e3)/(8 l l2)|", float(np.max(np.abs(v - closed))),
                         0.0, rtol=1e-12))
    return out


def model_has_flexible_elongation(model: fm.Model) -> bool:
    """Whether the rod's elongations are degrees of freedom (``--eps1flex``)."""
    return "e2.1" in model.q_labels


def describe(result: fm.SimulationResult) -> None:
    """Print the extremes of ``v/l2`` over the run."""
    v = midpoint_deflection(result.model, result.x)
    phi = np.degrees(result["x2.1"])
    half = phi <= 180.0
    print(f"v/l2: max {v.max():+.5f} at {phi[np.argmax(v)]:.1f} deg, "
          f"min {v.min():+.5f} at {phi[np.argmin(v)]:.1f} deg; first-half-turn maximum at "
          f"{phi[half][np.argmax(v[half])]:.1f} deg")
    print(f"integrator: {result.stats}")


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--nbeams", type=beam_counts, default=[1],
                        help="beams along the rod (default 1); a range 1..10 or a list 1,2,4 "
                             "runs the study of EXERCISES 4 part 2 as a sweep on Dask")
    parser.add_argument("--eps1flex", action="store_true", help="flexible elongation")
    parser.add_argument("--revolutions", type=POSITIVE, default=2.0,
                        help="crank turns (default 2)")
    parser.add_argument("--omega", type=POSITIVE, default=OMEGA, help="crank speed [rad/s]")
    parser.add_argument("--alpha", type=number(0.0), default=0.0,
                        help="crank acceleration [rad/s^2], >= 0")
    parser.add_argument("--method", default="GeneralizedAlpha", choices=sorted(METHODS),
                        help="time integrator (default GeneralizedAlpha: fixed steps that "
                             "damp the unresolved stiff modes; RK45 is the course's ode45)")
    parser.add_argument("--steps-per-revolution", type=count(1), default=STEPS_PER_REVOLUTION,
                        help="fixed steps per turn of GeneralizedAlpha (default 400: v/l2 "
                             "within about 2e-4 of the step-converged history; 800: 5e-5)")
    parser.add_argument("--rtol", type=number(SMALLEST_RTOL, LARGEST_RTOL), default=1e-6,
                        help="relative tolerance of RK45 and the other error-controlled methods")
    parser.add_argument("--exaggeration", type=FINITE, default=EXAGGERATION,
                        help="deflection scale in the movie (default 10)")
    add_file_option(parser, "--out", "table or study",
                    "write the result table as CSV; of a study, its Parquet table (written as "
                    "cases finish; the same command resumes it)")
    add_output_options(parser)
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run a study on this Dask scheduler instead of a local cluster")
    where.add_argument("--serial", action="store_true",
                       help="run a study's cases one by one in this process, without Dask "
                            "(faster for a few short cases: no cluster to start)")
    args = parse(parser, argv)
    if len(args.nbeams) > 1:
        return study_main(parser, args)
    if args.scheduler or args.serial:
        parser.error(f"{'--scheduler' if args.scheduler else '--serial'} is for a study: give "
                     f"several --nbeams, e.g. 1..10")
    if args.out and not args.out.endswith(".csv"):
        parser.error("--out of one run is a .csv table (a .parquet table is a study's)")
    args.nbeams = args.nbeams[0]

    model = build_model(args.nbeams, args.eps1flex, args.omega, args.alpha)
    print(model.summary())
    try:
        result = run(model, args.revolutions, omega=args.omega, alpha=args.alpha,
                     method=args.method, steps_per_revolution=args.steps_per_revolution,
                     rtol=args.rtol, on_failure="return", progress=True)
    except KeyboardInterrupt as interrupt:  # write what was computed, then stop
        if args.out and getattr(interrupt, "partial_result", None) is not None:
            write_csv(interrupt.partial_result, args.out)
            print(f"interrupted: {len(interrupt.partial_result.t)} rows written to {args.out}")
        raise
    print(f"\nsimulation: {result.message}")
    if args.out:
        write_csv(result, args.out)
        print(f"{len(result.t)} rows written to {args.out}")
    if len(result.t) < 2:
        return 1
    describe(result)
    ok = print_checks("\nchecks:", checks(result))

    def draw(filename, window):
        v = midpoint_deflection(model, result.x)
        plot.plot_curves(np.degrees(result["x2.1"]), {"v/l2": v}, xlabel="crank angle [deg]",
                         ylabel="mid-point deflection v/l2 [-]", title=model.name,
                         filename=filename, window=window)

    finish_outputs(args, result, draw, movie_title=f"{model.name} (deflection x "
                   f"{args.exaggeration:g})", exaggeration=args.exaggeration)
    return 0 if ok and result.success else 1


def beam_counts(text: str) -> list[int]:
    """An argparse type: a number of beams, or several (``1..10``, ``1,2,4``), each >= 1."""
    from flexmbd.studies import parse_values

    try:
        values = parse_values(text, "--nbeams")
    except fm.FlexmbdError as error:
        raise argparse.ArgumentTypeError(str(error).removeprefix("--nbeams: ")) from None
    if not all(isinstance(n, int) and n >= 1 for n in values):
        raise argparse.ArgumentTypeError(f"{text}: beam counts are whole numbers of at least 1")
    return values


def crank_angle(result: fm.SimulationResult) -> np.ndarray:
    """The crank angle ``phi2`` [rad] at the output times, shape ``(nt,)``."""
    return result["x2.1"]


def deflection(result: fm.SimulationResult) -> np.ndarray:
    """``v/l2`` at the output times, shape ``(nt,)`` (:func:`midpoint_deflection`)."""
    return midpoint_deflection(result.model, result.x)


def peak_deflection(result: fm.SimulationResult) -> float:
    """The largest ``|v/l2|`` of the run."""
    return float(np.max(np.abs(deflection(result)), initial=0.0))


def study(nbeams: list[int], eps1flex: bool = False, revolutions: float = 2.0, *,
          client=None, out: str | None = None, progress: bool | None = None, **options):
    """EXERCISES 4 part 2 as a sweep over ``nbeams`` (:func:`flexmbd.sweep`): an xarray
    Dataset with the histories ``phi`` [rad] and ``v_over_l2`` along ``(case, step)`` and
    the metric ``peak`` (largest ``|v/l2|``) per case; ``options`` go to :func:`run`."""
    analysis = functools.partial(run, revolutions=revolutions, **options)
    builder = functools.partial(build_model, omega=options.get("omega", OMEGA),
                                alpha=options.get("alpha", 0.0))
    return fm.sweep(builder, {"nbeams": nbeams, "eps1flex": [eps1flex]}, analysis,
                    {"phi": crank_angle, "v_over_l2": deflection, "peak": peak_deflection},
                    client, out=out, progress=progress)


def plot_convergence(data, eps1flex: bool = False, *, filename: str | None = None,
                     window: bool = False):
    """The study's figure: the ``v/l2`` histories of the finished cases together, beside
    the peak ``|v/l2|`` against the number of beams. Returns the matplotlib figure."""
    ok = data["status"].values == "ok"
    nbeams, peak = data["nbeams"].values, data["peak"].values
    phi = np.degrees(data["phi"].values[np.argmax(ok)])
    curves = {f"{n} beam{'s' * int(n > 1)}": v for n, v, good in
              zip(nbeams, data["v_over_l2"].values, ok, strict=True) if good}
    return plot.plot_study(phi, curves, nbeams[ok], peak[ok], xlabel="crank angle [deg]",
                           ylabel="mid-point deflection v/l2 [-]", parameter_label="beams",
                           metric_label="peak |v/l2| [-]",
                           title=f"flexible slider-crank: v/l2 against the number of beams"
                                 f"{' (flexible elongation)' if eps1flex else ''}",
                           filename=filename, window=window)


def study_main(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """``--nbeams`` with several values: the study, its table and its plot."""
    if args.movie:
        parser.error("--movie animates one run; give one --nbeams value")
    if args.out and not args.out.endswith(".parquet"):
        parser.error("--out of a study is a .parquet table, written as cases finish")
    where = "this process" if args.serial else args.scheduler or "a local Dask cluster"
    print(f"study: v/l2 for {', '.join(map(str, args.nbeams))} beams"
          f"{', flexible elongation' if args.eps1flex else ''}, on {where}")
    try:
        data = study(args.nbeams, args.eps1flex, args.revolutions,
                     client="serial" if args.serial else args.scheduler,
                     out=args.out, progress=True, omega=args.omega, alpha=args.alpha,
                     method=args.method, steps_per_revolution=args.steps_per_revolution,
                     rtol=args.rtol)
    except KeyboardInterrupt:
        if args.out:
            print(f"interrupted: the finished cases are in {args.out}; run the same command "
                  f"to resume", file=sys.stderr)
        raise
    if args.out:
        print(f"table written to {args.out}")
    ok = data["status"].values == "ok"
    nbeams, peak = data["nbeams"].values, data["peak"].values
    finest = peak[ok][np.argmax(nbeams[ok])] if ok.any() else np.nan
    print(f"\n{'nbeams':>6}  {'peak |v/l2|':>12}  {'vs finest':>10}  {'time [s]':>8}  status")
    for k in range(len(nbeams)):
        status = "ok" if ok[k] else str(data["error"].values[k])
        print(f"{nbeams[k]:>6}  {peak[k]:>12.6f}  {peak[k] / finest - 1:>+10.2e}  "
              f"{data['wall_time'].values[k]:>8.3f}  {status}")
    if (args.plot or args.show) and ok.any():
        plot_convergence(data, args.eps1flex, filename=args.plot, window=args.show)
        if args.plot:
            print(f"plot saved to {args.plot}")
        if args.show:
            plot.show()
    return 0 if ok.all() else 1


if __name__ == "__main__":
    sys.exit(main())
