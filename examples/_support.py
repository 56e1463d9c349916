"""Shared plumbing of the examples: the check table and the output options."""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass

from flexmbd.errors import FlexmbdError
from flexmbd.io.outputs import check_display, check_output


@dataclass(frozen=True)
class Check:
    """A computed value against an independent expected value.

    Passes when ``|computed - expected| <= rtol * max(|expected|, scale)``.
    """

    name: str
    computed: float
    expected: float
    rtol: float = 1e-9
    scale: float = 1.0

    @property
    def error(self) -> float:
        return abs(self.computed - self.expected)

    @property
    def passed(self) -> bool:
        return self.error <= self.rtol * max(abs(self.expected), self.scale)


def print_checks(title: str, checks: list[Check], file=None) -> bool:
    """Print a table of checks; returns whether all passed."""
    file = file or sys.stdout
    width = max(len(c.name) for c in checks)
    print(title, file=file)
    print(f"  {'quantity':<{width}}  {'computed':>20}  {'expected':>20}  {'|error|':>9}",
          file=file)
    for c in checks:
        mark = "ok" if c.passed else "FAILED"
        print(f"  {c.name:<{width}}  {c.computed:>20.12g}  {c.expected:>20.12g}  "
              f"{c.error:>9.1e}  {mark}", file=file)
    passed = all(c.passed for c in checks)
    print(f"  {'all' if passed else 'NOT all'} {len(checks)} checks passed", file=file)
    return passed


def _output_file(what: str):
    """An argparse type for an output file holding ``what`` (``"plot"``, ``"movie"``,
    ``"table"``), checked before any work: type, directory, the extra that writes it."""
    def check(name: str) -> str:
        try:
            check_output(name, what, "file")
        except FlexmbdError as error:
            raise argparse.ArgumentTypeError(str(error).removeprefix("file: ")) from None
        return name
    return check


def number(low: float = -math.inf, high: float = math.inf, *, whole: bool = False,
           open_low: bool = False):
    """An argparse type for a finite number in ``[low, high]`` (``(low, high]`` with
    ``open_low``), a whole number with ``whole``."""
    bounds = [f"{'>' if open_low else '>='} {low:g}"] if low > -math.inf else []
    bounds += [f"<= {high:g}"] if high < math.inf else []
    wanted = " and ".join(["finite", *bounds])

    def check(text: str):
        try:
            value = int(text) if whole else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not a {'whole ' if whole else ''}number") from None
        above = value > low if open_low else value >= low
        if not (math.isfinite(value) and above and value <= high):
            raise argparse.ArgumentTypeError(f"{text} must be {wanted}")
        return value
    return check


#: argparse types of the usual options
POSITIVE = number(0.0, open_low=True)
FINITE = number()


def count(low: int = 1):
    """An argparse type for a whole number of at least ``low``."""
    return number(low, whole=True)


def example_parser(doc: str, prog: str | None) -> argparse.ArgumentParser:
    """The parser of an example: its docstring's first paragraph as description."""
    return argparse.ArgumentParser(prog=prog, description=doc.split("\n\n")[0])


#: the example metavar of each kind of output file
_METAVARS = {"table": "FILE.csv", "plot": "FILE.png", "movie": "FILE.mp4",
             "table or study": "FILE.csv|.parquet"}


def add_file_option(parser: argparse.ArgumentParser, flag: str, what: str, text: str) -> None:
    """An option naming an output file holding ``what`` (``"plot"``, ``"movie"``,
    ``"table"``), checked when the arguments are parsed, before any work."""
    parser.add_argument(flag, metavar=_METAVARS[what], type=_output_file(what), help=text)


def add_output_options(parser: argparse.ArgumentParser, table: bool = False) -> None:
    """``--plot``, ``--movie``, ``--show`` and, with ``table``, ``--out FILE.csv``; the files
    are checked before any work."""
    if table:
        add_file_option(parser, "--out", "table", "write the result table as CSV")
    add_file_option(parser, "--plot", "plot", "save a plot (.png, .pdf, .svg)")
    add_file_option(parser, "--movie", "movie",
                    "save an animation (.mp4 needs the movie extra; .gif works without)")
    parser.add_argument("--show", action="store_true",
                        help="open the plot and the animation in windows")


def parse(parser: argparse.ArgumentParser, argv: list[str] | None) -> argparse.Namespace:
    """Parse ``argv``; ``--show`` without a display is a usage error before any work."""
    args = parser.parse_args(argv)
    if getattr(args, "show", False):
        try:
            check_display()
        except FlexmbdError as error:
            parser.error(str(error))
    return args


def finish_outputs(args: argparse.Namespace, result, draw_plot, *, movie_title: str,
                   exaggeration: float = 1.0) -> None:
    """Save or show the plot (``draw_plot(filename, window)``) and the animation."""
    from flexmbd import plot

    if len(result.t) == 0:
        return
    if args.plot or args.show:
        draw_plot(args.plot, args.show)
        if args.plot:
            print(f"plot saved to {args.plot}")
    if args.movie or args.show:
        animation = plot.animate(result, args.movie, title=movie_title,
                                 exaggeration=exaggeration, window=args.show)
        if args.movie:
            print(f"movie saved to {args.movie}")
    if args.show:
        plot.show()
        del animation


def format_matrix(matrix, rows: list[str], columns: list[str], digits: int = 5) -> str:
    """A labelled matrix as text, for printing Jacobians and transfer functions."""
    width = max(digits + 7, *(len(c) for c in columns))
    lead = max((len(r) for r in rows), default=0)
    lines = [" " * (lead + 2) + "".join(f"{c:>{width}}" for c in columns)]
    for label, row in zip(rows, matrix, strict=True):
        lines.append(f"  {label:<{lead}}" + "".join(f"{v:>{width}.{digits}g}" for v in row))
    return "\n".join(lines)
