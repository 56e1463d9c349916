"""Check a student's exercise file part by part against flexmbd's answers.

The file runs in a child process (:mod:`flexmbd.course.launch`; in a graded check inside
the operating-system sandbox of :mod:`flexmbd.course.sandbox`) under a time limit per
part; each part is called at the exercise's configuration and at random ones, and the
grader compares what comes back with the engine's answer (:mod:`flexmbd.course.compare`).
No answer ever enters the student's process. A failure names the first entry that
differs and, when the answer equals a typical wrong one, says what to fix: a transposed
or column-permuted Jacobian, the bending sign convention, degrees for radians, lumped for
consistent mass, a missing quadratic velocity term, single precision. :func:`check`
returns a :class:`Report` with a score and, per part, the reason it did not pass;
:meth:`Report.gradescope` is the results JSON of a Gradescope autograder.
"""

from __future__ import annotations

import hashlib
import os
import secrets
import stat
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ArgumentError
from ..summary import dataclass_repr
from . import expressions
from .compare import close, diagnose, first_difference, single_precision_in, unwrapped
from .launch import ISOLATIONS, Outcome, Stop, launcher, run, verify
from .parts import Exercise, Part
from .sandbox import Limits
from .untrusted import one_line

#: outcomes of a part
PASSED, FAILED, NOT_DONE = "passed", "failed", "not done"
#: why a part did not pass (the class table's reasons; ``passed`` when it did)
WRONG, ERROR, TIME, MEMORY, KILLED, NOT_DEFINED = ("wrong", "error", "time", "memory",
                                                   "killed", "not defined")
#: the seed of a self-check's random configurations (a graded check draws its own)
SELF_CHECK_SEED = 2026
#: the largest file a check reads [bytes]
FILE_CAP = 32 * 2**20


@dataclass(frozen=True)
class PartReport:
    """The outcome of one part: ``status`` (passed, failed, not done), ``reason`` (passed,
    wrong, error, time, memory, killed, not defined), a message and the hint for a
    recognised mistake."""

    __repr__ = dataclass_repr

    letter: str
    function: str
    status: str
    message: str = ""
    hint: str = ""
    reason: str = PASSED


@dataclass
class Report:
    """The outcome of checking one file: per part, a score and a problem with the file
    itself (it failed to load or ran out of time) if any.

    Attributes:
        points: points per part letter (default 1 each).
        seconds: how long the check took [s].
        seed: the seed of the random configurations.
        sha256: the hash of the file as it was checked.
        isolation: how the file ran, in words.
    """

    __repr__ = dataclass_repr

    exercise: Exercise
    file: str
    parts: list[PartReport] = field(default_factory=list)
    problem: str | None = None
    seconds: float = 0.0
    points: dict[str, float] = field(default_factory=dict)
    seed: int = SELF_CHECK_SEED
    sha256: str = ""
    isolation: str = ""

    def worth(self, letter: str) -> float:
        """The points of part ``letter``."""
        return float(self.points.get(letter, 1.0))

    @property
    def score(self) -> float:
        """Points of the parts passed."""
        return sum(self.worth(p.letter) for p in self.parts if p.status == PASSED)

    @property
    def max_score(self) -> float:
        return sum(self.worth(p.letter) for p in self.exercise.parts)

    @property
    def exit_status(self) -> int:
        """0 when every part passed, 1 otherwise (for autograders)."""
        return 0 if all(p.status == PASSED for p in self.parts) and self.parts else 1

    def text(self) -> str:
        """The report as the command prints it."""
        ex = self.exercise
        lines = [f"exercise {ex.number} ({ex.name}): {one_line(self.file)}"]
        if self.problem:
            lines.append(f"  note: {self.problem}")
        for p in self.parts:
            lines.append(f"  {ex.number}{p.letter}  {p.function:<26} {p.status}"
                         + (f": {p.message}" if p.message else ""))
            if p.hint:
                lines.append(f"      hint: {p.hint}")
        lines.append(f"score {_number(self.score)}/{_number(self.max_score)}")
        return "\n".join(lines)

    def gradescope(self) -> dict:
        """The report as a Gradescope autograder's ``results.json``: the score, the time,
        a summary the student sees (the reason when the file did not load), one test per
        part with its points, status and message."""
        ex = self.exercise
        summary = (f"Your file did not load completely: {self.problem}. Parts that need "
                   f"what did not load fail." if self.problem else
                   f"exercise {ex.number} ({ex.name}): {_number(self.score)} of "
                   f"{_number(self.max_score)} points")
        return {"score": self.score, "max_score": self.max_score,
                "execution_time": round(self.seconds, 3), "output": summary,
                "visibility": "visible", "stdout_visibility": "hidden",
                "tests": [{"name": f"{ex.number}{p.letter} {p.function}",
                           "score": self.worth(p.letter) if p.status == PASSED else 0.0,
                           "max_score": self.worth(p.letter),
                           "status": "passed" if p.status == PASSED else "failed",
                           "output": ": ".join(filter(None, [p.status, p.message]))
                           + (f" (hint: {p.hint})" if p.hint else ""),
                           "visibility": "visible"}
                          for p in self.parts],
                "extra_data": {"exercise": ex.name, "file": one_line(self.file),
                               "problem": self.problem, "seed": self.seed,
                               "sha256": self.sha256, "isolation": self.isolation}}


