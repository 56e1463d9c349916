"""The exceptions of flexmbd.

Every error a user can cause is one of these, with a message that names the
nodes, elements, coordinates, time or input-file line involved. The command
line prints the message as one line and exits non-zero.
"""

from __future__ import annotations

from typing import Any


class FlexmbdError(Exception):
    """Base class of all flexmbd errors."""


class Problem(str):
    """One problem of a model, in words, and what it is about.

    ``about`` holds ``("node", number)``, ``("nodal mass", number)``, ``("element",
    number)``, ``("coordinate", label)`` or ``("deformation", label)`` pairs, so that a reader
    of an input file can point at the lines that made those entities.
    """

    about: tuple[tuple[str, object], ...]

    def __new__(cls, text: str, *about: tuple[str, object]) -> Problem:
        problem = super().__new__(cls, text)
        problem.about = about
        return problem


class ModelError(FlexmbdError, ValueError):
    """A model description is inconsistent.

    ``problems`` lists every problem found, one sentence each (a :class:`Problem`
    where the builder knows what it is about), so that a user can fix them all
    at once.
    """

    def __init__(self, problems: list[str] | str):
        self.problems = [problems] if isinstance(problems, str) else list(problems)
        if len(self.problems) == 1:
            text = f"invalid model: {self.problems[0]}"
        else:
            lines = "".join(f"\n  - {p}" for p in self.problems)
            text = f"invalid model, {len(self.problems)} problems:{lines}"
        super().__init__(text)


class SimulationError(FlexmbdError, RuntimeError):
    """An analysis could not continue at time ``time``.

    Runs over a time grid attach what was computed before the failure as
    ``partial_result`` (``None`` for a single-configuration solve).
    """

    def __init__(self, message: str, time: float | None = None):
        super().__init__(message)
        self.time = time
        self.partial_result: Any = None  # the result so far (flexmbd.results)


class StiffnessError(SimulationError):
    """An integrator of SciPy's is held to tiny steps by a fast mode that the outputs
    cannot show: the model is stiff for it; the message names the mode and the method
    that fits (generalized-alpha)."""


class ConvergenceError(SimulationError):
    """The Newton-Raphson position solve did not converge."""

    def __init__(self, message: str, time: float | None = None,
                 iterations: int = 0, residual: float = float("nan")):
        super().__init__(message, time)
        self.iterations = iterations
        self.residual = residual


class SingularConfigurationError(SimulationError):
    """The constraint Jacobian ``D_c`` is singular (e.g. a dead point)."""


class InputFileError(FlexmbdError, ValueError):
    """A SPACAR input file cannot be read; names the line and the reason."""

    def __init__(self, message: str, path: str | None = None, line: int | None = None):
        where = ""
        if path is not None:
            where = f"{path}:{line}: " if line is not None else f"{path}: "
        elif line is not None:
            where = f"line {line}: "
        super().__init__(where + message)
        self.path = path
        self.line = line


class ArgumentError(FlexmbdError, ValueError):
    """An argument of a function or an option of the command line cannot work; the message
    starts with its name (``argument``)."""

    def __init__(self, argument: str, message: str):
        super().__init__(f"{argument}: {message}")
        self.argument = argument


class UnstressedError(ArgumentError):
    """A state without stresses has no buckling load factor: no multiple of its loads
    makes it buckle."""


class LabelError(FlexmbdError, KeyError):
    """No coordinate, deformation or result column has that label; a ``KeyError``, so that
    look-ups behave like those of a mapping."""

    def __str__(self) -> str:  # KeyError would show the message in quotes
        return str(self.args[0]) if self.args else ""


class ColumnError(LabelError):
    """A result has no column of that name, or did not record it."""


class OptionalDependencyError(FlexmbdError, ImportError):
    """A feature needs an optional extra that is not installed; names the pip command."""


class OutputError(FlexmbdError, ValueError):
    """A result, figure or movie cannot be written as asked (e.g. an unknown file type)."""


class SandboxError(FlexmbdError, RuntimeError):
    """The operating-system sandbox that a graded run needs cannot be made here; names what
    is missing and what to do instead."""


class AnalysisWarning(UserWarning):
    """An analysis took another way than its default one (LAPACK where ARPACK could not
    tell the modes), or its result needs a caveat; the message says which and why."""


class AccuracyWarning(AnalysisWarning):
    """A setting that will cost accuracy the user may not expect: a fixed time step that
    resolves the model's lowest vibration period in too few steps (period elongation and
    numerical damping grow over the periods); the message names the setting that would
    do."""


class ModelWarning(UserWarning):
    """A model that builds but that some analysis will refuse: a degree of freedom that
    moves no mass in a model that has mass (a simulation or vibration modes need it; a
    static analysis does not)."""


class ResultFileWarning(UserWarning):
    """A result file read with a caveat: it ends inside its steps (a run interrupted while
    writing), and the complete steps were read; the message names the file and what was
    left out."""
