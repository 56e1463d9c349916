"""``flexmbd spacar MODE FILE`` (a run as ``spacar(mode, file)``, with SPACAR's result
files), ``flexmbd compare A B`` (two result files, or a result file and a run) and
``flexmbd stressbeam FILE STEP`` (beam stresses of a result, for SPACAR's tools)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..errors import ArgumentError

RESULT_SUFFIXES = (".sbd", ".sbm", ".ltv")


def add_commands(commands) -> None:
    """The ``spacar`` and ``compare`` commands."""
    spacar = commands.add_parser(
        "spacar", help="run a file as spacar(mode, file) does, writing .sbd/.sbm/.ltv",
        description="Run a SPACAR input file as spacar(MODE, FILE): 0 check, 1 motion, "
                    "2 inverse dynamics, 3 and 4 linearization along the stored path, 7 and "
                    "10 statics (10 with .sbm), 9 state space; a negative mode as the "
                    "positive one. The result files are written next to FILE.")
    spacar.add_argument("mode", type=int, metavar="MODE", help="SPACAR's mode")
    spacar.add_argument("file", metavar="FILE", help="the input file, with or without .dat")
    compare = commands.add_parser(
        "compare", help="largest difference per record of two SPACAR result files",
        description="Compare SPACAR result files record by record: REFERENCE against OTHER, "
                    "each a .sbd, .sbm or .ltv; OTHER may be a .dat file, run in the "
                    "reference's MODE. Exit 0 when every record both have agrees within "
                    "--rtol of the reference's largest value.")
    compare.add_argument("reference", metavar="REFERENCE", help="a .sbd, .sbm or .ltv file")
    compare.add_argument("other", metavar="OTHER", help="a .sbd, .sbm, .ltv or .dat file")
    compare.add_argument("--rtol", type=float, default=1e-6,
                         help="largest difference relative to the record's largest value "
                              "(default 1e-6)")
    compare.add_argument("--mode", type=int,
                         help="SPACAR mode to run OTHER.dat in (default: REFERENCE's MODE)")
    stress = commands.add_parser(
        "stressbeam", help="largest stresses at both ends of beams of a SPACAR result",
        description="The largest von Mises stress at both ends of spatial beams (BEAM, "
                    "BEAMW) at one step of a SPACAR result: the positions and stresses of "
                    "FILE.sbd, of the model FILE.dat, each beam with its cross-section. "
                    "Prints one line per beam: its number and the stress at p and at q "
                    "[Pa]. The stressbeam of flexmbd's MATLAB face (matlab/) runs it.")
    stress.add_argument("file", metavar="FILE",
                        help="the result, FILE.sbd (or FILE), beside its FILE.dat")
    stress.add_argument("step", type=int, metavar="STEP", help="the step (1-based)")
    stress.add_argument("--beam", nargs="+", action="append", required=True,
                        metavar="ELEMENT SHAPE DIMENSION",
                        help="a beam and its section: ELEMENT rect WIDTH THICKNESS, or "
                             "ELEMENT circ DIAMETER [m] (as SPACAR Light's cshape and dim); "
                             "once per beam")


def run_spacar(args: argparse.Namespace) -> int:
    """``flexmbd spacar``: 0 when the run completed, 1 when it stopped early, 130 when it
    was interrupted (the steps computed are written in either case)."""
    from ..io.sbd.runs import MODES, spacar_run

    run = spacar_run(args.mode, args.file, progress=True)
    print(f"mode {args.mode} ({MODES[abs(args.mode)]}) of {run.base}.dat: {run.message}")
    for path in run.write():
        file = run.files[path.suffix[1:].upper()]
        print(f"  {path}: {len(file.tables)} tables, {len(file.steps)} records x "
              f"{file.n_steps} steps")
    if run.interrupted:
        return 130
    return 0 if run.success else 1


def run_compare(args: argparse.Namespace) -> int:
    """``flexmbd compare``: 0 when the records agree within ``--rtol``, 1 otherwise."""
    from ..io.sbd import read_sbd
    from ..io.sbd.compare import compare

    if not args.rtol >= 0 or not math.isfinite(args.rtol):
        raise ArgumentError("--rtol", f"must be a finite number >= 0, got {args.rtol}")
    if Path(args.reference).suffix.lower() not in RESULT_SUFFIXES:
        raise ArgumentError("REFERENCE", f"{args.reference!r} must be a .sbd, .sbm or .ltv "
                                         f"file")
    reference = read_sbd(args.reference)
    if Path(args.other).suffix.lower() == ".dat":
        other = _run_for(reference, args)
    elif Path(args.other).suffix.lower() in RESULT_SUFFIXES:
        other = read_sbd(args.other)
    else:
        raise ArgumentError("OTHER", f"{args.other!r} must be a .sbd, .sbm, .ltv or .dat file")
    differences = compare(reference, other)
    print(f"{args.reference} ({reference.n_steps} steps) against {args.other} "
          f"({other.n_steps} steps), relative tolerance {args.rtol:g}:")
    rows = [["record", "largest diff", "at step", "largest value", "relative", ""]]
    failed = 0
    for d in differences:
        if math.isnan(d.largest):
            rows.append([d.name, "-", "-", "-", "-", d.note])
            continue
        bad = d.relative > args.rtol
        failed += bad
        rows.append([d.name, f"{d.largest:.3e}", "" if d.step is None else str(d.step),
                     f"{d.scale:.3e}", f"{d.relative:.2e}",
                     "; ".join(filter(None, ["DIFFERS" if bad else "", d.note]))])
    widths = [max(len(r[k]) for r in rows) for k in range(5)]
    for r in rows:
        print("  " + "  ".join(c.ljust(w) if k == 0 else c.rjust(w)
                               for k, (c, w) in enumerate(zip(r, widths, strict=False)))
              + ("  " + r[5] if r[5] else ""))
    compared = sum(not math.isnan(d.largest) for d in differences)
    print(f"{compared - failed} of {compared} records agree" +
          (f"; {failed} differ" if failed else ""))
    return 1 if failed else 0


def _run_for(reference, args: argparse.Namespace):
    """The file of ``reference``'s kind from a run of ``args.other`` (a .dat) in its mode."""
    from ..io.sbd import read_sbd
    from ..io.sbd.runs import spacar_run

    mode = args.mode
    if mode is None:
        # an .sbm or .ltv keeps no MODE: its .sbd beside it does
        data = Path(args.reference).with_suffix(".sbd")
        stored = reference if "MODE" in reference.tables else (
            read_sbd(data) if data.is_file() else None)
        if stored is None or "MODE" not in stored.tables:
            raise ArgumentError("--mode", f"{args.reference} stores no MODE (nor a .sbd beside "
                                          f"it): give the mode to run {args.other} in")
        mode = int(stored["MODE"][0, 0])
    run = spacar_run(mode, args.other, progress=True)
    if reference.kind not in run.files:
        raise ArgumentError("--mode", f"mode {mode} writes no {reference.kind.lower()} file "
                                      f"(it writes {', '.join(run.files)})")
    print(f"ran {args.other} in mode {mode}: {run.message}")
    return run.files[reference.kind]


