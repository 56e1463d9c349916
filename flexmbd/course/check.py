"""Check a student's exercise file part by part against flexmbd's answers.

The file runs in a child process (:mod:`flexmbd.course.runner`) under a time limit;
each part is called at the exercise's configuration and at random ones and compared
with the engine's answer. A failure names the first entry that differs and, when the
answer equals a typical wrong one, says what to fix: a transposed or column-permuted
Jacobian, the bending sign convention, degrees for radians, lumped for consistent mass,
a missing quadratic velocity term. :func:`check` returns a :class:`Report` with a score;
:meth:`Report.gradescope` is the results JSON of a Gradescope autograder.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ArgumentError
from ..summary import dataclass_repr
from .parts import Exercise, Part

#: outcomes of a part
PASSED, FAILED, NOT_DONE = "passed", "failed", "not done"


@dataclass(frozen=True)
class PartReport:
    """The outcome of one part: ``status`` (passed, failed, not done), a message and the
    hint for a recognised mistake."""

    __repr__ = dataclass_repr

    letter: str
    function: str
    status: str
    message: str = ""
    hint: str = ""


@dataclass
class Report:
    """The outcome of checking one file: per part, a score and a problem with the file
    itself (it failed to load or ran out of time) if any.

    Attributes:
        points: points per part letter (default 1 each).
        seconds: how long the check took [s].
    """

    __repr__ = dataclass_repr

    exercise: Exercise
    file: str
    parts: list[PartReport] = field(default_factory=list)
    problem: str | None = None
    seconds: float = 0.0
    points: dict[str, float] = field(default_factory=dict)

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
        lines = [f"exercise {ex.number} ({ex.name}): {self.file}"]
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
                "extra_data": {"exercise": ex.name, "file": self.file,
                               "problem": self.problem}}


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
    """A part's calls: its cases and their ids, its symbolic call, its probes."""

    cases: list
    ids: list
    symbolic: int | None
    probes: list = field(default_factory=list)
    probe_ids: list = field(default_factory=list)

    def all_ids(self) -> list[int]:
        return [*self.ids, *([self.symbolic] if self.symbolic is not None else []),
                *self.probe_ids]


def _calls(exercise: Exercise, seed: int) -> tuple[list[dict], dict]:
    """The calls for the child, and per part its :class:`_Plan`."""
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
        symbolic = None
        if part.symbolic is not None and _has_sympy():
            import sympy as sp

            names, reference = part.symbolic()
            symbolic = len(calls)
            calls.append({"id": symbolic, "function": part.function,
                          "args": [{"symbols": n} if isinstance(n, list) else {"symbol": n}
                                   for n in names], "reference": sp.srepr(reference)})
        probes = part.probes(rng) if part.probes is not None else []
        probe_ids = []
        for probe in probes:
            probe_ids.append(len(calls))
            calls.append({"id": len(calls), "function": part.function,
                          "args": [_encode(a) for a in probe.args],
                          "substitutes": {name: _encode(np.asarray(value, dtype=float))
                                          for name, value in probe.substitutes.items()}})
        plan[part.letter] = _Plan(cases, ids, symbolic, probes, probe_ids)
    return calls, plan


