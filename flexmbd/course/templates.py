"""Exercise files: the solution, the template made from it, and notebooks.

A solution file marks the student's formulas with ``# BEGIN SOLUTION`` / ``# END
SOLUTION`` inside the part's function, as nbgrader and otter-grader do. The template
replaces each marked block with a call of :func:`~flexmbd.course.student.not_done`
carrying the part's letter and hint, so it runs as written and says which part is
missing. Files are in the "percent" format (``# %%`` starts a code cell, ``# %%
[markdown]`` a text cell), which Jupyter, VS Code and jupytext read; :func:`notebook`
turns one into an ``.ipynb``.

The solutions are not in the installed package, which students install too: they are
in the source repository's ``lecturer/solutions/``. The package ships the templates made
from them (``flexmbd/course/handouts/``); ``python -m flexmbd.course.templates`` makes
them again after a solution changed.
"""

from __future__ import annotations

import json
import os
import re
import sys
from importlib import resources
from pathlib import Path

from ..errors import ArgumentError, InputFileError
from .parts import Exercise
from .runner import notebook_code

__all__ = ["cells", "make_template", "notebook", "notebook_code", "solution_source",
           "solutions_directory", "template_source", "write_handouts"]

_BEGIN, _END = "# BEGIN SOLUTION", "# END SOLUTION"
_DEF = re.compile(r"^def (\w+)\(")


#: the solutions in the source repository, beside the package
REPOSITORY_SOLUTIONS = Path(__file__).resolve().parents[2] / "lecturer" / "solutions"


def solutions_directory(given: str | os.PathLike | None = None) -> Path:
    """Where the solutions are: ``given``, else ``FLEXMBD_SOLUTIONS``, else the source
    repository's ``lecturer/solutions`` when flexmbd runs from a clone.

    Raises:
        ArgumentError: none of them holds the solutions (an installed package has none).
    """
    for candidate in (given, os.environ.get("FLEXMBD_SOLUTIONS"), REPOSITORY_SOLUTIONS):
        if candidate and (Path(candidate) / "sliding_bar.py").is_file():
            return Path(candidate)
    if given:
        raise ArgumentError("--from", f"{given} holds no solutions (sliding_bar.py, ...)")
    raise ArgumentError("solution", "the solutions are not in the installed package (students "
                                    "install it too); lecturers find them in flexmbd's source "
                                    "repository, lecturer/solutions/: clone it and give "
                                    "--from CLONE/lecturer/solutions (or set "
                                    "FLEXMBD_SOLUTIONS)")


def solution_source(exercise: Exercise, directory: str | os.PathLike | None = None) -> str:
    """The completed file of ``exercise`` (text of a Python script), from
    :func:`solutions_directory`."""
    return (solutions_directory(directory) / f"{exercise.module}.py").read_text()


def template_source(exercise: Exercise) -> str:
    """The template of ``exercise``, as the package ships it."""
    return (resources.files("flexmbd.course") / "handouts" / f"{exercise.module}.py").read_text()


def make_template(exercise: Exercise, solution: str) -> str:
    """The template of a solution's text: every marked block replaced by "not done yet"."""
    parts = {part.function: part for part in exercise.parts}
    lines, out, function, inside = solution.splitlines(), [], None, False
    for number, line in enumerate(lines, 1):
        match = _DEF.match(line)
        if match:
            function = match.group(1)
        stripped = line.strip()
        if stripped == _BEGIN:
            if function not in parts:
                raise InputFileError(f"{_BEGIN} outside the function of a part "
                                     f"({function})", f"{exercise.module}.py", number)
            part, inside = parts[function], True
            indent = line[:len(line) - len(line.lstrip())]
            out.append(f"{indent}# part {part.letter}: write {part.returns}")
            out.append(f"{indent}not_done({part.letter!r}, {part.hint!r})")
        elif stripped == _END:
            inside = False
        elif not inside:
            out.append(line)
    return "\n".join(out) + "\n"


def cells(source: str) -> list[tuple[str, str]]:
    """``(kind, text)`` of a percent-format script, kind ``"code"`` or ``"markdown"``."""
    found: list[tuple[str, list[str]]] = []
    for line in source.splitlines():
        if line.startswith("# %%"):
            found.append(("markdown" if "[markdown]" in line else "code", []))
            continue
        if not found:
            found.append(("code", []))
        kind, body = found[-1]
        body.append(line[2:] if kind == "markdown" and line.startswith("# ") else
                    "" if kind == "markdown" and line == "#" else line)
    return [(kind, "\n".join(body).strip("\n")) for kind, body in found
            if "\n".join(body).strip()]


def notebook(source: str) -> str:
    """The percent-format ``source`` as a Jupyter notebook (nbformat 4, JSON text)."""
    def cell(kind, text):
        lines = text.splitlines(keepends=True)
        common = {"cell_type": kind, "metadata": {}, "source": lines}
        return common if kind == "markdown" else {**common, "execution_count": None,
                                                   "outputs": []}

    return json.dumps({"cells": [cell(kind, text) for kind, text in cells(source)],
                       "metadata": {"kernelspec": {"display_name": "Python 3",
                                                   "language": "python", "name": "python3"},
                                    "language_info": {"name": "python"}},
                       "nbformat": 4, "nbformat_minor": 5}, indent=1) + "\n"


def write_handouts(directory: str | os.PathLike | None = None) -> list[Path]:
    """Make every template again from the solutions into ``flexmbd/course/handouts``."""
    from .catalogue import EXERCISES

    target = Path(__file__).resolve().parent / "handouts"
    target.mkdir(exist_ok=True)
    written = []
    for exercise in EXERCISES.values():
        path = target / f"{exercise.module}.py"
        path.write_text(make_template(exercise, solution_source(exercise, directory)))
        written.append(path)
    return written


if __name__ == "__main__":
    for written_path in write_handouts(sys.argv[1] if len(sys.argv) > 1 else None):
        print(f"wrote {written_path}")