def run_stressbeam(args: argparse.Namespace) -> int:
    """``flexmbd stressbeam``: the beams' largest stresses at both ends, one line each."""
    import numpy as np

    from ..analysis.stresses import beam_resultants
    from ..io.dat import read_dat
    from ..io.sbd import read_sbd
    from ..model.numbering import SpacarNumbering

    base = Path(args.file)
    if base.suffix.lower() in (*RESULT_SUFFIXES, ".dat"):
        base = base.with_suffix("")
    model, _ = read_dat(base.with_suffix(".dat"))
    result = read_sbd(base.with_suffix(".sbd"))
    number = SpacarNumbering(model)
    x, sigma = np.empty(model.n_coordinates), np.empty(model.n_deformations)
    x[number.x] = result.step("X", args.step)[:, 0]
    sigma[number.e] = result.step("SIG", args.step)[:, 0]
    for spec in args.beam:
        element, section = _beam_section(spec, model)
        ends = [section.largest_stress(r)[0]
                for r in beam_resultants(model, x, sigma, element)]
        print(f"{element} {ends[0]:.17g} {ends[1]:.17g}")
    return 0


def _beam_section(spec: list[str], model):
    """``ELEMENT rect WIDTH THICKNESS`` or ``ELEMENT circ DIAMETER`` as the element's number
    and its :class:`~flexmbd.sections.Section`."""
    from ..sections import Circle, Rectangle

    shapes = {"rect": (Rectangle, 2), "circ": (Circle, 1)}
    usage = "give --beam ELEMENT rect WIDTH THICKNESS or --beam ELEMENT circ DIAMETER"
    if len(spec) < 2 or spec[1] not in shapes:
        raise ArgumentError("--beam", f"{' '.join(spec)!r}: {usage}")
    make, count = shapes[spec[1]]
    try:
        element = int(spec[0])
        dimensions = [float(v) for v in spec[2:]]
    except ValueError:
        raise ArgumentError("--beam", f"{' '.join(spec)!r}: {usage}") from None
    if len(dimensions) != count:
        raise ArgumentError("--beam", f"{' '.join(spec)!r}: {usage}")
    found = model.elements.get(element)
    if found is None or found.type.keyword not in ("BEAM", "BEAMW"):
        raise ArgumentError("--beam", f"element {element} is not a spatial beam (BEAM, BEAMW) "
                                      f"of the model")
    return element, make(*dimensions)
