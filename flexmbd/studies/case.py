"""One case of a parameter study: build the model, analyse it, keep the outputs.

This is what runs on a worker. It never raises: whatever goes wrong (a model that
cannot be built, an analysis that fails or stops early, an output that cannot be
computed) becomes the case's status and error message, so that one bad case never
stops a study.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import ArgumentError, FlexmbdError
from ..model import Model
from ..settings import RunSettings

#: the analyses a study names by a string (else ``analysis`` is a function of the model)
ANALYSES = ("auto", "kinematic", "dynamic", "inverse", "static", "modes", "buckling")
#: modes and buckling loads a named ``"modes"`` or ``"buckling"`` analysis keeps
MODE_COUNT = 6
#: reductions of a history to one number, for outputs written ``"STAT:COLUMN"``
STATISTICS: dict[str, Callable[[np.ndarray], float]] = {
    "initial": lambda v: v[0],
    "final": lambda v: v[-1],
    "max": np.max,
    "min": np.min,
    "absmax": lambda v: np.max(np.abs(v)),
    "mean": np.mean,
    "rms": lambda v: np.sqrt(np.mean(np.square(v))),
}

Output = Callable[[object], object] | str


@dataclass(frozen=True)
class Study:
    """What every case of a study shares; sent to the workers with each case.

    Attributes:
        build: ``build(**parameters)`` returning a :class:`~flexmbd.Model`, or a
            ``(model, settings)`` pair such as :func:`~flexmbd.read_dat` returns.
        analysis: a function of the model returning a result, or one of
            :data:`ANALYSES`, run with the settings of the build.
        outputs: ``{name: output}``; an output is a function of the result returning a
            number (a metric) or a 1-D array (a history), a result column ``"x5.1"``
            (a history) or ``"STAT:COLUMN"`` with a STAT of :data:`STATISTICS` (a metric).
            A named modes analysis has the columns ``f1 .. f6`` [Hz], buckling
            ``lambda1 .. lambda6``.
    """

    build: Callable[..., object]
    analysis: Callable[[Model], object] | str
    outputs: Mapping[str, Output]

    def run(self, index: int, parameters: dict[str, object]) -> dict[str, object]:
        """The row of case ``index``: ``case``, the parameters, the outputs, ``status``
        (``"ok"`` or ``"failed"``), ``error`` (``""`` when ok) and ``wall_time`` [s]."""
        start = time.perf_counter()
        values: dict[str, object] = dict.fromkeys(self.outputs, math.nan)
        status, error = "ok", ""
        try:
            result = self._analyse(parameters)
        except Exception as failure:  # every failure is the case's result
            status, error = "failed", describe(failure)
        else:
            if getattr(result, "success", True) is False:
                status, error = "failed", f"analysis: {getattr(result, 'message', 'failed')}"
            for name, output in self.outputs.items():
                try:
                    values[name] = evaluate(output, result, name)
                except Exception as failure:
                    if status == "ok":  # the first failure is the one to read
                        status, error = "failed", f"output {name!r}: {describe(failure)}"
        return {"case": index, **parameters, **values, "status": status, "error": error,
                "wall_time": time.perf_counter() - start}

    def _analyse(self, parameters: dict[str, object]):
        try:
            built = self.build(**parameters)
        except Exception as failure:
            raise _StageError("build", failure) from failure
        model, settings = split_build(built)
        try:
            if callable(self.analysis):
                return self.analysis(model)
            return named_analysis(self.analysis, model, settings)
        except Exception as failure:
            raise _StageError("analysis", failure) from failure


class _StageError(Exception):
    """A failure of one stage of a case (``build``, ``analysis``)."""

    def __init__(self, stage: str, failure: BaseException):
        super().__init__(f"{stage}: {describe(failure)}")


def describe(failure: BaseException) -> str:
    """A failure as one line: flexmbd's own messages as they are, others with their type."""
    if isinstance(failure, (FlexmbdError, _StageError)):
        text = str(failure)
    else:
        text = f"{type(failure).__name__}: {failure}".rstrip(": ")
    return " ".join(text.split())


