"""Check a student's exercise file part by part against flexmbd's answers.

The file runs in a child process (:mod:`flexmbd.course.runner`) under a time limit;
each part is called at the exercise's configuration and at random ones and compared
with the engine's answer. A failure names the first entry that differs and, when the
answer equals a typical wrong one, says what to fix: a transposed or column-permuted
Jacobian, the bending sign convention, degrees for radians, lumped for consistent mass,
a missing quadratic velocity term. :func:`check` returns a :class:`Report` with a score;
:meth:`Report.gradescope` is the JSON that otter-grader and Gradescope take in.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ArgumentError
from .parts import Exercise, Part

#: outcomes of a part
PASSED, FAILED, NOT_DONE = "passed", "failed", "not done"


@dataclass(frozen=True)
class PartReport:
    """The outcome of one part: ``status`` (passed, failed, not done), a message and the
    hint for a recognised mistake."""

    letter: str
    function: str
    status: str
    message: str = ""
    hint: str = ""


@dataclass
class Report:
    """The outcome of checking one file: per part, a score and a problem with the file
    itself (it failed to load or ran out of time) if any."""

    exercise: Exercise
    file: str
    parts: list[PartReport] = field(default_factory=list)
    problem: str | None = None

    @property
    def score(self) -> int:
        """Parts passed (one point each)."""
        return sum(p.status == PASSED for p in self.parts)

    @property
    def max_score(self) -> int:
        return len(self.exercise.parts)

    @property
    def exit_status(self) -> int:
        """0 when every part passed, 1 otherwise (for autograders)."""
        return 0 if self.score == self.max_score else 1

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
        lines.append(f"score {self.score}/{self.max_score}")
        return "\n".join(lines)

    def gradescope(self) -> dict:
        """The report in the Gradescope results format (read by otter-grader)."""
        ex = self.exercise
        return {"score": self.score, "max_score": self.max_score, "exercise": ex.name,
                "file": self.file, "problem": self.problem,
                "tests": [{"name": f"{ex.number}{p.letter} {p.function}",
                           "score": int(p.status == PASSED), "max_score": 1,
                           "status": "passed" if p.status == PASSED else "failed",
                           "output": ": ".join(filter(None, [p.status, p.message]))
                           + (f" (hint: {p.hint})" if p.hint else "")}
                          for p in self.parts]}


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


def _calls(exercise: Exercise, seed: int) -> tuple[list[dict], dict]:
    """The calls for the child, and per part its cases and the id of its symbolic call."""
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
        plan[part.letter] = (cases, ids, symbolic)
    return calls, plan


def _run(path: Path, calls: list[dict], timeout: float) -> tuple[dict, str | None, bool]:
    """Run the child; returns the records by call id, the load problem and whether the
    time limit ended it."""
    with tempfile.TemporaryDirectory(prefix="flexmbd-check-") as tmp:
        request, results = Path(tmp) / "request.json", Path(tmp) / "results.jsonl"
        request.write_text(json.dumps({"calls": calls}))
        results.touch()
        env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1"}
        timed_out = False
        try:
            subprocess.run([sys.executable, "-m", "flexmbd.course.runner", str(path),
                            str(request), str(results)], cwd=path.parent, env=env,
                           stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL, timeout=timeout, check=False)
        except subprocess.TimeoutExpired:
            timed_out = True
        records: dict = {}
        problem, loaded = None, False
        for line in results.read_text(errors="replace").splitlines():
            try:
                record = json.loads(line)
            except json.JSONDecodeError:
                continue
            if "loaded" in record:
                loaded, problem = True, record.get("problem")
            elif record.get("started"):
                records.setdefault(record["id"], {"started": True})
            else:
                records[record["id"]] = record
    if not loaded:
        problem = ("the file did not finish loading within the time limit" if timed_out
                   else "the file's process ended before it finished loading")
    return records, problem, timed_out


def _array(record: dict) -> np.ndarray | tuple | None:
    if "array" in record:
        return np.array(record["array"], dtype=float).reshape(record["shape"])
    if "tuple" in record:
        items = [_array(item) for item in record["tuple"]]
        return None if any(i is None for i in items) else tuple(items)
    return None


def _conform(got, expected):
    """``got`` in the shape of ``expected`` when it holds the same vector, else ``got``."""
    if isinstance(expected, tuple) or isinstance(got, tuple):
        return got
    expected = np.asarray(expected, dtype=float)
    if got.shape == expected.shape:
        return got
    vector = expected.ndim <= 1 or 1 in expected.shape
    if got.size == expected.size and vector and (got.ndim <= 1 or 1 in got.shape):
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
    bad = _off(got, expected, rtol)
    index = tuple(int(i) for i in np.argwhere(bad)[0]) if expected.ndim else ()
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


def diagnose(part: Part, args: tuple, got, expected) -> str:
    """The hint for a wrong answer that matches a typical mistake, or ``""``."""
    def matches(wrong):
        try:
            return _close(got, wrong, part.rtol)
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
    if expected.ndim == 2 and min(expected.shape) > 1:
        if got.shape == expected.T.shape and _close(got.T, expected, part.rtol):
            return (f"transposed: the answer has shape {expected.shape}, one row per "
                    f"deformation (or coordinate) and one column per coordinate (or q)")
        if got.shape == expected.shape:
            order = []
            for column in got.T:
                found = [k for k, e in enumerate(expected.T) if _close(column, e, part.rtol)]
                order.append(found[0] if found else None)
            if None not in order and order != list(range(len(order))):
                return (f"columns out of order: your columns are the answer's columns "
                        f"{order}; order them as the coordinates ({part.arguments}) are")
    if matches(-expected):
        return "the sign is reversed: check the direction of d = r_q - r_p and of the normals"
    return ""


def check(exercise: Exercise, path: str | os.PathLike, timeout: float = 60.0,
          seed: int = 2026) -> Report:
    """Check the student's file ``path`` (``.py`` or ``.ipynb``) for ``exercise``.

    Args:
        timeout: time limit [s] for the student's process (all parts together).
        seed: seed of the random configurations.
    """
    path = Path(path)
    if not path.is_file():
        raise ArgumentError("file", f"{path} does not exist or is not a file")
    if path.suffix not in (".py", ".ipynb"):
        raise ArgumentError("file", f"{path} is not a Python script (.py) or notebook "
                                    f"(.ipynb)")
    calls, plan = _calls(exercise, seed)
    records, problem, timed_out = _run(path.resolve(), calls, timeout)
    report = Report(exercise, str(path), problem=problem)
    stopped = False
    for part in exercise.parts:
        cases, ids, symbolic = plan[part.letter]
        outcome = _part(part, cases, [records.get(i) for i in ids],
                        records.get(symbolic) if symbolic is not None else None,
                        timed_out, stopped)
        stopped = stopped or outcome.message.startswith("time limit")
        report.parts.append(outcome)
    return report


def _part(part: Part, cases, records, symbolic, timed_out: bool, stopped: bool) -> PartReport:
    """One part's outcome from its records (``None``: the call never ran)."""
    def result(status, message="", hint=""):
        return PartReport(part.letter, part.function, status, message, hint)

    for args, record in zip(cases, records, strict=True):
        if record is None or record.keys() == {"started"}:
            if stopped:
                return result(FAILED, "not run: the time limit ended the file earlier")
            if timed_out and record is not None:
                return result(FAILED, f"time limit: the call with {_describe(part, args)} "
                                      f"did not return (an endless loop?)")
            return result(FAILED, "not run: the file's process ended (exit or crash) "
                                  "before this part")
        if record.get("missing"):
            return result(NOT_DONE, f"no function {part.function}() in the file")
        if "not_done" in record:
            return result(NOT_DONE, record["not_done"].removeprefix(
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
        expected = part.answer(*args)
        if not record.get("finite", True) or not _close(got, expected, part.rtol):
            return result(FAILED, f"at {_describe(part, args)}: "
                                  f"{_first_difference(got, expected, part.rtol)}",
                          diagnose(part, args, got, expected))
    note = ""
    if symbolic is not None and symbolic.get("symbolic") == "equal":
        note = "SymPy expression algebraically equal to flexmbd's"
    return result(PASSED, note)
