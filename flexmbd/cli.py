"""The ``flexmbd`` command line.

Every error a user can cause ends as one line on stderr and a non-zero exit
code, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from . import __version__
from .errors import ArgumentError, FlexmbdError

EXIT_ERROR = 1
EXIT_USAGE = 2


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="flexmbd",
        description="Planar flexible multibody dynamics with the finite-element approach.",
    )
    parser.add_argument("--version", action="version",
                        version=f"flexmbd {__version__} (core: {_core_build()})")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    example = commands.add_parser(
        "example", help="run one of the course exercises (flexmbd example --list)",
        description="Run an exercise; options after NAME go to the example "
                    "(flexmbd example NAME --help).",
        add_help=False,
    )
    example.add_argument("name", nargs="?", help="example name")
    example.add_argument("--list", action="store_true", help="list the examples")
    example.add_argument("-h", "--help", action="store_true", help="show help")
    run = commands.add_parser(
        "run", help="run a SPACAR input file (flexmbd run FILE.dat --out results.csv)",
        description="Run a planar SPACAR input file: kinematics, forward or inverse dynamics "
                    "over the file's TIMESTEP grid.")
    from .run_file import add_arguments

    add_arguments(run)
    from .linear_cli import add_commands

    add_commands(commands)
    from .course_cli import add_commands as add_course_commands

    add_course_commands(commands)
    from .studies.cli import add_command as add_sweep_command

    add_sweep_command(commands)
    return parser


def _core_build() -> str:
    """What the compiled core was built with, or why it cannot be loaded."""
    from .engine import CORE_BUILD

    return CORE_BUILD


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).replace("\n  - ", "; ").split())


def _run_example(args: argparse.Namespace, rest: list[str]) -> int:
    from .examples import EXAMPLES

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


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``flexmbd`` command; returns the exit code."""
    parser = _parser()
    args, rest = parser.parse_known_args(argv)
    try:
        if args.command == "example":
            return _run_example(args, rest)
        if args.command == "run":
            if rest:
                parser.error(f"unrecognized arguments: {' '.join(rest)}")
            from .run_file import run

            return run(args)
        if rest:
            parser.error(f"unrecognized arguments: {' '.join(rest)}")
        if args.command == "sweep":
            from .studies.cli import run as run_sweep

            return run_sweep(args)
        if args.command == "exercise":
            from .course_cli import run as run_course

            return run_course(args)
        if args.command in ("static", "modes", "buckling", "statespace"):
            from .linear_cli import run as run_linear

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