def split_build(built) -> tuple[Model, RunSettings]:
    """The model and settings of what a build returned.

    Raises:
        ArgumentError: neither a model nor a ``(model, settings)`` pair.
    """
    if isinstance(built, Model):
        return built, RunSettings()
    if isinstance(built, tuple) and len(built) == 2 and isinstance(built[0], Model) \
            and isinstance(built[1], RunSettings):
        return built
    raise _StageError("build", ArgumentError("build", f"must return a Model or a (model, settings) "
                                                 f"pair, returned {type(built).__name__}"))


def named_analysis(name: str, model: Model, settings: RunSettings):
    """Run the analysis ``name`` of :data:`ANALYSES` as ``flexmbd run`` and the linearized
    commands do, with the file's settings; failures are returned, not raised."""
    from ..analysis.runs import analyse, check_mode, default_mode

    if name in ("static", "modes", "buckling"):
        from ..analysis.statics import file_equilibrium

        statics = file_equilibrium(model, settings)
        if name == "static" or not statics.success:
            return statics
        from ..analysis.modes import buckling, vibration_modes

        found = {"modes": vibration_modes, "buckling": buckling}[name]
        return found(statics.linearization(), min(MODE_COUNT, len(model.dynamic_q_labels)))
    mode = default_mode(model) if name == "auto" else name
    check_mode(model, mode)
    times = settings.output_times()
    if times is None:
        raise ArgumentError("analysis", f"a {mode} analysis needs output times: the file has "
                                        f"no TIMESTEP line; add one, or give the analysis as "
                                        f"a function, e.g. lambda model: fm.simulate(model, "
                                        f"times)")
    return analyse(model, settings, mode, times)


def evaluate(output: Output, result, name: str) -> float | np.ndarray:
    """The value of one output on a result: a float (metric) or a float array ``(n,)``
    (history)."""
    if callable(output):
        value = output(result)
    else:
        statistic, _, column = output.rpartition(":")
        value = _column(result, column)
        if statistic:
            value = np.asarray(value, dtype=float)
            if value.size == 0:
                raise ArgumentError(name, "the analysis computed no rows")
            value = STATISTICS[statistic](value)
    array = np.asarray(value, dtype=float)
    if array.ndim == 0:
        return float(array)
    if array.ndim == 1:
        return array
    raise ArgumentError(name, f"an output is a number or a 1-D array, got shape {array.shape}")


def _column(result, name: str):
    """A column of a result by name; a modes result has ``f1 ..`` [Hz], a buckling result
    ``lambda1 ..``."""
    for attribute, prefix in (("frequencies", "f"), ("factors", "lambda")):
        values = getattr(result, attribute, None)
        if values is not None and not hasattr(result, "columns"):
            k = name.removeprefix(prefix)
            if name.startswith(prefix) and k.isdigit() and 1 <= int(k) <= len(values):
                return values[int(k) - 1]
            raise ArgumentError(name, f"the result has {prefix}1 .. {prefix}{len(values)}")
    return result[name]


def check_outputs(outputs) -> dict[str, Output]:
    """Outputs as ``{name: output}``: a mapping as given, or a list of column names and
    ``"STAT:COLUMN"`` strings, each its own name.

    Raises:
        ArgumentError: an output that is neither a function nor a string, an unknown STAT.
    """
    if isinstance(outputs, str):
        outputs = [outputs]
    if not isinstance(outputs, Mapping):
        try:
            outputs = {name: name for name in outputs}
        except TypeError:
            raise ArgumentError("outputs", f"must be a mapping {{name: output}} or a list of "
                                           f"columns, got {type(outputs).__name__}") from None
    if not outputs:
        raise ArgumentError("outputs", "name at least one output to keep")
    for name, output in outputs.items():
        if callable(output):
            continue
        if not isinstance(output, str):
            raise ArgumentError("outputs", f"{name!r}: an output is a function of the result "
                                           f"or a column name, got {output!r}")
        statistic, colon, _ = output.rpartition(":")
        if colon and statistic not in STATISTICS:
            raise ArgumentError("outputs", f"{output!r}: {statistic!r} is not one of "
                                           f"{', '.join(STATISTICS)}")
    return dict(outputs)
