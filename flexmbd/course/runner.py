"""The checker's child process: load a student's file and call its parts.

Run as ``python -m flexmbd.course.runner FILE REQUEST RESULTS`` by
:mod:`flexmbd.course.check`, never by users. ``REQUEST`` is a JSON file of calls
(function name, encoded arguments, optionally a SymPy reference); each call's outcome
is appended to ``RESULTS`` as one JSON line, with a ``started`` line before it, so the
parent knows which call hung when the time limit ends the process. The student's
output goes nowhere: results travel only through ``RESULTS``, so a file that prints
garbage cannot confuse the checker.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys
import traceback

import numpy as np


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
    """A result as JSON: ``{"array", "shape"}``, ``{"tuple"}``, ``{"sympy"}`` or
    ``{"garbage"}`` for anything that is not numbers."""
    try:
        import sympy as sp
    except ImportError:  # pragma: no cover - sympy is a dependency of the course extra
        sp = None
    if sp is not None and isinstance(result, sp.Basic | sp.MatrixBase) \
            and getattr(result, "free_symbols", None):
        return {"sympy": sp.srepr(result)}
    if sp is not None and isinstance(result, sp.MatrixBase):
        result = np.array(result.evalf(), dtype=float)
    try:
        array = np.asarray(result, dtype=float)
    except (TypeError, ValueError):
        if isinstance(result, tuple | list) and len(result) <= 10:
            return {"tuple": [encode(item) for item in result]}
        return {"garbage": repr(result)[:200]}
    if array.size > 100_000:
        return {"garbage": f"an array of shape {array.shape}"}
    return {"array": np.where(np.isfinite(array), array, 0.0).tolist(),
            "finite": bool(np.all(np.isfinite(array))), "shape": list(array.shape)}


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


def load(path: str) -> tuple[dict, str | None]:
    """Run the student's file (script or notebook); returns its namespace and the error
    that stopped it, if any. A notebook's cells run one by one; a failing cell is
    noted and the next ones still run."""
    namespace = {"__name__": "student_exercise", "__file__": path}
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


def main(path: str, request: str, results: str) -> None:
    path = os.path.abspath(path)
    with open(request, encoding="utf-8") as handle:
        calls = json.load(handle)["calls"]
    out = open(results, "a", encoding="utf-8")  # noqa: SIM115 - written call by call

    def write(record):
        out.write(json.dumps(record) + "\n")
        out.flush()

    sink = io.StringIO()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        namespace, problem = load(path)
        write({"loaded": True, "problem": problem})
        for call in calls:
            write({"id": call["id"], "started": True})
            function = namespace.get(call["function"])
            if not callable(function):
                write({"id": call["id"], "missing": True})
                continue
            try:
                result = function(*[decode(a) for a in call["args"]])
                record = encode(result)
                if call.get("reference") and "sympy" in record:
                    record["symbolic"] = compare_symbolic(result, call["reference"])
            except BaseException as error:
                if type(error).__name__ == "NotDone":
                    record = {"not_done": str(error)}
                else:
                    record = {"error": _message(error, path)}
            sink.seek(0)
            sink.truncate()
            write({"id": call["id"], **record})
    out.close()


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    main(*sys.argv[1:4])
