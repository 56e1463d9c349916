"""``flexmbd static | modes | buckling | statespace FILE.dat``: the linearized analyses of a
SPACAR input file, printed as tables and written as result files and plots.

Each starts from the static equilibrium of the file (``XF``, gravity, and the load
steps of ``DELXF``, ``DELINPX``, ``ITERSTEP``) and analyses its last load step, as
SPACAR's static and linear modes do; ``flexmbd modes --along`` linearizes along the
file's motion instead (``TIMESTEP``).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from ..errors import ArgumentError
from ..io.outputs import check_output
from ..io.sbd.records import SPACAR_MODES
from ..model import Model
from ..results import write_csv
from ..settings import RunSettings

# the analyses load when a command runs, not when the parser is built

COMMANDS = {
    "static": "static equilibrium with load steps (XF, DELXF, DELINPX, ITERSTEP)",
    "modes": "eigenfrequencies [Hz] and mode shapes at the equilibrium, or --along the motion",
    "buckling": "buckling load factors of the loads at the equilibrium, with the shapes",
    "statespace": "state-space model A, B, C, D for INPUTF inputs and OUTX/OUTXP outputs",
}


def add_commands(commands) -> None:
    """The four sub-commands and their options."""
    for name, text in COMMANDS.items():
        parser = commands.add_parser(name, help=text, description=text[0].upper() + text[1:])
        parser.add_argument("file", metavar="FILE.dat", help="SPACAR input file")
        parser.add_argument("--release", action="store_true",
                            help="release over-constraints as SPACAR Light does (they are "
                                 "printed)")
        parser.add_argument("--out", metavar="FILE",
                            help="write the table (.csv; static: also SPACAR's .sbd; modes: "
                                 "also .sbm, the linearized equations of every load step; "
                                 "statespace: .npz with A, B, C, D)")
        if name != "statespace":
            parser.add_argument("--plot", metavar="FILE.png",
                                help="plot the results (static: outputs against the load "
                                     "factor; modes/buckling: the shapes; --along: frequencies)")
        if name in ("modes", "buckling"):
            parser.add_argument("--count", type=int, default=6,
                                help="modes to report (default 6)")
        if name == "static":
            parser.add_argument("--steps", type=int, help="load steps (default: ITERSTEP)")
            parser.add_argument("--modes", type=int, default=0, metavar="K",
                                help="the K lowest frequencies at every load step")
            parser.add_argument("--buckling", type=int, default=0, metavar="K",
                                help="the K buckling load factors (signed) at every step")
            parser.add_argument("--compliance", action="append", default=[],
                                metavar="NODE[:ROT]",
                                help="the compliance of a node (and its rotational node) at "
                                     "every step; repeat for more nodes")
            parser.add_argument("--frame", choices=("global", "body"), default="global",
                                help="axes of the compliance (default global)")
            parser.add_argument("--drive", choices=("held", "free"), default="held",
                                help="inputs held or free in the compliance (default held)")
        if name == "modes":
            parser.add_argument("--along", action="store_true",
                                help="linearize at every output time of the file's motion")
        if name == "statespace":
            parser.add_argument("--damping", type=float, metavar="ZETA",
                                help="modal damping ratio of every mode (default: the "
                                     "model's EDAMP)")
            parser.add_argument("--bode", metavar="FILE.png",
                                help="Bode plot from the first input to every output")


def run(args: argparse.Namespace) -> int:
    """Run one linearized command; 0 on success, 1 when the equilibrium failed."""
    kinds = {"out": {"static": "results", "statespace": "matrices",
                     "modes": "table" if getattr(args, "along", False) else "linear"
                     }.get(args.command, "table"),
             "plot": "plot", "bode": "plot"}
    for option, kind in kinds.items():
        if getattr(args, option, None):
            check_output(getattr(args, option), kind, f"--{option}")
    if getattr(args, "count", 1) < 1:
        raise ArgumentError("--count", f"must be at least 1, got {args.count}")
    from .run import read_input

    model, settings = read_input(args.file, args.release)
    print(model.summary())
    if args.command == "modes" and args.along:
        return _modes_along(args, model, settings)
    from ..analysis.statics import file_equilibrium

    statics = file_equilibrium(model, settings, getattr(args, "steps", None))
    if not statics.success:
        print(statics.message)
        if args.command == "static" and args.out:
            from .run import save_result

            save_result(statics, args.out, SPACAR_MODES["static"])
        return 1
    return {"static": _static, "modes": _modes, "buckling": _buckling,
            "statespace": _statespace}[args.command](args, model, settings, statics)


def watched_columns(model: Model, settings: RunSettings) -> list[str]:
    """The columns a static table shows: OUTX, else the first six dynamic degrees of
    freedom."""
    return list(settings.outputs or model.dynamic_q_labels[:6])


def _static(args, model, settings, statics) -> int:
    columns = watched_columns(model, settings)
    print(statics.message)
    shown = {"load": statics["load"], **{c: statics[c] for c in columns}}
    table = _load_step_table(args, statics)
    for name, values in table.items():
        # the printed table shows each compliance's diagonal; the CSV holds it all
        if name != "load" and (not name.startswith("C") or name[-1] == name[-2]):
            shown[name] = values
    print(_table(list(shown), list(shown.values())))
    for note in getattr(table, "notes", ()):   # why a cell is NaN
        print(f"note: {note}")
    if args.out:
        from .run import save_result

        if table and Path(args.out).suffix.lower() == ".csv":
            write_csv(args.out, {**statics.columns(), **{k: v for k, v in table.items()
                                                         if k != "load"}})
        else:
            save_result(statics, args.out, SPACAR_MODES["static"])
        print(f"{len(statics.t)} rows written to {args.out}")
    if args.plot and len(statics.t) > 1:
        statics.plot(columns, "load", filename=args.plot, title=f"{model.name} (static)")
        print(f"plot saved to {args.plot}")
    return 0


def _load_step_table(args, statics) -> dict:
    """The linearized analyses of every load step the options ask for (empty: none)."""
    if not (args.modes or args.buckling or args.compliance):
        return {}
    from ..analysis.load_steps import load_step_table

    for option in ("modes", "buckling"):
        if getattr(args, option) < 0:
            raise ArgumentError(f"--{option}", f"must be 0 or more, got {getattr(args, option)}")
    nodes = []
    for given in args.compliance:
        node, _, rotational = given.partition(":")
        try:
            nodes.append((int(node), int(rotational) if rotational else None))
        except ValueError:
            raise ArgumentError("--compliance", f"{given!r}: give NODE or NODE:ROT, node "
                                                f"numbers") from None
    return load_step_table(statics, modes=args.modes, buckle=args.buckling,
                           compliance=nodes, frame=args.frame, drive=args.drive,
                           progress=True)


def _modes(args, model, settings, statics) -> int:
    from ..analysis.modes import vibration_modes

    modes = vibration_modes(statics.linearization(), args.count)
    if args.out and Path(args.out).suffix.lower() == ".sbm":
        from ..io.sbd import write_sbm

        write_sbm(args.out, [statics.linearization(k) for k in range(len(statics.t))])
        print(f"linearized equations of {len(statics.t)} load steps written to {args.out}")
        args = argparse.Namespace(**{**vars(args), "out": None})
    _report_shapes(args, model, f"vibration modes at the equilibrium (load factor "
                                f"{statics.t[-1]:g}):", ("frequency [Hz]", "frequency"),
                   modes.frequencies, modes.linearization.x, modes.motion,
                   lambda k, f: f"mode {k}: {f:.4g} Hz")
    return 0


def _modes_along(args, model, settings) -> int:
    from ..analysis.modes import modes_along
    from ..analysis.runs import analyse, default_mode
    from .run import output_times

    times = output_times(settings, None, None)
    motion = analyse(model, settings, default_mode(model), times, progress=True)
    print(motion.message)
    along = modes_along(motion, args.count, progress=True)
    columns = along.columns()
    shown = slice(None, None, max(1, len(along.t) // 20))
    print(_table(list(columns), [v[shown] for v in columns.values()]))
    if args.out:
        write_csv(args.out, columns)
        print(f"{len(along.t)} rows written to {args.out}")
    if args.plot and len(along.t) > 1:
        from ..plot import plot_curves

        plot_curves(along.t, {k: v for k, v in columns.items() if k != "t"}, xlabel="t [s]",
                    ylabel="frequency [Hz]", title=f"{model.name}: frequencies along the motion",
                    filename=args.plot)
        print(f"plot saved to {args.plot}")
    return 0 if motion.success else 1


def _buckling(args, model, settings, statics) -> int:
    from ..analysis.modes import buckling

    result = buckling(statics.linearization(), args.count)
    _report_shapes(args, model, f"buckling load factors of the loads at load factor "
                                f"{statics.t[-1]:g}:", ("load factor", "load_factor"),
                   result.factors, result.linearization.x, result.motion,
                   lambda k, f: f"buckling {k}: factor {f:.4g}")
    return 0


def _report_shapes(args, model, heading: str, names: tuple[str, str], values: np.ndarray,
                   x: np.ndarray, motion: np.ndarray, label) -> None:
    """Print the table of a value per mode (``names``: its header and its CSV column), write
    it (``--out``) and draw the shapes ``motion`` at ``x``, titled ``label(k, value)``
    (``--plot``)."""
    numbers = np.arange(1, len(values) + 1)
    print(heading)
    print(_table(["mode", names[0]], [numbers, values]))
    if args.out:
        write_csv(args.out, {"mode": numbers, names[1]: values})
        print(f"{len(numbers)} rows written to {args.out}")
    if args.plot:
        from ..plot import plot_shapes

        plot_shapes(model, x, motion, [label(k, v) for k, v in zip(numbers, values, strict=True)],
                    title=model.name, filename=args.plot)
        print(f"shapes saved to {args.plot}")


def _statespace(args, model, settings, statics) -> int:
    from ..analysis.statespace import state_space

    if not settings.force_inputs or not (settings.outputs or settings.rate_outputs):
        raise ArgumentError("FILE.dat", "a state-space model needs INPUTF (force inputs) and "
                                        "OUTX or OUTXP (outputs) lines: SPACAR's third block "
                                        "after END HALT, e.g. 'INPUTF 1 5 2' and 'OUTX 1 5 2'")
    system = state_space(statics.linearization(), settings.force_inputs, settings.outputs,
                         settings.rate_outputs, damping_ratio=args.damping)
    if settings.output_order:  # the file's numbering of the outputs
        rows = [system.outputs.index(name) for name in settings.output_order]
        system = dataclasses.replace(system, C=system.C[rows], D=system.D[rows],
                                     outputs=tuple(settings.output_order))
    poles = np.linalg.eigvals(system.A)
    print(f"state space: {system.A.shape[0]} states, inputs {', '.join(system.inputs)}, "
          f"outputs {', '.join(system.outputs)}")
    print("static gain (outputs per unit input):")
    gain = system.static_gain()
    print(_table(["output", *system.inputs],
                 [np.array(system.outputs), *(gain[:, j] for j in range(gain.shape[1]))]))
    frequencies = np.unique(np.round(np.abs(poles.imag) / (2 * np.pi), 9))
    print(f"pole frequencies |Im p|/(2 pi) [Hz]: "
          f"{', '.join(f'{f:.6g}' for f in frequencies[:8])}")
    if args.out:
        path = Path(args.out)
        np.savez(path, A=system.A, B=system.B, C=system.C, D=system.D,
                 inputs=np.array(system.inputs), outputs=np.array(system.outputs),
                 states=np.array(system.states))
        print(f"A, B, C, D written to {args.out}")
    if args.bode:
        _bode(system, model, args.bode)
        print(f"Bode plot saved to {args.bode}")
    return 0


def _bode(system, model, filename) -> None:
    """Magnitude and phase from the first input to every output, ``C (i w - A)^-1 B`` in
    the modal coordinates of ``A`` (a transfer-function form loses precision)."""
    from ..plot import plot_panels

    poles, vectors = np.linalg.eig(system.A)
    size = np.abs(poles)
    low, high = max(size[size > 0].min() / 10, 1e-3), size.max() * 10
    omega = np.logspace(np.log10(low), np.log10(high), 600)
    left = system.C @ vectors
    right = np.linalg.solve(vectors, system.B[:, 0])
    response = (left[:, None, :] * right / (1j * omega[:, None] - poles)).sum(axis=-1)
    magnitude, phase = {}, {}
    for k, output in enumerate(system.outputs):
        name = f"{output}/{system.inputs[0]}"
        magnitude[name] = 20 * np.log10(np.abs(response[k]) + 1e-300)
        phase[name] = np.degrees(np.unwrap(np.angle(response[k])))
    fig = plot_panels(omega / (2 * np.pi), [magnitude, phase], xlabel="frequency [Hz]",
                      ylabels=["magnitude [dB]", "phase [deg]"], title=f"{model.name}: Bode")
    for ax in fig.axes:
        ax.set_xscale("log")
    from ..plot import save_figure

    save_figure(fig, filename)


def _table(headers: list[str], columns: list[np.ndarray]) -> str:
    """Columns as aligned text with a header row."""
    cells = [[str(h) for h in headers]]
    for row in zip(*columns, strict=True):
        cells.append([value if isinstance(value, str) else f"{value:.6g}" for value in row])
    widths = [max(len(r[k]) for r in cells) for k in range(len(headers))]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True))
                     for r in cells)
