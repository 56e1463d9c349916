"""Grading a class: every submission of a folder, checked in graded mode, in parallel
(``flexmbd exercise grade``).

A submission is a ``.py`` or ``.ipynb`` file in the folder (the student is its name) or
the one such file in a subfolder (the student is the subfolder's name). Each runs in an
operating-system sandbox of its own (:mod:`flexmbd.course.sandbox`) and is graded on its
own: whatever a file does, or whatever goes wrong with it, affects only its own row. A
row and the student's reports are written as each submission finishes
(:mod:`flexmbd.course.gradebook`), so an interrupted run keeps what it graded and a
rerun grades only the rest, with the same seed.
"""

from __future__ import annotations

import datetime
import hashlib
import math
import os
import secrets
import statistics
import threading
import time
from collections import Counter
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

from ..errors import ArgumentError
from ..summary import dataclass_repr
from .check import ERROR, FAILED, PASSED, PartReport, Report, check_content, read_submission
from .gradebook import NOT_SUBMITTED, Grade, Gradebook, flexmbd_version, table
from .launch import Cancelled, end_all, launcher, verify
from .parts import Exercise
from .sandbox import Limits
from .untrusted import one_line

SUFFIXES = (".py", ".ipynb")


@dataclass(frozen=True)
class Submission:
    """One student's file, or why the student's entry cannot be graded (``problem``)."""

    student: str
    path: Path
    problem: str | None = None


def _candidates(folder: Path) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.suffix in SUFFIXES
                  and not p.name.startswith(".") and (p.is_file() or p.is_symlink()))


