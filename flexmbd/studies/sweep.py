"""Parameter studies: every case of a grid built, analysed and reduced to a table row, on a
Dask cluster (local by default) or in this process."""

from __future__ import annotations

import os
from collections.abc import Callable
from importlib.util import find_spec
from pathlib import Path
from typing import Any

from ..errors import ArgumentError, OptionalDependencyError
from ..io.outputs import check_output
from .case import ANALYSES, Study, check_outputs
from .grid import cases as grid_cases
from .grid import check_name
from .runner import check_client, run_cases
from .store import Journal, history_columns, table


def sweep(build, grid, analysis, outputs, client=None, *,
          out: str | os.PathLike | None = None, restart: bool = False,
          progress: bool | None = None):
    """Run a parameter study: one analysis per case of ``grid``, one table row per case.

    Args:
        build: ``build(**parameters)`` returning a :class:`~flexmbd.Model` or a ``(model,
            settings)`` pair; or the path of a SPACAR file, whose values the parameters
            name as ``KEYWORD:NUMBER...:POSITION`` (``"ESTIFF:2:2"`` is EI of element 2;
            see :class:`~flexmbd.io.dat.parameters.DatTemplate`).
        grid: ``{name: values}`` for every combination, or a list of ``{name: value}``
            cases.
        analysis: a function of the model returning a result (``lambda model:
            fm.simulate(model, times)``), or one of ``"auto"`` (the file's dynamics,
            else kinematics), ``"kinematic"``, ``"dynamic"``, ``"inverse"`` (over the
            file's TIMESTEP), ``"static"``, ``"modes"``, ``"buckling"`` (at the file's
            equilibrium).
        outputs: what to keep of each result: ``{name: function of the result}`` (a
            number is a metric, a 1-D array a history), or result columns (``"x5.1"``, a
            history) and statistics of them (``"absmax:e2.2"``; also initial, final, max,
            min, mean, rms), each its own name. Modes keep ``f1 .. f6`` [Hz].
        client: ``None`` for a local Dask cluster with one single-threaded worker
            process per core, started and stopped here; a ``dask.distributed.Client`` or
            a scheduler address (``"tcp://host:8786"``) to run on that cluster;
            ``"serial"`` to run in this process, without Dask.
        out: a ``.parquet`` file written as cases finish. When it holds cases of the
            same study (an interrupted run), only the missing cases run.
        restart: discard what ``out`` holds and run every case.
        progress: a bar with the cases done, failed and remaining (``None``: on a
            terminal only).

    Returns:
        A pandas DataFrame, one row per case in grid order: ``case``, the parameters,
        the metrics, ``status`` (``"ok"`` or ``"failed"``), ``error`` (the message of a
        failed case) and ``wall_time`` [s]. When histories are kept, an xarray Dataset
        instead: the same columns along ``case`` and each history along ``(case,
        step)``, NaN-padded to the longest.

    A case that fails is a row with its message, never a failed study. On an
    interrupt, what finished is written to ``out`` before ``KeyboardInterrupt`` is
    raised again (with the table so far as its ``partial_result``).

    Raises:
        ArgumentError: a grid, analysis, output, file or parameter name that cannot
            work, before any case runs.
        OptionalDependencyError: pandas, pyarrow or Dask missing: ``pip install
            'flexmbd[dask]'``.

    Examples:
        A truss spring's static stretch under a load, for two stiffnesses, in this
        process:

        >>> import flexmbd as fm
        >>> def spring(EA):
        ...     return (fm.ModelBuilder("spring").add_node(1, 0, 0).add_node(2, 1, 0)
        ...             .add_truss(1, 1, 2).dynamic_deformation(1)
        ...             .set_stiffness(1, axial=EA).fix(1).fix(2, "y").build())
        >>> table = fm.sweep(spring, {"EA": [100.0, 200.0]},
        ...                  lambda model: fm.static_equilibrium(model, loads={"x2.1": 1.0}),
        ...                  {"stretch": lambda statics: statics["e1.1"][-1]},
        ...                  client="serial", progress=False)
        >>> print([round(float(s), 4) for s in table["stretch"]])
        [0.01, 0.005]
    """
    _require("pandas", "study tables")
    cases = grid_cases(grid)
    outputs = check_outputs(outputs)
    for name in outputs:
        check_name(name, "outputs")
        if name in cases[0]:
            raise ArgumentError("outputs", f"{name!r} is also a parameter; name it otherwise")
    build = _check_build(build, cases)
    if not (callable(analysis) or analysis in ANALYSES):
        raise ArgumentError("analysis", f"must be a function of the model or one of "
                                        f"{', '.join(ANALYSES)}, got {analysis!r}")
    journal = None
    if out is not None:
        check_output(out, "study", "out")
        journal = Journal(out, cases, list(outputs))
        if restart:
            journal.discard()
    check_client(client)
    study = Study(build, analysis, outputs)
    rows = journal.load() if journal else []
    finished = {row["case"] for row in rows}
    pending = [(k, case) for k, case in enumerate(cases) if k not in finished]

    def record(row: dict) -> None:
        rows.append(row)
        if journal:
            journal.add(row)

    try:
        run_cases(study, pending, client, record, progress, len(cases), len(rows))
    except BaseException as stop:
        if journal:
            journal.close(rows)
        if isinstance(stop, KeyboardInterrupt):  # Ctrl-C carries the table so far
            stop.partial_result = _result(rows, list(outputs))  # type: ignore[attr-defined]
        raise
    if journal:
        journal.close(rows)
    return _result(rows, list(outputs))


def _require(module: str, what: str) -> None:
    if not find_spec(module):
        raise OptionalDependencyError(f"sweep: {what} need {module}: pip install "
                                      f"'flexmbd[dask]'")


def _check_build(build, cases: list[dict]) -> Callable:
    """``build`` as a callable; a SPACAR file (a path or its template) checked against the
    cases before any runs: every parameter name located, every value a number."""
    from ..io.dat.parameters import DatTemplate

    if isinstance(build, (str, os.PathLike)):
        build = DatTemplate.read(Path(build))
    if isinstance(build, DatTemplate):
        build.check(cases)
    elif not callable(build):
        raise ArgumentError("build", f"must be a function returning a model or the path of a "
                                     f"SPACAR file, got {type(build).__name__}")
    return build


def _result(rows: list[dict], outputs: list[str]):
    """The study's DataFrame, or its xarray Dataset when histories were kept."""
    frame = table(rows, outputs)
    histories = history_columns(frame, outputs)
    if not histories:
        return frame
    _require("xarray", "histories")
    import numpy as np
    import xarray as xr

    steps = max(len(v) for name in histories for v in frame[name])
    variables: dict[str, Any] = {}
    for name in histories:
        padded = np.full((len(frame), steps), np.nan)
        for k, values in enumerate(frame[name]):
            padded[k, :len(values)] = values
        variables[name] = (("case", "step"), padded)
    scalars = frame.drop(columns=histories)
    for name in scalars.columns.drop("case"):
        variables[name] = ("case", scalars[name].to_numpy())
    return xr.Dataset(variables, coords={"case": scalars["case"].to_numpy()})
