"""The checker's child process: load a student's file and call its parts.

Run by :mod:`flexmbd.course.check` as ``python -I -m flexmbd.course.runner FILE REQUEST``
in a scratch folder holding only a copy of ``FILE``, never by users. ``REQUEST`` is a JSON
file: the calls (function name, encoded arguments, optionally a SymPy reference), the
file descriptor of the pipe the results go through, whether the run is graded, and the
scratch folder. Each call's outcome is one JSON line on that pipe, after a ``started``
line, so the parent knows which call hung when it ends the process. The student's
output is capped and discarded: results travel only through the pipe, whose descriptor
the runner moves before the student's code runs.

A graded run (:mod:`flexmbd.course.sandbox`) also confines the student's code: no
writes outside the scratch folder, no new processes, no network, no flexmbd beyond the
helper module the template imports, and no reading of flexmbd's files.
"""

from __future__ import annotations

import io
import json
import os
import sys
import traceback

import numpy as np

#: what a student's file may print before the rest is dropped [characters]
OUTPUT_CAP = 20_000


class CappedOutput(io.TextIOBase):
    """A ``sys.stdout`` that keeps the first :data:`OUTPUT_CAP` characters and drops the
    rest at once: printing in a loop costs the student's process, not the check."""

    def __init__(self) -> None:
        self.kept: list[str] = []
        self.size = 0

    def writable(self) -> bool:
        return True

    def write(self, text) -> int:
        text = str(text)
        if self.size < OUTPUT_CAP:
            self.kept.append(text[:OUTPUT_CAP - self.size])
            self.size += len(self.kept[-1])
        return len(text)


def decode(value):
    """An argument from its JSON form (numbers, ``{"array": ...}``, ``{"symbol": name}``,
    ``{"symbols": [names]}``)."""
    if isinstance(value, dict):
        if "array" in value:
            return np.array(value["array"], dtype=float)
        import sympy as sp

        if "symbol" in value:
            return sp.Symbol(value["symbol"], real=True)
        return sp.Matrix([sp.Symbol(name, real=True) for name in value["symbols"]])
    return value


def _where(error: BaseException, path: str) -> str:
    """``" (line N)"`` of the deepest frame in the student's file, if any."""
    lines = [f.lineno for f in traceback.extract_tb(error.__traceback__)
             if os.path.abspath(f.filename) == path]
    return f" (line {lines[-1]})" if lines else ""


def _message(error: BaseException, path: str) -> str:
    text = " ".join(str(error).split())[:300]
    return f"{type(error).__name__}: {text}{_where(error, path)}"


def encode(result) -> dict:
    """A result as JSON: ``{"array", "shape"}`` (NaN and infinities kept), ``{"tuple"}``,
    ``{"sympy"}``, ``{"none"}`` or ``{"garbage"}`` for anything that is not numbers."""
    if result is None:
        return {"none": True}
    sp = sys.modules.get("sympy")   # an answer in SymPy was made with an imported SymPy
    if sp is not None and isinstance(result, sp.Basic | sp.MatrixBase) \
            and getattr(result, "free_symbols", None):
        return {"sympy": sp.srepr(result)}
    if sp is not None and isinstance(result, sp.MatrixBase):
        result = np.array(result.evalf(), dtype=float)
    try:
        array = np.asarray(result, dtype=float)
    except (TypeError, ValueError, OverflowError):
        if isinstance(result, tuple | list) and len(result) <= 10:
            return {"tuple": [encode(item) for item in result]}
        return {"garbage": _short(result)}
    if array.size > 100_000:
        return {"garbage": f"an array of shape {array.shape}"}
    return {"array": array.tolist(), "finite": bool(np.all(np.isfinite(array))),
            "shape": list(array.shape)}


def _short(value) -> str:
    """``repr(value)``, short, and never failing (a student's object may raise)."""
    try:
        return repr(value)[:200]
    except BaseException:
        return f"an object of type {type(value).__name__}"


def compare_symbolic(result, reference: str) -> str:
    """``"equal"`` when ``result - reference`` simplifies to zero, else ``"different"``."""
    import sympy as sp

    expected = sp.sympify(reference)
    got = sp.Matrix(result) if isinstance(expected, sp.MatrixBase) else result
    if isinstance(got, sp.MatrixBase) and got.shape != expected.shape:
        if 1 not in got.shape or len(got) != len(expected):
            return "different"
        got = got.reshape(*expected.shape)  # a vector given as a row or a column
    difference = sp.simplify(got - expected)
    zero = difference.is_zero_matrix if isinstance(difference, sp.MatrixBase) \
        else difference == 0
    return "equal" if zero else "different"