def submissions(folder: str | os.PathLike) -> list[Submission]:
    """The submissions of ``folder``, by student name. An entry that cannot be graded (a
    link instead of a file, a subfolder with two candidate files, a file and a folder of
    the same student) is a submission with its ``problem``: it gets its row, with no
    points, and does not stop the others.

    Raises:
        ArgumentError: no such folder, or no submission in it.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ArgumentError("FOLDER", f"{folder} is not a directory")
    found = []
    for entry in sorted(folder.iterdir()):
        if entry.name.startswith("."):
            continue
        if entry.suffix in SUFFIXES and (entry.is_symlink() or entry.is_file()):
            problem = "the submission is a link, not a file of its own" \
                if entry.is_symlink() else None
            found.append(Submission(entry.stem, entry, problem))
        elif entry.is_dir():
            if entry.is_symlink():
                found.append(Submission(entry.name, entry, "the submission's folder is a "
                                                           "link, not a folder of its own"))
                continue
            files = _candidates(entry)
            if len(files) > 1:
                names = ", ".join(one_line(p.name, 80) for p in files)
                found.append(Submission(entry.name, entry, f"the folder holds {len(files)} "
                                                           f"files that could be the "
                                                           f"submission ({names})"))
            elif files:
                problem = "the submission is a link, not a file of its own" \
                    if files[0].is_symlink() else None
                found.append(Submission(entry.name, files[0], problem))
    if not found:
        raise ArgumentError("FOLDER", f"{folder} holds no .py or .ipynb submission")
    counted = Counter(s.student for s in found)
    twice = {name for name, count in counted.items() if count > 1}
    out = [s for s in found if s.student not in twice]
    for name in sorted(twice):
        out.append(Submission(name, folder / name, "two submissions (a file and a folder of "
                                                   "the same name)"))
    return sorted(out, key=lambda s: s.student)


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


def read_roster(path: str | os.PathLike) -> list[str]:
    """The students of a roster: one name per line (blank lines and ``#`` comments
    skipped), or a CSV table's ``student`` column.

    Raises:
        ArgumentError: the file cannot be read, or names no student.
    """
    try:
        lines = Path(path).read_text(encoding="utf-8-sig").splitlines()
    except OSError as error:
        raise ArgumentError("--roster", f"cannot read {path}: {error.strerror}") from None
    if lines and "," in lines[0] and "student" in [c.strip() for c in lines[0].split(",")]:
        import csv

        names = [row["student"].strip() for row in csv.DictReader(lines)
                 if (row.get("student") or "").strip()]
    else:
        names = [line.strip() for line in lines if line.strip()
                 and not line.lstrip().startswith("#")]
    if not names:
        raise ArgumentError("--roster", f"{path} names no student")
    return names


@dataclass
class ClassGrades:
    """The grades of a class by student (rows of this run and of an earlier one that was
    interrupted), the reports of the files graded in this run, and how long it took [s]."""

    __repr__ = dataclass_repr

    exercise: Exercise
    grades: dict[str, Grade]
    reports: dict[str, Report]
    seconds: float
    seed: int
    missing: list[str]

    def write_csv(self, path: str | os.PathLike) -> Path:
        """The class table: one row per student (see :mod:`flexmbd.course.gradebook`)."""
        from .gradebook import write_atomically

        path = Path(path)
        write_atomically(path, table(self.exercise, self.grades.values()))
        return path

    def summary(self) -> str:
        """The score distribution and the parts most often failed."""
        graded = [g for g in self.grades.values()
                  if set(g.reasons.values()) != {NOT_SUBMITTED}]
        scores = [g.score for g in graded]
        top = sum(1.0 for _ in self.exercise.parts) if not graded else graded[0].max_score
        lines = [f"graded {len(scores)} submissions of exercise {self.exercise.number} "
                 f"({self.exercise.name}) in {self.seconds:.1f} s, seed {self.seed}"]
        if scores:
            lines.append(f"score: mean {statistics.mean(scores):.2f}, median "
                         f"{statistics.median(scores):g} of {top:g}")
            histogram = Counter(scores)
            width = max(histogram.values())
            for value in sorted(histogram, reverse=True):
                bar = "#" * max(1, round(30 * histogram[value] / width))
                lines.append(f"  {value:>5g}  {bar} {histogram[value]}")
        failed = Counter(k for g in graded for k, r in g.reasons.items() if r != PASSED)
        if failed:
            lines.append("parts most often not passed:")
            for letter, count in failed.most_common(5):
                part = self.exercise.part(letter)
                lines.append(f"  {self.exercise.number}{letter} {part.function}: "
                             f"{count} of {len(scores)}")
        problems = sum(bool(g.problem) for g in graded)
        if problems:
            lines.append(f"{problems} file(s) did not load completely or could not be "
                         f"graded (see their reports)")
        same = Counter(g.sha256 for g in graded if g.sha256)
        for digest, count in same.items():
            if count > 1:
                names = sorted(one_line(g.student, 80) for g in graded if g.sha256 == digest)
                lines.append(f"identical files ({digest[:12]}): {', '.join(names)}")
        if self.missing:
            lines.append(f"no submission from {len(self.missing)} student(s) of the roster: "
                         f"{', '.join(one_line(m, 80) for m in self.missing)}")
        return "\n".join(lines)


def _now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def _unchecked(exercise: Exercise, file: str, problem: str, seed: int, sha256: str = "",
               reason: str = ERROR, points=None) -> Report:
    """The report of an entry that could not be checked: no part passed, and why."""
    parts = [PartReport(p.letter, p.function, FAILED, f"not graded: {problem}", reason=reason)
             for p in exercise.parts]
    return Report(exercise, file, parts, problem=problem, seed=seed, sha256=sha256,
                  points=dict(points or {}))


def grade(exercise: Exercise, folder: str | os.PathLike, *, points=None,
          timeout: float = 10.0, jobs: int | None = None, seed: int | None = None,
          isolation="sandbox", limits: Limits | None = None,
          out: str | os.PathLike | None = None, reports: str | os.PathLike | None = None,
          roster: list[str] | None = None,
          progress: Callable[[str, Report | None], None] | None = None) -> ClassGrades:
    """Check every submission of ``folder`` in graded mode, ``jobs`` at a time (default:
    the CPUs), each in a sandbox of its own.

    Args:
        seed: the seed of every submission's random configurations; default: the seed of
            the rows already in ``out``, else a new random one (recorded in the table).
        isolation: ``"sandbox"`` (the default), ``"in-process"`` (unsafe) or a launcher.
        out, reports: the class table and the reports folder, written as each submission
            finishes; rows already in ``out`` for the same file are kept, not graded
            again.
        roster: every student of the class: those without a submission get a row.
        progress: ``progress(student, report)`` after each submission (``report`` is
            ``None`` for a row kept from an earlier run).

    Raises:
        ArgumentError: a bad folder or option, or a ``seed`` other than the one the rows
            in ``out`` were graded with.
        SandboxError: the sandbox cannot be made here.
    """
    found = submissions(folder)
    jobs = jobs or os.cpu_count() or 1
    if jobs < 1:
        raise ArgumentError("--jobs", f"must be at least 1, got {jobs}")
    book = Gradebook(exercise, out, reports) if out is not None else None
    if book is not None and book.seed is not None:
        if seed is not None and seed != book.seed:
            raise ArgumentError("--seed", f"{out} was graded with seed {book.seed}: give "
                                          f"--seed {book.seed} to go on with it, or another "
                                          f"--out")
        seed = book.seed
    seed = secrets.randbits(32) if seed is None else seed
    hide = [Path(folder).resolve(), *([Path(out).resolve().parent] if out else []),
            *([Path(reports).resolve()] if reports else [])]
    start = launcher(isolation, limits, hide)
    if isolation != "none":
        verify(start)
    begun = time.monotonic()
    graded: dict[str, Report] = {}

    def one(submission: Submission) -> tuple[Grade | None, Report | None]:
        """The row of one submission, whatever happens to it."""
        file = str(submission.path)
        if submission.problem:
            return None, _unchecked(exercise, file, submission.problem, seed, points=points)
        try:
            content = read_submission(submission.path, follow_links=False)
        except ArgumentError as error:
            return None, _unchecked(exercise, file, str(error).removeprefix("file: "), seed,
                                    points=points)
        sha256 = hashlib.sha256(content).hexdigest()
        kept = book.kept(submission.student, sha256) if book is not None else None
        if kept is not None:
            return kept, None
        try:
            return None, check_content(exercise, file, content, start, timeout=timeout,
                                       seed=seed, points=points, cancel=cancel)
        except Cancelled:
            return None, None
        except Exception as error:  # the grader's own failure costs this row only
            return None, _unchecked(exercise, file, f"the grader could not check this file "
                                                    f"({type(error).__name__}: "
                                                    f"{one_line(error)})", seed, sha256,
                                    points=points)

    rows: dict[str, Grade] = {}
    cancel = threading.Event()
    pool = ThreadPoolExecutor(max_workers=jobs)
    try:
        running = {pool.submit(one, s): s for s in found}
        for future in as_completed(running):
            student = running[future].student
            kept, report = future.result()
            if report is not None:
                graded[student] = report
                rows[student] = Grade.of(student, report, _now())
                if book is not None:
                    book.record(rows[student], report)
            elif kept is not None:
                rows[student] = kept
            if progress is not None:
                progress(student, report)
    except BaseException:   # interrupted: the rows written stay, the runs end now
        pool.shutdown(wait=False, cancel_futures=True)
        end_all(cancel)
        raise
    pool.shutdown()
    missing = sorted(set(roster or ()) - set(rows))
    for student in missing:
        row = Grade(student, "", "", {p.letter: 0.0 for p in exercise.parts},
                    {p.letter: NOT_SUBMITTED for p in exercise.parts}, 0.0,
                    sum(float((points or {}).get(p.letter, 1.0)) for p in exercise.parts),
                    "no submission (on the roster)", "", flexmbd_version(), _now())
        rows[student] = row
        if book is not None:
            book.record(row)
    return ClassGrades(exercise, rows, graded, time.monotonic() - begun, seed, missing)
