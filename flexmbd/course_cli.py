"""``flexmbd exercise list [NAME]``: the course's exercises and their lettered parts."""

from __future__ import annotations

import argparse


def add_commands(commands) -> None:
    """The ``exercise`` command and its actions."""
    parser = commands.add_parser(
        "exercise", help="the course's exercises, part by part (flexmbd exercise list)",
        description="The course's exercises and their lettered parts.")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    listing = actions.add_parser("list", help="the exercises and their parts",
                                 description="The exercises and their lettered parts: the "
                                             "function a student writes for each part, its "
                                             "arguments and what it returns.")
    listing.add_argument("name", nargs="?", help="one exercise, by name or number")


def run(args: argparse.Namespace) -> int:
    """Run one ``exercise`` action; returns the exit code."""
    from .course import EXERCISES, exercise

    chosen = [exercise(args.name)] if args.name else list(EXERCISES.values())
    for k, item in enumerate(chosen):
        if k:
            print()
        print(f"{item.number}. {item.title}   (name: {item.name})")
        print(f"   {item.model}")
        width = max(len(f"{p.function}({p.arguments})") for p in item.parts)
        for part in item.parts:
            call = f"{part.function}({part.arguments})"
            print(f"   {item.number}{part.letter}  {call:<{width}}  -> {part.returns}")
    return 0
