"""Grading a class: every submission of a folder, checked in graded mode, in parallel
(``flexmbd exercise grade``).

A submission is a ``.py`` or ``.ipynb`` file in the folder (the student is its name) or
the one such file in a subfolder (the student is the subfolder's name). Each gets a
report written by the grader itself, after its process group has ended, and a row of
the class table with the points of each part.
"""

from __future__ import annotations

import csv
import json
import math
import os
import statistics
import time
from collections import Counter
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

from ..errors import ArgumentError
from ..summary import dataclass_repr
from .check import PASSED, Report, check
from .parts import Exercise

SUFFIXES = (".py", ".ipynb")


@dataclass(frozen=True)
class Submission:
    """One student's file."""

    student: str
    path: Path


def submissions(folder: str | os.PathLike) -> list[Submission]:
    """The submissions of ``folder``, by student name.

    Raises:
        ArgumentError: no such folder, no submission in it, or a subfolder with more than
            one file that could be the submission.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ArgumentError("FOLDER", f"{folder} is not a directory")
    found = []
    for entry in sorted(folder.iterdir()):
        if entry.is_file() and entry.suffix in SUFFIXES and not entry.name.startswith("."):
            found.append(Submission(entry.stem, entry))
        elif entry.is_dir() and not entry.name.startswith("."):
            files = sorted(p for p in entry.iterdir() if p.is_file() and p.suffix in SUFFIXES)
            if len(files) > 1:
                names = ", ".join(p.name for p in files)
                raise ArgumentError("FOLDER", f"{entry} holds {len(files)} files that could be "
                                              f"the submission ({names}); leave one")
            if files:
                found.append(Submission(entry.name, files[0]))
    if not found:
        raise ArgumentError("FOLDER", f"{folder} holds no .py or .ipynb submission")
    counted = Counter(s.student for s in found)
    twice = [name for name, count in counted.items() if count > 1]
    if twice:
        raise ArgumentError("FOLDER", f"two submissions of {', '.join(twice)} (a file and a "
                                      f"folder of the same name)")
    return found


def parse_points(text: str | None, exercise: Exercise) -> dict[str, float]:
    """``"a=2,b=0.5"`` as points per part letter; parts not named keep 1.

    Raises:
        ArgumentError: a letter the exercise does not have, or points that are not a finite
            number >= 0.
    """
    points: dict[str, float] = {}
    letters = [p.letter for p in exercise.parts]
    for item in filter(None, (text or "").split(",")):
        letter, _, value = item.strip().partition("=")
        letter = letter.strip().removeprefix(str(exercise.number))
        if letter not in letters:
            raise ArgumentError("--points", f"exercise {exercise.number} has parts "
                                            f"{', '.join(letters)}, not {letter!r}")
        try:
            number = float(value)
        except ValueError:
            raise ArgumentError("--points", f"{item.strip()!r}: give PART=POINTS, e.g. "
                                            f"a=2") from None
        if not math.isfinite(number) or number < 0:
            raise ArgumentError("--points", f"{item.strip()!r}: points must be a finite "
                                            f"number >= 0")
        points[letter] = number
    return points


@dataclass
class ClassGrades:
    """The reports of a class, by student, and how long grading took [s]."""

    __repr__ = dataclass_repr

    exercise: Exercise
    reports: dict[str, Report]
    seconds: float

    def write_csv(self, path: str | os.PathLike) -> Path:
        """One row per student: the points of each part, the total and the maximum, and
        the problem with the file if any."""
        path = Path(path)
        letters = [p.letter for p in self.exercise.parts]
        with path.open("w", newline="") as handle:
            table = csv.writer(handle)
            table.writerow(["student", "file", *(f"{self.exercise.number}{k}" for k in letters),
                            "score", "max_score", "problem"])
            for student, report in sorted(self.reports.items()):
                status = {p.letter: p for p in report.parts}
                table.writerow([student, report.file,
                                *(f"{report.worth(k) if status[k].status == PASSED else 0:g}"
                                  for k in letters),
                                f"{report.score:g}", f"{report.max_score:g}",
                                report.problem or ""])
        return path

    def write_reports(self, folder: str | os.PathLike) -> Path:
        """Each student's report as text and as Gradescope JSON in ``folder``."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        for student, report in self.reports.items():
            (folder / f"{student}.txt").write_text(report.text() + "\n")
            (folder / f"{student}.json").write_text(json.dumps(report.gradescope(),
                                                               indent=1) + "\n")
        return folder

    def summary(self) -> str:
        """The score distribution and the parts most often failed."""
        scores = [r.score for r in self.reports.values()]
        top = next(iter(self.reports.values())).max_score
        lines = [f"graded {len(scores)} submissions of exercise {self.exercise.number} "
                 f"({self.exercise.name}) in {self.seconds:.1f} s",
                 f"score: mean {statistics.mean(scores):.2f}, median "
                 f"{statistics.median(scores):g} of {top:g}"]
        histogram = Counter(scores)
        width = max(histogram.values())
        for value in sorted(histogram, reverse=True):
            bar = "#" * max(1, round(30 * histogram[value] / width))
            lines.append(f"  {value:>5g}  {bar} {histogram[value]}")
        failed = Counter(p.letter for r in self.reports.values() for p in r.parts
                         if p.status != PASSED)
        if failed:
            lines.append("parts most often not passed:")
            for letter, count in failed.most_common(5):
                part = self.exercise.part(letter)
                lines.append(f"  {self.exercise.number}{letter} {part.function}: "
                             f"{count} of {len(scores)}")
        problems = sum(bool(r.problem) for r in self.reports.values())
        if problems:
            lines.append(f"{problems} file(s) did not load completely (see their reports)")
        return "\n".join(lines)


def grade(exercise: Exercise, folder: str | os.PathLike, *, points=None,
          timeout: float = 10.0, jobs: int | None = None, seed: int = 2026,
          progress: Callable[[str, Report], None] | None = None) -> ClassGrades:
    """Check every submission of ``folder`` in graded mode, ``jobs`` at a time (default:
    the CPUs); ``progress(student, report)`` after each."""
    found = submissions(folder)
    jobs = jobs or os.cpu_count() or 1
    if jobs < 1:
        raise ArgumentError("--jobs", f"must be at least 1, got {jobs}")
    begun = time.monotonic()
    reports: dict[str, Report] = {}
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        running = {pool.submit(check, exercise, s.path, timeout=timeout, seed=seed,
                               graded=True, points=points): s for s in found}
        for future in as_completed(running):
            student = running[future].student
            reports[student] = future.result()
            if progress is not None:
                progress(student, reports[student])
    return ClassGrades(exercise, reports, time.monotonic() - begun)
