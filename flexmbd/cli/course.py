"""``flexmbd exercise list|start|check|solution``: the course's exercises, part by part."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..errors import ArgumentError

_NAME_HELP = "the exercise, by name (sliding-bar, ...) or number (1-4)"


def add_commands(commands) -> None:
    """The ``exercise`` command and its actions."""
    parser = commands.add_parser(
        "exercise", help="the course's exercises, part by part (flexmbd exercise list)",
        description="The course's exercises: list them, start one from its template, check "
                    "your file part by part, or (lecturers) write the completed file.")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    listing = actions.add_parser("list", help="the exercises and their parts",
                                 description="The exercises and their lettered parts: the "
                                             "function a student writes for each part, its "
                                             "arguments and what it returns.")
    listing.add_argument("name", nargs="?", help="one exercise, by name or number")
    for action, text in (("start", "write the template to complete"),
                         ("solution", "write the completed file (for lecturers)")):
        sub = actions.add_parser(action, help=text, description=text[0].upper() + text[1:]
                                 + ": a Python script, or a Jupyter notebook with --notebook.")
        sub.add_argument("name", help=_NAME_HELP)
        sub.add_argument("directory", nargs="?", default=".",
                         help="where to write it (default: the current directory)")
        sub.add_argument("--notebook", action="store_true", help="write a .ipynb notebook")
        sub.add_argument("--force", action="store_true", help="overwrite an existing file")
        if action == "solution":
            sub.add_argument("--from", dest="solutions", metavar="DIR",
                             help="the solutions (default: FLEXMBD_SOLUTIONS, or the source "
                                  "repository's lecturer/solutions); they are not in the "
                                  "installed package")
    check = actions.add_parser(
        "check", help="check a completed file part by part",
        description="Run FILE (.py or .ipynb) in a separate process, in a scratch folder, "
                    "with a time limit per part; call each part at the exercise's "
                    "configuration and at random ones, and compare with flexmbd's answers. "
                    "Exit status 0 when every part passes, 1 otherwise (--exit-zero: 0 "
                    "whenever the check itself succeeded).")
    check.add_argument("name", help=_NAME_HELP)
    check.add_argument("file", help="the student's file")
    check.add_argument("--json", metavar="REPORT.json",
                       help="also write the report as a Gradescope autograder's results "
                            "(the file is then checked as --graded)")
    check.add_argument("--graded", action="store_true",
                       help="check the file as a grade: in an operating-system sandbox of "
                            "its own (bubblewrap), with a random seed")
    check.add_argument("--exit-zero", action="store_true",
                       help="exit 0 whatever the score (for autograder scripts)")
    grade = actions.add_parser(
        "grade", help="grade every submission in a folder (for lecturers)",
        description="Check every .py or .ipynb in FOLDER (or the one in each subfolder) in "
                    "graded mode, in parallel, each in an operating-system sandbox of its "
                    "own (bubblewrap); write one row per student with the points and the "
                    "reason of each part as each submission finishes (--out), a report per "
                    "student (--reports), and print the score distribution and the parts "
                    "most often failed. A rerun with the same --out grades only what is not "
                    "in the table yet, with the same seed.")
    grade.add_argument("name", help=_NAME_HELP)
    grade.add_argument("folder", help="the folder of submissions")
    grade.add_argument("--out", default="grades.csv", metavar="GRADES.csv",
                       help="the class table (default grades.csv)")
    grade.add_argument("--reports", metavar="DIR",
                       help="the reports, text and Gradescope JSON per student (default: "
                            "GRADES_reports beside the table)")
    grade.add_argument("--jobs", type=int, help="submissions checked at a time (default: "
                                                "the CPUs)")
    grade.add_argument("--roster", metavar="STUDENTS.txt",
                       help="the class: one student per line (or a CSV with a 'student' "
                            "column); those who submitted nothing get a row and are listed")
    recipe = actions.add_parser(
        "recipe", help="files for grading elsewhere: a Gradescope autograder, a container",
        description="Write the files of a recipe into DIRECTORY: 'gradescope', the setup.sh "
                    "and run_autograder of a Gradescope autograder that checks each "
                    "submission in flexmbd's sandbox (give --exercise); 'container', the "
                    "Dockerfile and sandbox/ folder of an image that runs one graded process, "
                    "for grade --sandbox-command where bubblewrap is not allowed.")
    recipe.add_argument("kind", choices=("gradescope", "container"))
    recipe.add_argument("directory", nargs="?", default=".",
                        help="where to write the files (default: the current directory)")
    recipe.add_argument("--exercise", metavar="NAME", help=_NAME_HELP + " (gradescope)")
    recipe.add_argument("--points", metavar="a=2,b=1",
                        help="points per part (gradescope; default 1 each)")
    recipe.add_argument("--force", action="store_true", help="overwrite existing files")
    for sub in (check, grade):
        sub.add_argument("--timeout", type=float, default=10.0,
                         help="time limit of each part, and of loading the file [s] "
                              "(default 10)")
        sub.add_argument("--seed", type=int,
                         help="seed of the random configurations (default: a new random "
                              "one for a grade, recorded in the table and the report; 2026 "
                              "for a self-check); give it to reproduce a grade")
        sub.add_argument("--points", metavar="a=2,b=1",
                         help="points per part (default 1 each)")
        sub.add_argument("--memory", type=float, default=2048.0, metavar="MB",
                         help="memory a graded run may use [MB] (default 2048)")
        sub.add_argument("--sandbox-command", metavar="CMD",
                         help="start each graded run with this command instead of "
                              "bubblewrap, e.g. a container per run (see the course guide)")
        sub.add_argument("--unsafe-in-process", action="store_true",
                         help="where no sandbox can be made: confine graded files only by "
                              "an audit hook inside their own Python, which a hostile file "
                              "gets around (it says what that leaves open)")


def run(args: argparse.Namespace) -> int:
    """Run one ``exercise`` action; returns the exit code."""
    from ..course import exercise

    if args.action == "list":
        return _list(args)
    if args.action == "recipe":
        return _recipe(args)
    chosen = exercise(args.name)
    if args.action == "check":
        return _check(chosen, args)
    if args.action == "grade":
        return _grade(chosen, args)
    return _write(chosen, args)


def _list(args) -> int:
    from ..course import EXERCISES, exercise

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


def _recipe(args) -> int:
    """``recipe``: the files of a Gradescope autograder or of a container image."""
    from ..course import exercise, recipes
    from ..course.grading import parse_points

    if args.kind == "gradescope":
        if not args.exercise:
            raise ArgumentError("--exercise", "a Gradescope autograder checks one exercise: "
                                              "give --exercise NAME")
        chosen = exercise(args.exercise)
        options = f"--points {args.points}" if args.points else ""
        parse_points(args.points, chosen)
        written = recipes.gradescope(chosen, args.directory, options, force=args.force)
        print("\n".join(f"wrote {path}" for path in written))
        print("zip setup.sh and run_autograder (and a flexmbd wheel if flexmbd is not on "
              "the package index) and upload the zip as the autograder")
        return 0
    written = recipes.container(args.directory, force=args.force)
    print("\n".join(f"wrote {path}" for path in written))
    print(f"build the image with `docker build -t flexmbd-sandbox {args.directory}`, then "
          f"grade with\n  flexmbd exercise grade NAME FOLDER --sandbox-command "
          f"\"{recipes.CONTAINER_COMMAND}\"")
    return 0


def _write(chosen, args) -> int:
    """``start`` (the template) or ``solution`` (the completed file) into a directory."""
    from ..course.templates import notebook, solution_source, template_source

    directory = Path(args.directory)
    if directory.exists() and not directory.is_dir():
        raise ArgumentError("directory", f"{directory} is a file, not a directory")
    suffix = "_solution" if args.action == "solution" else ""
    target = directory / f"{chosen.module}{suffix}{'.ipynb' if args.notebook else '.py'}"
    if target.exists() and not args.force:
        raise ArgumentError("directory", f"{target} exists; give --force to overwrite it")
    source = (solution_source(chosen, args.solutions) if args.action == "solution"
              else template_source(chosen))
    directory.mkdir(parents=True, exist_ok=True)
    target.write_text(notebook(source) if args.notebook else source, encoding="utf-8")
    print(f"wrote {target}")
    if args.action == "start":
        parts = ", ".join(f"{chosen.number}{p.letter} {p.function}" for p in chosen.parts)
        run = f"jupyter lab {target}" if args.notebook else f"python {target}"
        print(f"complete the parts {parts};\nrun it with `{run}` and check it with "
              f"`flexmbd exercise check {chosen.name} {target}`")
    return 0


def _isolation(args):
    """The isolation of a graded run from the options; says once what the unsafe one
    leaves open."""
    from ..course.inprocess import OPEN_HOLES
    from ..course.launch import ContainerCommand
    from ..course.sandbox import Limits

    if args.unsafe_in_process and args.sandbox_command:
        raise ArgumentError("--unsafe-in-process", "give it or --sandbox-command, not both")
    if not args.memory > 0:
        raise ArgumentError("--memory", f"must be a positive number of MB, got {args.memory:g}")
    limits = Limits(memory=int(args.memory * 2**20))
    if args.sandbox_command:
        return ContainerCommand(args.sandbox_command, limits), limits
    if args.unsafe_in_process:
        print(f"flexmbd: warning: {OPEN_HOLES}", file=sys.stderr)
        return "in-process", limits
    return "sandbox", limits


def _check(chosen, args) -> int:
    from ..course.check import check
    from ..course.grading import parse_points

    _check_timeout(args.timeout)
    points = parse_points(args.points, chosen)
    if args.json:
        report_path = Path(args.json)
        if report_path.suffix != ".json" or not report_path.parent.resolve().is_dir():
            raise ArgumentError("--json", f"cannot write {args.json!r}: give a .json file in "
                                          f"an existing directory")
    # a report for an autograder is a grade: the file runs in the sandbox
    graded = args.graded or bool(args.json) or args.unsafe_in_process or \
        bool(args.sandbox_command)
    isolation, limits = _isolation(args) if graded else ("none", None)
    report = check(chosen, args.file, timeout=args.timeout, seed=args.seed, graded=graded,
                   points=points, isolation=isolation, limits=limits)
    print(report.text())
    if graded:
        print(f"seed {report.seed}, {report.isolation}", file=sys.stderr)
    if args.json:  # written by the checker, after the student's processes have ended
        from ..course.gradebook import write_atomically

        write_atomically(Path(args.json), json.dumps(report.gradescope(), indent=1) + "\n")
        print(f"report written to {args.json}", file=sys.stderr)
    return 0 if args.exit_zero else report.exit_status


def _check_timeout(timeout: float) -> None:
    if not 0 < timeout < float("inf"):
        raise ArgumentError("--timeout", f"must be a positive number of seconds, got "
                                         f"{timeout:g}")


def _grade(chosen, args) -> int:
    """``grade``: the class table and the reports, written as each submission finishes,
    and the summary; 0 when every submission was graded."""
    from ..course.grading import grade, parse_points, read_roster, submissions
    from ..course.untrusted import one_line

    _check_timeout(args.timeout)
    points = parse_points(args.points, chosen)
    out = Path(args.out)
    if out.suffix != ".csv" or not out.parent.resolve().is_dir():
        raise ArgumentError("--out", f"cannot write {args.out!r}: give a .csv file in an "
                                     f"existing directory")
    reports = Path(args.reports) if args.reports else out.with_name(out.stem + "_reports")
    roster = read_roster(args.roster) if args.roster else None
    isolation, limits = _isolation(args)
    count = len(submissions(args.folder))
    print(f"grading {count} submissions of exercise {chosen.number} ({chosen.name})",
          flush=True)
    done = 0

    def progress(student, report):
        nonlocal done
        done += 1
        name = one_line(student, 80)
        if report is None:
            print(f"  [{done}/{count}] {name}: kept from {out}", flush=True)
            return
        print(f"  [{done}/{count}] {name}: {report.score:g}/{report.max_score:g}"
              + (f" ({report.problem})" if report.problem else ""), flush=True)

    grades = grade(chosen, args.folder, points=points, timeout=args.timeout, jobs=args.jobs,
                   seed=args.seed, isolation=isolation, limits=limits, out=out,
                   reports=reports, roster=roster, progress=progress)
    print(grades.summary())
    print(f"table written to {out}, reports to {reports}/")
    return 0