def _number(value: float) -> str:
    return f"{value:g}"


def _encode(value):
    if isinstance(value, np.ndarray):
        return {"array": value.tolist()}
    if isinstance(value, np.generic):
        return value.item()
    return value


def _has_sympy() -> bool:
    """Whether SymPy answers can be compared (the ``symbolic`` extra)."""
    try:
        import sympy  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass(frozen=True)
class _Plan:
    """A part's calls: its cases and their ids, its symbolic call (with the symbols' names
    and the reference as a tree), its probes."""

    cases: list
    ids: list
    symbolic: int | None
    names: list = field(default_factory=list)
    reference: dict | None = None
    probes: list = field(default_factory=list)
    probe_ids: list = field(default_factory=list)

    def all_ids(self) -> list[int]:
        return [*self.ids, *([self.symbolic] if self.symbolic is not None else []),
                *self.probe_ids]


def _calls(exercise: Exercise, seed: int) -> tuple[list[dict], dict]:
    """The calls for the child (arguments only), and per part its :class:`_Plan`."""
    from .runner import sympy_tree

    rng = np.random.default_rng(seed)
    calls: list[dict] = []
    plan: dict = {}
    for part in exercise.parts:
        cases = part.cases(rng)
        ids = []
        for args in cases:
            ids.append(len(calls))
            calls.append({"id": len(calls), "function": part.function,
                          "args": [_encode(a) for a in args]})
        symbolic, names, reference = None, [], None
        if part.symbolic is not None and _has_sympy():
            arguments, expression = part.symbolic()
            symbolic, reference = len(calls), sympy_tree(expression, budget=10**6)
            names = [n for a in arguments for n in (a if isinstance(a, list) else [a])]
            calls.append({"id": symbolic, "function": part.function,
                          "args": [{"symbols": n} if isinstance(n, list) else {"symbol": n}
                                   for n in arguments]})
        probes = part.probes(rng) if part.probes is not None else []
        probe_ids = []
        for probe in probes:
            probe_ids.append(len(calls))
            calls.append({"id": len(calls), "function": part.function,
                          "args": [_encode(a) for a in probe.args],
                          "substitutes": {name: _encode(np.asarray(value, dtype=float))
                                          for name, value in probe.substitutes.items()}})
        plan[part.letter] = _Plan(cases, ids, symbolic, names, reference, probes, probe_ids)
    return calls, plan


def _array(record) -> np.ndarray | tuple | None:
    """The numbers of a record, ``None`` for anything that does not decode to them."""
    try:
        if "array" in record:
            return np.array(record["array"], dtype=float).reshape(record["shape"])
        if "tuple" in record:
            items = [_array(item) for item in record["tuple"]]
            return None if any(i is None for i in items) else tuple(items)
    except (TypeError, ValueError, KeyError, OverflowError, AttributeError):
        return None
    return None


def _describe(part: Part, args: tuple) -> str:
    names = [n.strip() for n in part.arguments.split(",")]
    shown = []
    for name, value in zip(names, args, strict=False):
        if isinstance(value, np.ndarray):
            shown.append(f"{name}=[{', '.join(f'{v:.6g}' for v in value)}]")
        else:
            shown.append(f"{name}={value:.6g}" if isinstance(value, float) else f"{name}={value}")
    return ", ".join(shown)


