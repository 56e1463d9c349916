"""The class table and the reports of a grading run, written as each submission finishes.

A :class:`Grade` is one row: per part the points and the reason (passed, wrong, error,
time, memory, killed, not defined), the score, the problem with the file, the seed, the
flexmbd version, the time and the file's SHA-256. A :class:`Gradebook` keeps the rows of
a table on disk: it reads the rows a run interrupted earlier left, so that a rerun grades
only the rest, and after every submission it writes the whole table and that student's
reports anew.

Every file is written to a new temporary file in its folder (created, never opened
through an existing name) and then renamed over the old one: a link planted where a
report goes is replaced, never followed, and a table is never half written.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import ArgumentError
from .check import PASSED, Report
from .parts import Exercise
from .untrusted import one_line

#: a student on the roster who submitted nothing
NOT_SUBMITTED = "not submitted"


def flexmbd_version() -> str:
    """The version of flexmbd that grades."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("flexmbd")
    except PackageNotFoundError:   # a checkout that is not installed
        from .. import __version__

        return __version__


@dataclass
class Grade:
    """One student's row: ``points`` and ``reasons`` per part letter."""

    student: str
    file: str
    sha256: str
    points: dict[str, float]
    reasons: dict[str, str]
    score: float
    max_score: float
    problem: str = ""
    seed: str = ""
    version: str = ""
    graded_at: str = ""
    extra: dict = field(default_factory=dict)

    @classmethod
    def of(cls, student: str, report: Report, when: str) -> Grade:
        """The row of a report."""
        return cls(student, report.file, report.sha256,
                   {p.letter: report.worth(p.letter) if p.status == PASSED else 0.0
                    for p in report.parts},
                   {p.letter: p.reason for p in report.parts}, report.score,
                   report.max_score, report.problem or "", str(report.seed),
                   flexmbd_version(), when)


def columns(exercise: Exercise) -> list[str]:
    """The table's columns."""
    letters = [f"{exercise.number}{p.letter}" for p in exercise.parts]
    return ["student", "file", "sha256", *letters, "score", "max_score",
            *(f"{k} reason" for k in letters), "problem", "seed", "flexmbd_version",
            "graded_at"]


def _cell(value: float) -> str:
    return f"{value:g}"


def write_atomically(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a new file renamed over it (see the module)."""
    fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


def _text(value: str, limit: int) -> str:
    """Student text for a cell: one line, and never a spreadsheet formula (a cell that
    starts with ``=``, ``+``, ``-`` or ``@`` gets a ``'`` in front)."""
    text = one_line(value, limit)
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


def table(exercise: Exercise, grades) -> str:
    """The CSV text of ``grades`` (sorted by student)."""
    letters = [p.letter for p in exercise.parts]
    text = io.StringIO()
    writer = csv.writer(text)
    writer.writerow(columns(exercise))
    for grade in sorted(grades, key=lambda g: g.student):
        writer.writerow([_text(grade.student, 200), _text(grade.file, 500), grade.sha256,
                         *(_cell(grade.points.get(k, 0.0)) for k in letters),
                         _cell(grade.score), _cell(grade.max_score),
                         *(grade.reasons.get(k, "") for k in letters),
                         _text(grade.problem, 500), grade.seed, grade.version,
                         grade.graded_at])
    return text.getvalue()


class Gradebook:
    """The table ``out`` and the reports folder ``reports`` of a grading run.

    Raises:
        ArgumentError: ``out`` holds a table of another exercise (other columns), or rows
            of more than one seed.
    """

    def __init__(self, exercise: Exercise, out: str | os.PathLike,
                 reports: str | os.PathLike | None) -> None:
        self.exercise = exercise
        self.out = Path(out)
        self.reports = Path(reports) if reports is not None else None
        self.grades: dict[str, Grade] = {}
        if self.out.is_file():
            self._read()

    def _read(self) -> None:
        with self.out.open(newline="", encoding="utf-8") as handle:
            reader = csv.DictReader(handle)
            if reader.fieldnames != columns(self.exercise):
                raise ArgumentError("--out", f"{self.out} holds a table with other columns "
                                             f"(another exercise?): give another --out")
            letters = [p.letter for p in self.exercise.parts]
            n = self.exercise.number
            for row in reader:
                try:
                    grade = Grade(row["student"], row["file"], row["sha256"],
                                  {k: float(row[f"{n}{k}"]) for k in letters},
                                  {k: row[f"{n}{k} reason"] for k in letters},
                                  float(row["score"]), float(row["max_score"]),
                                  row["problem"], row["seed"], row["flexmbd_version"],
                                  row["graded_at"])
                except (TypeError, ValueError) as error:
                    raise ArgumentError("--out", f"{self.out}: a row that cannot be read "
                                                 f"({error}): give another --out") from None
                self.grades[grade.student] = grade
        seeds = {g.seed for g in self.grades.values() if g.sha256}
        if len(seeds) > 1:
            raise ArgumentError("--out", f"{self.out} holds rows graded with different seeds "
                                         f"({', '.join(sorted(seeds))}): give another --out")

    @property
    def seed(self) -> int | None:
        """The seed of the rows already graded, if any."""
        seeds = {g.seed for g in self.grades.values() if g.sha256}
        return int(seeds.pop()) if seeds else None

    def kept(self, student: str, sha256: str) -> Grade | None:
        """``student``'s row, if their file with this hash is graded already."""
        grade = self.grades.get(_text(student, 200))
        return grade if grade is not None and grade.sha256 == sha256 else None

    def record(self, grade: Grade, report: Report | None = None) -> None:
        """Add a row (and its student's reports) and write the table anew."""
        self.grades[_text(grade.student, 200)] = grade
        if report is not None and self.reports is not None:
            self.reports.mkdir(parents=True, exist_ok=True)
            write_atomically(self.reports / f"{grade.student}.txt", report.text() + "\n")
            write_atomically(self.reports / f"{grade.student}.json",
                             json.dumps(report.gradescope(), indent=1) + "\n")
        write_atomically(self.out, table(self.exercise, self.grades.values()))
