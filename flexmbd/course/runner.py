"""The child process of a check: it runs one student's file and calls its parts.

Started by :mod:`flexmbd.course.launch`, never by users, as ``python -I runner.py``: in a
graded run inside the operating-system sandbox (:mod:`flexmbd.course.sandbox`), where
nothing of flexmbd exists but this file and the helper the templates import
(:mod:`flexmbd.course.student`). So it imports nothing of flexmbd, only the standard
library and NumPy (SymPy when an answer is an expression), both imported once the import path of the
request is set.

The protocol, all of it on the standard streams:

* stdin: one JSON line, the *header* (the file's name and size in bytes, the calls, the
  limits, the import path), then the file's bytes. The runner writes the file into its
  working folder (the scratch folder) and closes stdin.
* stdout: one JSON record per line: ``{"loaded"}`` when the file has run, then per call a
  ``{"id", "started"}`` line and its outcome, and ``{"printing"}`` now and then while the
  file prints a lot. The runner moves stdout to a private descriptor and points
  descriptors 1 and 2 at ``/dev/null`` before the student's code runs; what the file prints
  is counted and dropped.

A call carries no answer: every reference stays in the grader, which compares. A SymPy
answer comes back as a tree of its operations (:func:`sympy_tree`), which the grader
rebuilds from a fixed list of operations without evaluating any text.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import resource
import sys
import traceback

#: what a student's file may print before the rest is dropped [characters]
OUTPUT_CAP = 20_000
#: the largest header the runner reads [bytes]
HEADER_CAP = 16 * 2**20
#: the largest answer sent back [entries of an array]; larger ones are reported, not sent
ANSWER_CAP = 100_000
#: the most nodes of a SymPy answer's tree
SYMPY_NODES = 20_000


class CappedOutput(io.TextIOBase):
    """A ``sys.stdout`` that keeps the first :data:`OUTPUT_CAP` characters, counts the rest
    and drops it at once: printing in a loop costs the student's process, not the check.
    Each time the count doubles past a megabyte, ``report(count)`` is told."""

    def __init__(self, report=None) -> None:
        self.kept: list[str] = []
        self.size = 0
        self.total = 0
        self._report = report
        self._next = 2**20

    def writable(self) -> bool:
        return True

    def write(self, text) -> int:
        text = str(text)
        if self.size < OUTPUT_CAP:
            self.kept.append(text[:OUTPUT_CAP - self.size])
            self.size += len(self.kept[-1])
        self.total += len(text)
        if self.total >= self._next and self._report is not None:
            self._next = 2 * self.total
            self._report(self.total)
        return len(text)


def decode(value):
    """An argument from its JSON form (numbers, ``{"array": ...}``, ``{"symbol": name}``,
    ``{"symbols": [names]}``)."""
    if isinstance(value, dict):
        if "array" in value:
            import numpy as np

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


def _kind(error: BaseException) -> str:
    """The built-in exception an error is (NumPy's ``_ArrayMemoryError`` is a
    ``MemoryError``; a student's own exception class is an ``Exception``)."""
    for kind in type(error).__mro__:
        if kind.__module__ == "builtins":
            return kind.__name__
    return "BaseException"


def sympy_tree(expression, budget: int = SYMPY_NODES) -> dict:
    """A SymPy expression or matrix as a tree of plain data: ``{"s": name}`` a symbol,
    ``{"i": digits}`` an integer, ``{"q": [p, q]}`` a rational, ``{"f": value}`` a float,
    ``{"c": name}`` a constant (``Pi``, ``Exp1``, ``ImaginaryUnit``), ``{"o": operation,
    "a": [arguments]}`` the rest, ``{"matrix": shape, "entries": [...]}`` a matrix (row
    by row).

    Raises:
        ValueError: more than ``budget`` nodes.
    """
    import sympy as sp

    count = 0

    def node(e):
        nonlocal count
        count += 1
        if count > budget:
            raise ValueError(f"an expression of more than {budget} terms")
        if e.is_Symbol:
            return {"s": e.name}
        if e.is_Integer:
            return {"i": str(int(e))}
        if e.is_Rational:
            return {"q": [str(e.p), str(e.q)]}
        if e.is_Float:
            return {"f": float(e)}
        if e.is_NumberSymbol or e is sp.I:
            return {"c": type(e).__name__}
        return {"o": type(e).__name__, "a": [node(a) for a in e.args]}

    if isinstance(expression, sp.MatrixBase):
        return {"matrix": list(expression.shape), "entries": [node(e) for e in expression]}
    return node(sp.sympify(expression))


def _dtype(result) -> str | None:
    """The precision of an answer made of NumPy arrays of less than double precision."""
    items = result if isinstance(result, tuple | list) else (result,)
    for item in items:
        dtype = getattr(item, "dtype", None)
        if dtype is not None and dtype.kind == "f" and dtype.itemsize < 8:
            return str(dtype)
    return None


def encode(result) -> dict:
    """A result as JSON: ``{"array", "shape"}`` (NaN and infinities kept, with ``"dtype"``
    when it is of single precision), ``{"tuple"}``, ``{"sympy"}`` (an expression with free
    symbols, :func:`sympy_tree`), ``{"none"}`` or ``{"garbage"}`` for anything else."""
    import numpy as np

    if result is None:
        return {"none": True}
    sp = sys.modules.get("sympy")   # an answer in SymPy was made with an imported SymPy
    if sp is not None and isinstance(result, sp.Basic | sp.MatrixBase) \
            and getattr(result, "free_symbols", None):
        try:
            return {"sympy": sympy_tree(result)}
        except (ValueError, RecursionError, AttributeError) as error:
            return {"garbage": f"a SymPy expression that cannot be sent ({error})"}
    if sp is not None and isinstance(result, sp.MatrixBase):
        result = np.array(result.evalf(), dtype=float)
    precision = _dtype(result)
    try:
        array = np.asarray(result, dtype=float)
    except (TypeError, ValueError, OverflowError):
        if isinstance(result, tuple | list) and len(result) <= 10:
            return {"tuple": [encode(item) for item in result]}
        return {"garbage": _short(result)}
    if array.size > ANSWER_CAP:
        return {"garbage": f"an array of shape {array.shape}"}
    return {"array": array.tolist(), "shape": list(array.shape),
            **({"dtype": precision} if precision else {})}


def _short(value) -> str:
    """``repr(value)``, short, and never failing (a student's object may raise)."""
    try:
        return repr(value)[:200]
    except BaseException:
        return f"an object of type {type(value).__name__}"


def _no_input(prompt=""):
    raise RuntimeError("input() waits for a keyboard, which a check has not: give the "
                       "value in the file")


def _display(*objects, **options):
    """Jupyter's ``display`` outside Jupyter: printed (and dropped, as all output)."""
    print(*objects)


def notebook_code(text: str) -> list[str]:
    """The code cells of a notebook's JSON ``text``; IPython magics and shell lines
    (``%``, ``!``) are dropped. Raises ``ValueError`` for text that is not a notebook."""
    data = json.loads(text)
    out = []
    for cell in data.get("cells", []):
        if cell.get("cell_type") != "code":
            continue
        source = cell.get("source", "")
        source = "".join(source) if isinstance(source, list) else str(source)
        out.append("\n".join(line for line in source.splitlines()
                             if not line.lstrip().startswith(("%", "!"))))
    return out


def load(path: str) -> tuple[dict, str | None]:
    """Run the student's file (script or notebook); returns its namespace and the error
    that stopped it, if any. The file is read as UTF-8 with or without a byte-order mark
    (as Python reads a script). A notebook's cells run one by one; a failing cell is
    noted and the next ones still run. ``input()`` fails with its reason and
    ``display()`` works as in a notebook."""
    namespace = {"__name__": "student_exercise", "__file__": path, "input": _no_input,
                 "display": _display}
    with open(path, encoding="utf-8-sig", errors="replace") as handle:
        text = handle.read()
    if path.endswith(".ipynb"):
        try:
            blocks = notebook_code(text)
        except (ValueError, AttributeError, TypeError) as error:
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


def limit(limits: dict) -> None:
    """Lower this process's limits for good (a process cannot raise a hard limit again):
    ``memory`` (address space) and ``file_size`` [bytes], ``cpu`` [s] (a second of grace
    between the signal and the kill), ``processes``; no core dumps."""
    wanted = [(resource.RLIMIT_CORE, 0, 0)]
    if limits.get("memory"):
        wanted.append((resource.RLIMIT_AS, limits["memory"], limits["memory"]))
    if limits.get("file_size"):
        wanted.append((resource.RLIMIT_FSIZE, limits["file_size"], limits["file_size"]))
    if limits.get("cpu"):
        wanted.append((resource.RLIMIT_CPU, int(limits["cpu"]), int(limits["cpu"]) + 1))
    if limits.get("processes"):
        wanted.append((resource.RLIMIT_NPROC, limits["processes"], limits["processes"]))
    for kind, soft, hard in wanted:
        _, current = resource.getrlimit(kind)
        if current != resource.RLIM_INFINITY:
            soft, hard = min(soft, current), min(hard, current)
        resource.setrlimit(kind, (soft, hard))


def _read_request() -> tuple[dict, bytes]:
    """The header and the file's bytes from stdin; stdin is then ``/dev/null``."""
    stream = sys.stdin.buffer
    header = json.loads(stream.readline(HEADER_CAP))
    content = stream.read(int(header["size"]))
    null = os.open(os.devnull, os.O_RDONLY)
    os.dup2(null, 0)
    os.close(null)
    return header, content


def _channel():
    """The results channel: stdout moved to a private descriptor; descriptors 1 and 2 then
    lead to ``/dev/null``, so that nothing the student's code writes reaches the grader
    by accident."""
    moved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    os.close(null)
    return os.fdopen(moved, "w", encoding="utf-8")


def main() -> None:
    # nothing inherited beyond the standard streams reaches the student's code
    os.closerange(3, 65536)
    header, content = _read_request()
    name = os.path.basename(str(header["file"]))
    path = os.path.abspath(name)
    with open(path, "wb") as handle:
        handle.write(content)
    out = _channel()

    def write(record):
        out.write(json.dumps(record) + "\n")
        out.flush()

    printed = CappedOutput(lambda count: write({"printing": count}))
    sys.stdout = sys.stderr = printed
    sys.path[:0] = [str(p) for p in header.get("path", [])]
    if header.get("limits"):
        limit(header["limits"])
    if header.get("confine") == "audit-hook":   # --unsafe-in-process only
        from flexmbd.course.inprocess import confine

        # SciPy loads its shared libraries through ctypes, which the hook refuses later
        for module in ("numpy", "scipy"):
            with contextlib.suppress(ImportError):
                __import__(module)

        confine(os.getcwd())
    namespace, problem = load(path)
    write({"loaded": True, "problem": problem, "printed": printed.total})
    calls = header["calls"]
    used = _track(namespace, {call["function"] for call in calls})
    for call in calls:
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
            record = encode(function(*[decode(a) for a in call["args"]]))
        except BaseException as error:
            if type(error).__name__ == "NotDone":
                record = {"not_done": str(error)}
            else:
                record = {"error": _message(error, path), "kind": _kind(error)}
        finally:
            namespace.update(saved)
        record["uses"] = sorted(used - {call["function"]})
        write({"id": call["id"], **record, "printed": printed.total})
    out.close()


if __name__ == "__main__":
    # run as a script: its own folder is not a place to import from
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path[:] = [p for p in sys.path if os.path.abspath(p or ".") != here]
    os.environ.setdefault("MPLBACKEND", "Agg")
    main()