def read_submission(path: str | os.PathLike, follow_links: bool = True) -> bytes:
    """The bytes of a submission, read once.

    Raises:
        ArgumentError: not a regular file, a link when ``follow_links`` is false (a graded
            file must be the student's own, not a link to someone else's), unreadable, or
            larger than :data:`FILE_CAP`.
    """
    flags = os.O_RDONLY | os.O_NONBLOCK | (0 if follow_links else os.O_NOFOLLOW)
    try:
        fd = os.open(path, flags)
    except OSError as error:
        if not follow_links and os.path.islink(path):
            raise ArgumentError("file", f"{one_line(path)} is a link, not a file: a graded "
                                        f"submission must be a file of its own") from None
        raise ArgumentError("file", f"cannot read {one_line(path)}: {error.strerror}") \
            from None
    with os.fdopen(fd, "rb") as handle:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise ArgumentError("file", f"{one_line(path)} is not a file")
        content = handle.read(FILE_CAP + 1)
    if len(content) > FILE_CAP:
        raise ArgumentError("file", f"{one_line(path)} is larger than "
                                    f"{FILE_CAP // 2**20} MB")
    return content


def _name_inside(path: Path) -> str:
    """The file's name in its scratch folder: its own where that is a plain name."""
    name = path.name
    if one_line(name, 100) == name and name.isprintable() and not name.startswith("."):
        return name
    return "submission" + path.suffix


def check(exercise: Exercise, path: str | os.PathLike, timeout: float = 10.0,
          seed: int | None = None, graded: bool = False,
          points: dict[str, float] | None = None, *, isolation=None,
          limits: Limits | None = None) -> Report:
    """Check the student's file ``path`` (``.py`` or ``.ipynb``) for ``exercise``.

    The file is read once; a copy runs in a process of its own, in a scratch folder
    holding only that copy, with a minimal environment; its output is dropped. Every
    part, whatever the file does or returns, gets a verdict.

    Args:
        timeout: time limit [s] of each part (all its calls together), and of loading the
            file: a part that runs longer fails alone, and the parts after it run in a
            new process.
        seed: seed of the random configurations. Default: a new random seed in a graded
            check (no table of answers computed beforehand can pass), 2026 in a
            self-check.
        graded: a grade: the file is not followed through a link and runs in the
            operating-system sandbox (:mod:`flexmbd.course.sandbox`) unless ``isolation``
            says otherwise.
        points: points per part letter (default 1 each).
        isolation: ``"sandbox"``, ``"in-process"`` (an audit hook in the student's own
            Python, which a hostile file gets around), ``"none"`` (a self-check) or a
            launcher of :mod:`flexmbd.course.launch`. Default: ``"sandbox"`` when graded,
            else ``"none"``.
        limits: the sandbox's limits of memory, processes, file size and CPU time
            (default :class:`~flexmbd.course.sandbox.Limits`).

    Raises:
        ArgumentError: no such file, not a script or notebook, or a bad option.
        SandboxError: the sandbox cannot be made here (with what to do instead).
    """
    path = Path(path)
    if path.suffix not in (".py", ".ipynb"):
        raise ArgumentError("file", f"{one_line(path)} is not a Python script (.py) or "
                                    f"notebook (.ipynb)")
    if not timeout > 0:
        raise ArgumentError("timeout", f"must be positive, got {timeout}")
    if isolation is None:
        isolation = "sandbox" if graded else "none"
    if isinstance(isolation, str) and isolation not in ISOLATIONS:
        raise ArgumentError("isolation", f"choose from {', '.join(ISOLATIONS)}, not "
                                         f"{isolation!r}")
    content = read_submission(path, follow_links=not graded)
    start = launcher(isolation, limits, hide=(path.resolve().parent,))
    if isolation != "none":
        verify(start)
    if seed is None:
        seed = secrets.randbits(32) if graded else SELF_CHECK_SEED
    return check_content(exercise, str(path), content, start, timeout=timeout, seed=seed,
                         points=points)


