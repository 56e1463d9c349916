"""``flexmbd sweep FILE.dat --vary NAME=VALUES ... --out table.parquet``: a parameter study
of a SPACAR input file on Dask."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import ArgumentError
from ..io.outputs import check_output
from ..studies.case import ANALYSES, MODE_COUNT, STATISTICS

DESCRIPTION = """Run a SPACAR input file once per combination of the --vary values, on a
local Dask cluster (one worker per core) or on --scheduler, and write one row per case
(parameters, metrics, status, error, wall time) to a Parquet table as cases finish. Run
the same command again to resume an interrupted study."""

EPILOG = """NAME is KEYWORD:NUMBER...:POSITION: the keyword, the element or node number
(and more numbers where that leaves several lines) and the position of the value after
them, e.g. ESTIFF:2:2 (EI of element 2), X:5:1 (x of node 5), INPUTX:2:3 (v0 of
'INPUTX 2 1 x0 v0'), TIMESTEP:1 (end time). VALUES is a list 1,2,5, a range 1..10, n
evenly spaced values 0.1..0.5/5 or a log range log:1e-3..1e3/7. Example:
flexmbd sweep crank.dat --vary ESTIFF:2:2=log:1..100/5 --vary INPUTX:2:3=100,150
--metric absmax:e2.2 --out study.parquet"""


def add_command(commands) -> None:
    """The ``sweep`` sub-command and its options."""
    parser = commands.add_parser(
        "sweep", help="parameter study of a SPACAR file on Dask (flexmbd sweep --help)",
        description=DESCRIPTION, epilog=EPILOG)
    parser.add_argument("file", metavar="FILE.dat", help="SPACAR input file")
    parser.add_argument("--vary", action="append", required=True, metavar="NAME=VALUES",
                        help="a value of the file and the values it takes (repeat for more; "
                             "every combination runs)")
    parser.add_argument("--out", required=True, metavar="TABLE.parquet",
                        help="the study's table, written as cases finish")
    parser.add_argument("--analysis", default="auto", choices=ANALYSES,
                        help="auto: dynamic when the file has DYNX/DYNE, else kinematic "
                             "(over TIMESTEP); static, modes, buckling at the file's "
                             "equilibrium")
    parser.add_argument("--metric", action="append", default=[], metavar="STAT:COLUMN",
                        help=f"a number per case, STAT one of {', '.join(STATISTICS)} "
                             f"(default: absmax and final of the degrees of freedom; modes: "
                             f"f1 .. f{MODE_COUNT})")
    parser.add_argument("--keep", action="append", default=[], metavar="COLUMN",
                        help="a result column to keep whole (a history) in the table")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on this Dask scheduler (tcp://host:8786) instead of a local "
                            "cluster")
    where.add_argument("--serial", action="store_true",
                       help="run the cases one by one in this process, without Dask")
    parser.add_argument("--restart", action="store_true",
                        help="discard what TABLE.parquet holds and run every case")


def run(args: argparse.Namespace) -> int:
    """``flexmbd sweep``: 0 when every case succeeded, 1 when some failed, 130 when
    interrupted (what finished is in the table; the same command resumes)."""
    from ..io.dat.parameters import DatTemplate
    from ..studies.grid import parse_values
    from ..studies.sweep import sweep

    check_output(args.out, "study", "--out")
    grid = {}
    for text in args.vary:
        name, equals, values = text.partition("=")
        if not equals or not name:
            raise ArgumentError("--vary", f"{text!r} is not NAME=VALUES, e.g. ESTIFF:2:2=1..5")
        if name in grid:
            raise ArgumentError("--vary", f"{name} is varied twice")
        grid[name] = parse_values(values, f"--vary {name}")
    template = DatTemplate.read(args.file)
    outputs = {**{m: m for m in args.metric or default_metrics(template, grid, args.analysis)},
               **{c: c for c in args.keep}}
    client = "serial" if args.serial else args.scheduler
    cases = 1
    for values in grid.values():
        cases *= len(values)
    where = ("this process" if args.serial else args.scheduler or "a local Dask cluster")
    print(f"sweep of {args.file}: {cases} case{'s' * (cases > 1)} of {args.analysis} analysis "
          f"on {where}; keeping {', '.join(outputs)}")
    out = Path(args.out)
    if (out.exists() or out.with_name(out.name + ".partial").exists()) and not args.restart:
        print(f"resuming: the cases already in {args.out} are not run again (--restart runs "
              f"every case)")
    try:
        result = sweep(template, grid, args.analysis, outputs, client, out=args.out,
                       restart=args.restart, progress=True)
    except KeyboardInterrupt as interrupt:
        done = getattr(interrupt, "partial_result", None)
        print(f"interrupted: {0 if done is None else _rows(done)} of {cases} cases are in "
              f"{args.out}; run the same command to resume", file=sys.stderr)
        return 130
    import pandas as pd

    # one row per case: a study that kept histories is a Dataset with a step dimension
    table = (result.drop_dims("step").to_dataframe().reset_index()
             if hasattr(result, "drop_dims") else result)
    failed = table[table["status"] != "ok"]
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(table.drop(columns=["error"]).to_string(index=False, max_rows=40))
    for _, row in failed.head(5).iterrows():
        print(f"case {row['case']} failed: {row['error']}")
    print(f"{len(table)} cases, {len(failed)} failed; table written to {args.out}")
    return 0 if failed.empty else 1


def default_metrics(template, grid: dict, analysis: str) -> list[str]:
    """What a study keeps when no --metric is given: frequencies or load factors of modes
    and buckling; the final value of the watched columns of a static analysis; the
    largest magnitude and the final value of the degrees of freedom otherwise (the
    driving loads of an inverse analysis)."""
    from ..analysis.runs import default_mode
    from ..studies.case import split_build
    from .run import default_columns, empty_result

    first = {name: values[0] for name, values in grid.items()}
    model, settings = split_build(template(**first))
    if analysis in ("modes", "buckling"):
        prefix = "f" if analysis == "modes" else "lambda"
        count = min(MODE_COUNT, len(model.dynamic_q_labels))
        return [f"{prefix}{k}" for k in range(1, count + 1)]
    if analysis == "static":
        from .linear import watched_columns

        return [f"final:{c}" for c in watched_columns(model, settings)[:4]]
    mode = default_mode(model) if analysis == "auto" else analysis
    columns = default_columns(empty_result(model, mode), mode)[:4]
    return [f"{stat}:{c}" for c in columns for stat in ("absmax", "final")]


def _rows(result) -> int:
    """Cases in a study's DataFrame or Dataset."""
    return int(result.sizes.get("case", 0)) if hasattr(result, "sizes") else len(result)