#: bytes a runner may send before the check stops reading it (a forged flood)
CHANNEL_CAP = 64 * 2**20
#: the minimal environment of a student's process: what Python and NumPy need
_ENVIRONMENT = {"LANG": "C.UTF-8", "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1",
                "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


@dataclass
class _Outcome:
    """What the runs of one file gave: the records by call id, the load problem, and per
    call whether its part ran out of time or its process ended."""

    records: dict = field(default_factory=dict)
    problem: str | None = None
    loaded: bool = False
    timed_out: set = field(default_factory=set)
    ended: set = field(default_factory=set)


def _run(path: Path, calls: list[dict], plan: dict, timeout: float, graded: bool
         ) -> _Outcome:
    """Run the student's file on ``calls`` in a scratch folder, ``timeout`` seconds per
    part: a part that runs out of time (or ends the process) is ended with the process,
    and a new process runs the parts after it."""
    outcome = _Outcome()
    part_of = {i: letter for letter, part in plan.items() for i in part.all_ids()}
    pending = list(calls)
    while pending:
        done = _run_once(path, pending, part_of, timeout, graded, outcome)
        if done is None:
            break
        # the part that stopped the process costs itself only: go on after it
        letter = part_of[done]
        pending = [c for c in pending if c["id"] not in outcome.records
                   and part_of[c["id"]] != letter]
    return outcome


def _run_once(path: Path, calls: list[dict], part_of: dict, timeout: float, graded: bool,
              outcome: _Outcome) -> int | None:
    """One runner process over ``calls``; returns the id of the call that stopped it
    early (out of time or ended), or ``None`` when it ran them all (or never loaded)."""
    with tempfile.TemporaryDirectory(prefix="flexmbd-check-") as scratch:
        home = Path(scratch) / "home"
        (home / "tmp").mkdir(parents=True)
        copy = Path(scratch) / path.name
        shutil.copyfile(path, copy)
        read, write = os.pipe()
        request = home / "request.json"
        request.write_text(json.dumps({"calls": calls, "channel": write, "graded": graded,
                                       "scratch": scratch}))
        env = {**_ENVIRONMENT, "HOME": str(home), "TMPDIR": str(home / "tmp"),
               "PATH": os.defpath}
        try:
            process = subprocess.Popen(
                [sys.executable, "-I", "-m", "flexmbd.course.runner", str(copy),
                 str(request)], cwd=scratch, env=env, stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, pass_fds=(write,),
                start_new_session=True)
        finally:
            os.close(write)
        try:
            return _follow(process, read, calls, part_of, timeout, outcome)
        finally:
            _end(process)
            os.close(read)


def _follow(process, read: int, calls: list[dict], part_of: dict, timeout: float,
            outcome: _Outcome) -> int | None:
    """Read the runner's records as they come, ending it when the call running has used
    its part's time; returns the id of the call that stopped the run early."""
    expected = iter(calls)
    current = None        # the call running, after its "started" record
    used: dict = {}       # seconds each part has run
    started_at = time.monotonic()
    buffer, total = b"", 0
    while True:
        budget = timeout - used.get(part_of.get(current), 0.0) if current is not None \
            else timeout
        left = budget - (time.monotonic() - started_at)
        ready, _, _ = select.select([read], [], [], max(left, 0.0))
        if not ready:
            if current is None:
                if not outcome.loaded:
                    outcome.problem = "the file did not finish loading within the time limit"
                    return None
                current = next(expected, {"id": None})["id"]
                if current is None:
                    return None
            outcome.timed_out.add(current)
            return current
        chunk = os.read(read, 65536)
        total += len(chunk)
        if not chunk or total > CHANNEL_CAP:  # the process ended (or floods the channel)
            if not outcome.loaded:
                outcome.problem = "the file's process ended before it finished loading"
                return None
            if current is not None:
                outcome.ended.add(current)
                return current
            following = next(expected, None)
            return None if following is None else following["id"]
        buffer += chunk
        *lines, buffer = buffer.split(b"\n")
        for line in lines:
            try:
                record = json.loads(line)
            except (json.JSONDecodeError, UnicodeDecodeError):
                continue
            if not isinstance(record, dict):
                continue
            if "loaded" in record and not outcome.loaded:
                outcome.loaded = True
                problem = record.get("problem")
                outcome.problem = str(problem) if problem else None
                started_at = time.monotonic()
            elif record.get("started") and current is None:
                following = next(expected, None)
                if following is None or record.get("id") != following["id"]:
                    continue  # not the call that comes next: not the runner's
                current, started_at = following["id"], time.monotonic()
            elif current is not None and record.get("id") == current:
                used[part_of[current]] = used.get(part_of[current], 0.0) + \
                    time.monotonic() - started_at
                outcome.records[current] = record
                current, started_at = None, time.monotonic()


def _end(process: subprocess.Popen) -> None:
    """End the runner and everything it started (its whole process group)."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(process.pid, signal.SIGKILL)
    try:
        process.wait(timeout=10)
    except subprocess.TimeoutExpired:   # the group was gone but not its leader
        process.kill()
        process.wait()


def _array(record) -> np.ndarray | tuple | None:
    """The numbers of a record, ``None`` for anything that does not decode to them."""
    try:
        if "array" in record:
            return np.array(record["array"], dtype=float).reshape(record["shape"])
        if "tuple" in record:
            items = [_array(item) for item in record["tuple"]]
            return None if any(i is None for i in items) else tuple(items)
    except (TypeError, ValueError, KeyError, OverflowError):
        return None
    return None


def _conform(got, expected):
    """``got`` in the shape of ``expected`` where that is unambiguous, else ``got``: a flat
    vector ``(n,)`` for a column ``(n, 1)`` or row ``(1, n)``, and any vector for a flat
    one. A row for a column (a transpose) stays, and fails with its hint."""
    if isinstance(expected, tuple) or isinstance(got, tuple):
        return got
    expected = np.asarray(expected, dtype=float)
    if got.shape == expected.shape or got.size != expected.size:
        return got
    vector = expected.ndim <= 1 or 1 in expected.shape
    flat_given = got.ndim <= 1
    flat_wanted = expected.ndim <= 1 and (got.ndim <= 1 or 1 in got.shape)
    if (vector and flat_given) or flat_wanted:
        return got.reshape(expected.shape)
    return got


def _off(got: np.ndarray, expected: np.ndarray, rtol: float) -> np.ndarray:
    """Where ``got`` differs from ``expected`` (same shapes): beyond ``rtol`` relative, with
    an absolute floor of 1e-9 of the answer's largest entry (at least 1)."""
    scale = max(1.0, float(np.max(np.abs(expected), initial=0.0)))
    return ~(np.abs(got - expected) <= rtol * np.abs(expected) + 1e-9 * scale)  # NaN: off


def _close(got, expected, rtol: float) -> bool:
    if isinstance(expected, tuple):
        return isinstance(got, tuple) and len(got) == len(expected) and all(
            _close(g, e, rtol) for g, e in zip(got, expected, strict=True))
    if isinstance(got, tuple):
        return False
    expected = np.asarray(expected, dtype=float)
    got = _conform(got, expected)
    if got.shape != expected.shape:
        return False
    return not np.any(_off(got, expected, rtol))


def _first_difference(got, expected, rtol: float) -> str:
    """The first entry that differs, or the shapes when they do."""
    if isinstance(expected, tuple):
        if not isinstance(got, tuple) or len(got) != len(expected):
            return f"expected a tuple of {len(expected)} arrays"
        for k, (g, e) in enumerate(zip(got, expected, strict=True)):
            if not _close(g, e, rtol):
                return f"item {k}: " + _first_difference(g, e, rtol)
        return ""
    expected = np.asarray(expected, dtype=float)
    if isinstance(got, tuple):
        return f"expected an array of shape {expected.shape}, got a tuple"
    got = _conform(got, expected)
    if got.shape != expected.shape:
        return f"shape {got.shape}, expected {expected.shape}"
    bad = np.argwhere(_off(got, expected, rtol))
    if expected.ndim and not len(bad):
        return "differs"
    index = tuple(int(i) for i in bad[0]) if expected.ndim else ()
    where = f"entry {list(index)}" if index else "value"
    return f"{where}: expected {expected[index]:.10g}, got {got[index]:.10g}"


def _describe(part: Part, args: tuple) -> str:
    names = [n.strip() for n in part.arguments.split(",")]
    shown = []
    for name, value in zip(names, args, strict=False):
        if isinstance(value, np.ndarray):
            shown.append(f"{name}=[{', '.join(f'{v:.6g}' for v in value)}]")
        else:
            shown.append(f"{name}={value:.6g}" if isinstance(value, float) else f"{name}={value}")
    return ", ".join(shown)


def _unwrapped(got, expected, angles) -> np.ndarray:
    """``got`` with its angle entries ``angles`` turned by whole turns to the nearest of
    ``expected``'s."""
    if isinstance(got, tuple) or isinstance(expected, tuple):
        return got
    expected = np.asarray(expected, dtype=float)
    got = _conform(got, expected)
    if got.shape != expected.shape:
        return got
    flat, wanted = got.astype(float).ravel().copy(), expected.ravel()
    for i in angles:
        if i < flat.size and np.isfinite(flat[i]):
            flat[i] -= 2 * np.pi * np.round((flat[i] - wanted[i]) / (2 * np.pi))
    return flat.reshape(got.shape)


def diagnose(part: Part, args: tuple, got, expected) -> str:
    """The hint for a wrong answer that matches a typical mistake, or ``""``."""
    def matches(wrong):
        try:
            mine = got if part.wrapped is None else _unwrapped(got, wrong,
                                                              part.wrapped(*args))
            return _close(mine, wrong, part.rtol)
        except (TypeError, ValueError):
            return False

    for mistake in part.mistakes:
        if matches(mistake.wrong(*args)):
            return mistake.hint
    names = [n.strip() for n in part.arguments.split(",")]
    for i in part.angles:
        for factor, read in ((math.pi / 180, "as degrees"), (180 / math.pi, "in radians "
                                                                               "twice")):
            shifted = list(args)
            shifted[i] = args[i] * factor
            try:
                wrong = part.answer(*shifted)
            except Exception:
                continue
            if matches(wrong):
                return (f"angles are in radians: your answer is right for {names[i]} read "
                        f"{read} (no np.radians/np.deg2rad on an angle that is already in "
                        f"radians)")
    if isinstance(expected, tuple) or isinstance(got, tuple):
        return ""
    expected = np.asarray(expected, dtype=float)
    if expected.ndim == 2 and got.shape == expected.T.shape and got.shape != expected.shape \
            and _close(got.T, expected, part.rtol):
        return (f"transposed: the answer has shape {expected.shape}, one row per "
                f"deformation (or coordinate) and one column per coordinate (or q)")
    if expected.ndim == 2 and min(expected.shape) > 1 and got.shape == expected.shape:
        order = []
        for column in got.T:
            found = [k for k, e in enumerate(expected.T) if _close(column, e, part.rtol)]
            order.append(found[0] if found else None)
        if None not in order and order != list(range(len(order))):
            return (f"columns out of order: your columns are the answer's columns "
                    f"{order}; order them as the coordinates ({part.arguments}) are")
    if matches(-expected):
        return "the sign is reversed: check the direction of d = r_q - r_p and of the normals"
    if got.shape == expected.shape and _close(got, expected, 1e-3):
        return (f"close to the answer but not within the check's relative {part.rtol:g}: if "
                f"the part iterates (Newton-Raphson), tighten its tolerance (|e| < 1e-12)")
    return ""


def check(exercise: Exercise, path: str | os.PathLike, timeout: float = 10.0,
          seed: int = 2026, graded: bool = False,
          points: dict[str, float] | None = None) -> Report:
    """Check the student's file ``path`` (``.py`` or ``.ipynb``) for ``exercise``.

    The file runs in a process of its own, in a scratch folder holding only a copy of it,
    with a minimal environment; its output is dropped. Every part, whatever the file
    does or returns, gets a verdict.

    Args:
        timeout: time limit [s] of each part (all its calls together), and of loading the
            file: a part that runs longer fails alone, and the parts after it run in a
            new process.
        seed: seed of the random configurations.
        graded: confine the file (:mod:`flexmbd.course.sandbox`): no flexmbd beyond the
            template's helper, no writes outside its scratch folder, no processes.
        points: points per part letter (default 1 each).
    """
    path = Path(path)
    if not path.is_file():
        raise ArgumentError("file", f"{path} does not exist or is not a file")
    if path.suffix not in (".py", ".ipynb"):
        raise ArgumentError("file", f"{path} is not a Python script (.py) or notebook "
                                    f"(.ipynb)")
    if not timeout > 0:
        raise ArgumentError("timeout", f"must be positive, got {timeout}")
    calls, plan = _calls(exercise, seed)
    begun = time.monotonic()
    outcome = _run(path.resolve(), calls, plan, timeout, graded)
    report = Report(exercise, str(path), problem=outcome.problem, points=dict(points or {}))
    for part in exercise.parts:
        try:
            verdict = _part(part, plan[part.letter], outcome)
        except Exception as error:  # the checker's own failure must not lose the report
            verdict = PartReport(part.letter, part.function, FAILED,
                                 f"the checker could not compare this answer "
                                 f"({type(error).__name__}: {error})")
        report.parts.append(verdict)
    report.parts = _knock_on(exercise, plan, outcome, report.parts)
    report.seconds = time.monotonic() - begun
    return report


def _knock_on(exercise: Exercise, plan: dict, outcome: _Outcome,
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
                                 verdict.message, "; ".join(filter(None, [note, verdict.hint])))
        out.append(verdict)
    return out


def _part(part: Part, plan: _Plan, outcome: _Outcome) -> PartReport:
    """One part's outcome from its records."""
    def result(status, message="", hint=""):
        return PartReport(part.letter, part.function, status, message, hint)

    checks = [(args, call, None) for args, call in zip(plan.cases, plan.ids, strict=True)]
    checks += [(probe.args, call, probe)
               for probe, call in zip(plan.probes, plan.probe_ids, strict=True)]
    for args, call, probe in checks:
        record = outcome.records.get(call)
        if record is None:
            if call in outcome.timed_out:
                return result(FAILED, f"time limit: the call with {_describe(part, args)} "
                                      f"did not return (an endless loop?)")
            if call in outcome.ended:
                return result(FAILED, f"the file's process ended (exit or crash) in the "
                                      f"call with {_describe(part, args)}")
            if not outcome.loaded:
                return result(FAILED, "not run: the file did not load")
            return result(FAILED, "not run: an earlier call of this part stopped the file")
        if record.get("missing"):
            if outcome.problem:
                return result(FAILED, f"not defined: the file stopped loading before "
                                      f"{part.function}() ({outcome.problem})")
            return result(NOT_DONE, f"no function {part.function}() in the file")
        if record.get("none"):
            return result(FAILED, f"returned None for {_describe(part, args)}",
                          "a missing return statement? end the function with "
                          "`return <the answer>`")
        if "not_done" in record:
            return result(NOT_DONE, str(record["not_done"]).removeprefix(
                f"part {part.letter} not done yet: "))
        if "error" in record:
            return result(FAILED, f"raised {record['error']} for {_describe(part, args)}")
        if "garbage" in record:
            return result(FAILED, f"returned {record['garbage']}, not numbers")
        if "sympy" in record:
            return result(FAILED, f"returned an expression with free symbols for "
                                  f"{_describe(part, args)}; return numbers")
        got = _array(record)
        if got is None:
            return result(FAILED, "returned something that is not numbers")
        if probe is not None:
            if not _close(got, probe.expected, part.rtol):
                unchanged = _close(got, part.answer(*args), part.rtol)
                return result(FAILED, f"at {_describe(part, args)}, with other values of "
                                      f"{', '.join(probe.substitutes)}: "
                                      f"{_first_difference(got, probe.expected, part.rtol)}",
                              f"{part.function} must be {probe.uses}"
                              + ("; your answer did not change with them" if unchanged
                                 else ""))
            continue
        expected = part.answer(*args)
        if part.wrapped is not None:
            got = _unwrapped(got, expected, part.wrapped(*args))
        if not _close(got, expected, part.rtol):
            return result(FAILED, f"at {_describe(part, args)}: "
                                  f"{_first_difference(got, expected, part.rtol)}",
                          diagnose(part, args, got, expected))
    symbolic = outcome.records.get(plan.symbolic) if plan.symbolic is not None else None
    note = ""
    if symbolic is not None and symbolic.get("symbolic") == "equal":
        note = "SymPy expression algebraically equal to flexmbd's"
    return result(PASSED, note)
