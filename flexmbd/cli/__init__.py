"""The ``flexmbd`` command line.

Every error a user can cause ends as one line on stderr and a non-zero exit
code, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from pathlib import Path

from .. import __version__
from ..errors import ArgumentError, FlexmbdError

EXIT_ERROR = 1
EXIT_USAGE = 2


def _parser(argv: list[str]) -> argparse.ArgumentParser:
    """The parser of the command in ``argv``: only its own group's module is imported (the
    others would add 15 ms of imports to every run); all of them for the overview, a help
    request or an unknown command, whose message lists them."""
    parser = argparse.ArgumentParser(
        prog="flexmbd",
        description="Flexible multibody dynamics with the finite-element approach, planar and "
                    "spatial.",
    )
    parser.add_argument("--version", action=_Version, help="show the version and exit")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    example = commands.add_parser(
        "example", help="run one of the course exercises (flexmbd example --list)",
        description="Run an exercise; options after NAME go to the example "
                    "(flexmbd example NAME --help).",
        add_help=False,
    )
    example.add_argument("name", nargs="?", help="example name")
    example.add_argument("--list", action="store_true", help="list the examples")
    example.add_argument("--file", nargs="?", const="", metavar="FILE",
                         help="write the installed example input file FILE (e.g. "
                              "slider_crank_flex.dat) into the current folder; without "
                              "FILE, list them")
    example.add_argument("-h", "--help", action="store_true", help="show help")
    command = next((word for word in argv if not word.startswith("-")), None)
    groups = [_GROUPS[command]] if command in _GROUPS else list(dict.fromkeys(
        _GROUPS.values()))
    for add_group in groups:
        if add_group is not None:
            add_group(commands)
    return parser


def _add_run(commands) -> None:
    from .run import add_arguments

    run = commands.add_parser(
        "run", help="run a SPACAR input file (flexmbd run FILE.dat --out results.csv)",
        description="Run a SPACAR input file: kinematics, forward or inverse dynamics over "
                    "the file's TIMESTEP grid.")
    add_arguments(run)


def _add_linear(commands) -> None:
    from .linear import add_commands

    add_commands(commands)


def _add_course(commands) -> None:
    from .course import add_commands

    add_commands(commands)


def _add_spacar(commands) -> None:
    from .spacar import add_commands

    add_commands(commands)


def _add_sweep(commands) -> None:
    from .sweep import add_command

    add_command(commands)


#: commands whose work is the compiled core's and BLAS's only on small matrices
SMALL_BLAS = ("example", "run")


def _one_blas_thread(argv: list[str]) -> None:
    """Start OpenBLAS with one thread for the commands of :data:`SMALL_BLAS`, unless the
    user chose (``OPENBLAS_NUM_THREADS``): on matrices of tens of rows its threads cost
    more than they give, and starting them and stopping them costs every process 7 to
    10 ms. Only possible before NumPy is loaded; the linearized analyses and studies keep
    OpenBLAS's default."""
    command = next((word for word in argv if not word.startswith("-")), None)
    if command in SMALL_BLAS and "numpy" not in sys.modules:
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


#: the commands besides ``example`` and what adds each one's parser (a group adds several)
_GROUPS = {"example": None, "run": _add_run, "static": _add_linear, "modes": _add_linear,
           "buckling": _add_linear, "statespace": _add_linear, "exercise": _add_course,
           "sweep": _add_sweep, "spacar": _add_spacar, "compare": _add_spacar,
           "stressbeam": _add_spacar}