def check_content(exercise: Exercise, file: str, content: bytes, start, *,
                  timeout: float, seed: int, points=None, cancel=None) -> Report:
    """:func:`check` of a file's ``content`` (read already), run by the launcher
    ``start`` (verified already); ``file`` is the name reports give, ``cancel`` the
    event of an interrupted grading (:func:`flexmbd.course.launch.end_all`)."""
    calls, plan = _calls(exercise, seed)
    part_of = {i: letter for letter, item in plan.items() for i in item.all_ids()}
    begun = time.monotonic()
    cpu = timeout * (len(exercise.parts) + 1) + 5.0
    outcome = run(start, _name_inside(Path(file)), content, calls, part_of, timeout, cpu,
                  cancel)
    if outcome.problem:   # the student's words: shown as one line of plain text
        outcome.problem = one_line(outcome.problem, 500)
    report = Report(exercise, file, problem=outcome.problem, points=dict(points or {}), seed=seed,
                    sha256=hashlib.sha256(content).hexdigest(), isolation=start.name)
    limits, single = start.limits, single_precision_in(content)
    for part in exercise.parts:
        try:
            verdict = _part(part, plan[part.letter], outcome, timeout, limits,
                            np.random.default_rng([seed, 1]), single)
        except Exception as error:  # the checker's own failure must not lose the report
            verdict = PartReport(part.letter, part.function, FAILED,
                                 f"the checker could not compare this answer "
                                 f"({type(error).__name__}: {one_line(error)})",
                                 reason=ERROR)
        report.parts.append(verdict)
    report.parts = _knock_on(exercise, plan, outcome, report.parts)
    report.seconds = time.monotonic() - begun
    return report


def _knock_on(exercise: Exercise, plan: dict, outcome: Outcome,
              verdicts: list[PartReport]) -> list[PartReport]:
    """A failed part that used failed earlier parts says so: fix those first."""
    failed = {v.letter for v in verdicts if v.status != PASSED}
    letter_of = {p.function: p.letter for p in exercise.parts}
    out = []
    for verdict in verdicts:
        uses = set()
        for call in plan[verdict.letter].all_ids():
            record = outcome.records.get(call)
            if isinstance(record, dict) and isinstance(record.get("uses"), list):
                uses |= {letter_of[f] for f in record["uses"] if f in letter_of}
        culprits = sorted(uses & failed - {verdict.letter})
        if verdict.status == FAILED and culprits:
            names = ", ".join(f"{exercise.number}{k} ({exercise.part(k).function})"
                              for k in culprits)
            note = f"it uses {names}, which {'fail' if len(culprits) > 1 else 'fails'}: " \
                   f"fix {'them' if len(culprits) > 1 else 'it'} first"
            verdict = PartReport(verdict.letter, verdict.function, verdict.status,
                                 verdict.message, "; ".join(filter(None, [note, verdict.hint])),
                                 verdict.reason)
        out.append(verdict)
    return out


def _megabytes(characters: int) -> str:
    return f"{characters / 1e6:.3g} MB"


def _stopped(stop: Stop, where: str, printed: int, timeout: float) -> tuple:
    """``(reason, message, hint)`` of a call that stopped its process."""
    noisy = (f"it had printed {_megabytes(printed)} by then: printing costs time; print "
             f"less (a check drops what is printed)") if printed >= 2**20 else ""
    if stop.reason == TIME:
        message = f"time limit: the call with {where} did not return within {timeout:g} s" \
            + (f" ({stop.words})" if stop.words else "")
        return TIME, message, noisy or "an endless loop, or a method far slower than needed?"
    if stop.reason == MEMORY:
        return MEMORY, f"memory limit: in the call with {where}, {stop.words}", \
            "no part needs that much memory: an array far too large, or too many processes?"
    return stop.reason, f"the file's process ended in the call with {where}: {stop.words}", \
        noisy


def _error_hint(kind: str, message: str, limits: Limits | None) -> tuple[str, str]:
    """``(reason, hint)`` of an exception the student's code raised."""
    if kind == "MemoryError":
        size = f"{limits.memory / 2**30:g} GB" if limits else "its memory"
        return MEMORY, (f"out of memory: a graded run may use {size}; an array that large "
                        f"is not needed here")
    if kind == "BlockingIOError" or "Resource temporarily unavailable" in message:
        count = f"{limits.processes}" if limits else "a few"
        return ERROR, f"a graded run may start {count} processes and threads in all"
    if kind in ("ModuleNotFoundError", "ImportError"):
        if "flexmbd" in message:
            return ERROR, ("a graded run has nothing of flexmbd but the template's helper "
                           "(flexmbd.course.student): a graded answer is your own code")
        return ERROR, ("a graded run has the standard library, NumPy, SciPy, SymPy and "
                       "Matplotlib, and nothing else")
    if "Read-only file system" in message:
        return ERROR, "a graded run writes only in its working (scratch) folder"
    if "File too large" in message:
        size = f"{limits.file_size / 2**20:g} MB" if limits else "a limited size"
        return ERROR, f"a graded run writes files of at most {size}"
    if "No space left on device" in message:
        size = f"{limits.scratch / 2**20:g} MB" if limits else "little"
        return ERROR, f"the scratch folder of a graded run holds {size}"
    if "Network is unreachable" in message or kind.startswith("socket"):
        return ERROR, "a graded run has no network"
    return ERROR, ""