def _no_input(prompt=""):
    raise RuntimeError("input() waits for a keyboard, which a check has not: give the "
                       "value in the file")


def _display(*objects, **options):
    """Jupyter's ``display`` outside Jupyter: printed (and dropped, as all output)."""
    print(*objects)


def load(path: str) -> tuple[dict, str | None]:
    """Run the student's file (script or notebook); returns its namespace and the error
    that stopped it, if any. A notebook's cells run one by one; a failing cell is
    noted and the next ones still run. ``input()`` fails with its reason and
    ``display()`` works as in a notebook."""
    namespace = {"__name__": "student_exercise", "__file__": path, "input": _no_input,
                 "display": _display}
    with open(path, encoding="utf-8", errors="replace") as handle:
        text = handle.read()
    if path.endswith(".ipynb"):
        from .templates import notebook_code

        try:
            blocks = notebook_code(text)
        except (ValueError, AttributeError) as error:
            return namespace, f"not a readable notebook: {error}"
    else:
        blocks = [text]
    problems = []
    for number, block in enumerate(blocks, 1):
        try:
            exec(compile(block, path, "exec"), namespace)  # the student's own file
        except BaseException as error:
            if type(error).__name__ == "NotDone":
                continue
            cell = f"cell {number}: " if len(blocks) > 1 else ""
            problems.append(cell + _message(error, path))
    return namespace, "; ".join(problems) or None


def _track(namespace: dict, names: set) -> set:
    """Wrap the student's functions of the parts so that a call records which of them it
    used (for "part c fails and d uses it"); returns the set they are recorded in."""
    used: set = set()

    def tracked(name, function):
        def call(*args, **kwargs):
            used.add(name)
            return function(*args, **kwargs)
        return call

    for name in names:
        if callable(namespace.get(name)):
            namespace[name] = tracked(name, namespace[name])
    return used


def _returning(value):
    """A function of any arguments that returns a copy of ``value`` (a probe's stand-in
    for one of the student's functions)."""
    def stand_in(*args, **kwargs):
        return value.copy()
    return stand_in


def _channel(fd: int):
    """The results pipe moved to a descriptor the student's code is not told of."""
    moved = os.dup(fd)
    os.close(fd)
    return os.fdopen(moved, "w", encoding="utf-8")


def main(path: str, request: str) -> None:
    path = os.path.abspath(path)
    with open(request, encoding="utf-8") as handle:
        spec = json.load(handle)
    out = _channel(spec["channel"])

    def write(record):
        out.write(json.dumps(record) + "\n")
        out.flush()

    sys.stdout = sys.stderr = CappedOutput()
    # what the runner needs later is loaded before the student's code may load nothing
    from . import student  # noqa: F401 - the helper the templates import
    from .templates import notebook_code  # noqa: F401
    if spec.get("graded"):
        from .sandbox import confine

        confine(spec["scratch"])
    namespace, problem = load(path)
    write({"loaded": True, "problem": problem})
    used = _track(namespace, {call["function"] for call in spec["calls"]})
    for call in spec["calls"]:
        write({"id": call["id"], "started": True})
        used.clear()
        function = namespace.get(call["function"])
        if not callable(function):
            write({"id": call["id"], "missing": True})
            continue
        saved = {name: namespace.get(name) for name in call.get("substitutes", {})}
        try:
            for name, value in call.get("substitutes", {}).items():
                namespace[name] = _returning(decode(value))
            result = function(*[decode(a) for a in call["args"]])
            record = encode(result)
            if call.get("reference") and "sympy" in record:
                record["symbolic"] = compare_symbolic(result, call["reference"])
        except BaseException as error:
            if type(error).__name__ == "NotDone":
                record = {"not_done": str(error)}
            else:
                record = {"error": _message(error, path)}
        finally:
            namespace.update(saved)
        record["uses"] = sorted(used - {call["function"]})
        write({"id": call["id"], **record})
    out.close()


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    main(*sys.argv[1:3])