class _Version(argparse.Action):
    """``--version``: what the compiled core was built with is looked up only when asked
    (it loads the engine)."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"flexmbd {__version__} (core: {_core_build()})")
        parser.exit()


def _core_build() -> str:
    """What the compiled core was built with, or why it cannot be loaded."""
    from ..engine import CORE_BUILD

    return CORE_BUILD


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).replace("\n  - ", "; ").split())


def _run_example(args: argparse.Namespace, rest: list[str]) -> int:
    from ..examples import EXAMPLES

    if args.file is not None:
        return _write_example_file(args.file)
    if args.list or args.name is None:
        if args.help:
            print("usage: flexmbd example NAME [options]   (flexmbd example NAME --help)\n")
        width = max(len(n) for n in EXAMPLES)
        for name, (_, _, text) in EXAMPLES.items():
            print(f"  {name:<{width}}  {text}")
        return 0
    if args.name not in EXAMPLES:
        print(f"flexmbd: error: unknown example {args.name!r}; choose from "
              f"{', '.join(EXAMPLES)}", file=sys.stderr)
        return EXIT_USAGE
    module_name, preset, _ = EXAMPLES[args.name]
    module = importlib.import_module(f"flexmbd.examples.{module_name}")
    argv = preset + rest + (["--help"] if args.help else [])
    try:
        return int(module.main(argv, prog=f"flexmbd example {args.name}") or 0)
    except SystemExit as done:  # argparse of the example: --help or a usage error
        return done.code if isinstance(done.code, int) else EXIT_USAGE


def _write_example_file(name: str) -> int:
    """``flexmbd example --file NAME``: copy an installed example input file into the
    current folder (never over an existing file); without NAME list them."""
    import difflib
    from importlib.resources import files

    available = sorted(entry.name for entry in files("flexmbd.examples").iterdir()
                       if entry.name.endswith(".dat"))
    if not name:
        print("example input files (flexmbd example --file NAME writes one here):")
        for found in available:
            print(f"  {found}")
        return 0
    if name not in available:
        close = difflib.get_close_matches(name, available, n=3, cutoff=0.5)
        meant = f"; did you mean {' or '.join(close)}?" if close else ""
        print(f"flexmbd: error: no example file {name!r}{meant} (the files: "
              f"{', '.join(available)})", file=sys.stderr)
        return EXIT_USAGE
    target = Path.cwd() / name
    if target.exists():
        print(f"flexmbd: error: {target} exists; remove or rename it first", file=sys.stderr)
        return EXIT_ERROR
    target.write_bytes((files("flexmbd.examples") / name).read_bytes())
    print(f"wrote {target}; run it with: flexmbd run {name}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``flexmbd`` command; returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    _one_blas_thread(argv)
    parser = _parser(argv)
    args, rest = parser.parse_known_args(argv)
    try:
        if args.command == "example":
            return _run_example(args, rest)
        if args.command == "run":
            if rest:
                parser.error(f"unrecognized arguments: {' '.join(rest)}")
            from .run import run

            return run(args)
        if rest:
            parser.error(f"unrecognized arguments: {' '.join(rest)}")
        if args.command == "sweep":
            from .sweep import run as run_sweep

            return run_sweep(args)
        if args.command == "exercise":
            from .course import run as run_course

            return run_course(args)
        if args.command in ("spacar", "compare", "stressbeam"):
            from .spacar import run_compare, run_spacar, run_stressbeam

            return {"spacar": run_spacar, "compare": run_compare,
                    "stressbeam": run_stressbeam}[args.command](args)
        if args.command in ("static", "modes", "buckling", "statespace"):
            from .linear import run as run_linear

            return run_linear(args)
        parser.print_help()
        return EXIT_USAGE
    except ArgumentError as error:  # an option that cannot work: a usage error
        print(f"flexmbd: error: {_one_line(error)}", file=sys.stderr)
        return EXIT_USAGE
    except FlexmbdError as error:
        print(f"flexmbd: error: {_one_line(error)}", file=sys.stderr)
        return EXIT_ERROR
    except BrokenPipeError:
        # the reader of the output (head, less) has gone: stop quietly, as the shell tools do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_ERROR
    except OSError as error:
        print(f"flexmbd: error: {_one_line(error)}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt:
        print("flexmbd: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