def _part(part: Part, plan: _Plan, outcome: Outcome, timeout: float,
          limits: Limits | None, rng, single: str | None = None) -> PartReport:
    """One part's outcome from its records; ``single``: the single-precision type the
    file names, if any."""
    def result(status, reason, message="", hint=""):
        return PartReport(part.letter, part.function, status, message, hint, reason)

    checks = [(args, call, None) for args, call in zip(plan.cases, plan.ids, strict=True)]
    checks += [(probe.args, call, probe)
               for probe, call in zip(plan.probes, plan.probe_ids, strict=True)]
    for args, call, probe in checks:
        where = _describe(part, args)
        record = outcome.records.get(call)
        if record is None:
            stop = outcome.stopped.get(call)
            if stop is not None:
                return result(FAILED, *_stopped(stop, where, outcome.printed.get(call, 0),
                                                timeout))
            if not outcome.loaded:
                reason = outcome.load_stop.reason if outcome.load_stop else ERROR
                return result(FAILED, reason, "not run: the file did not load")
            return result(FAILED, ERROR, "not run: an earlier call of this part stopped "
                                         "the file")
        if record.get("malformed"):
            return result(FAILED, ERROR, f"its answer for {where} could not be read (a "
                                         f"malformed record on the results channel)")
        if record.get("missing"):
            if outcome.problem:
                return result(FAILED, NOT_DEFINED, f"not defined: the file stopped loading "
                                                   f"before {part.function}() "
                                                   f"({outcome.problem})")
            return result(NOT_DONE, NOT_DEFINED, f"no function {part.function}() in the file")
        if record.get("none"):
            return result(FAILED, WRONG, f"returned None for {where}",
                          "a missing return statement? end the function with "
                          "`return <the answer>`")
        if "not_done" in record:
            return result(NOT_DONE, NOT_DEFINED, one_line(record["not_done"]).removeprefix(
                f"part {part.letter} not done yet: "))
        if "error" in record:
            message = one_line(record["error"])
            reason, hint = _error_hint(str(record.get("kind", "")), message, limits)
            return result(FAILED, reason, f"raised {message} for {where}", hint)
        if "garbage" in record:
            return result(FAILED, WRONG, f"returned {one_line(record['garbage'], 200)}, not "
                                         f"numbers")
        if "sympy" in record:
            return result(FAILED, WRONG, f"returned an expression with free symbols for "
                                         f"{where}; return numbers")
        got = _array(record)
        if got is None:
            return result(FAILED, WRONG, "returned something that is not numbers")
        precision = str(record["dtype"])[:20] if "dtype" in record else single
        if probe is not None:
            if not close(got, probe.expected, part.rtol):
                unchanged = close(got, part.answer(*args), part.rtol)
                return result(FAILED, WRONG, f"at {where}, with other values of "
                                             f"{', '.join(probe.substitutes)}: "
                                             f"{first_difference(got, probe.expected, part.rtol)}",
                              f"{part.function} must be {probe.uses}"
                              + ("; your answer did not change with them" if unchanged
                                 else ""))
            continue
        expected = part.answer(*args)
        if part.wrapped is not None:
            got = unwrapped(got, expected, part.wrapped(*args))
        if not close(got, expected, part.rtol):
            return result(FAILED, WRONG, f"at {where}: "
                                         f"{first_difference(got, expected, part.rtol)}",
                          diagnose(part, args, got, expected, precision))
    return result(PASSED, PASSED, _symbolic_note(plan, outcome, rng))


def _symbolic_note(plan: _Plan, outcome: Outcome, rng) -> str:
    """The note of a part that passed when its SymPy answer equals flexmbd's."""
    record = outcome.records.get(plan.symbolic) if plan.symbolic is not None else None
    if record is None or "sympy" not in record or plan.reference is None:
        return ""
    if expressions.equal(record["sympy"], plan.reference, plan.names, rng):
        return (f"SymPy expression equal to flexmbd's (the same values at "
                f"{expressions.POINTS} random points)")
    return ""
