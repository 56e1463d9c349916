"""Shared plumbing of the examples: the check table and the output options."""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass


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


PLOT_TYPES = (".png", ".pdf", ".svg", ".jpg")
MOVIE_TYPES = (".gif", ".mp4")


def _file_of_type(types: tuple[str, ...]):
    """An argparse type that accepts file names ending in one of ``types``."""
    def check(name: str) -> str:
        if not name.lower().endswith(types):
            raise argparse.ArgumentTypeError(f"{name!r} must end in {', '.join(types)}")
        return name
    return check


def example_parser(doc: str, prog: str | None) -> argparse.ArgumentParser:
    """The parser of an example: its docstring's first paragraph as description."""
    return argparse.ArgumentParser(prog=prog, description=doc.split("\n\n")[0])


def add_output_options(parser: argparse.ArgumentParser) -> None:
    """``--plot``, ``--movie`` and ``--show``, with the file types checked before any work."""
    parser.add_argument("--plot", metavar="FILE.png", type=_file_of_type(PLOT_TYPES),
                        help="save a plot (.png, .pdf, .svg)")
    parser.add_argument("--movie", metavar="FILE.mp4", type=_file_of_type(MOVIE_TYPES),
                        help="save an animation (.mp4 needs the movie extra; .gif works without)")
    parser.add_argument("--show", action="store_true",
                        help="open the plot and the animation in windows")


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
