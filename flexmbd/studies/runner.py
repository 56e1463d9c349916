"""Running the cases of a study, in this process or as futures on a Dask cluster, each
row recorded as it finishes."""

from __future__ import annotations

import math
import uuid
from collections.abc import Callable
from importlib.util import find_spec

from ..errors import ArgumentError, OptionalDependencyError
from ..progress import case_counter
from .case import describe
from .cluster import check_main_guard, connected

__all__ = ["check_client", "run_cases"]


def check_client(client) -> None:
    """Refuse a ``client`` that is none of ``None`` (a new local cluster), ``"serial"``, a
    scheduler address or a ``dask.distributed.Client``; and a new local cluster started
    from a script's top level without the ``__main__`` guard.

    Raises:
        ArgumentError: either.
    """
    if not (client is None or client == "serial" or isinstance(client, str) or
            hasattr(client, "submit")):
        raise ArgumentError("client", f"must be None, 'serial', a scheduler address or a "
                                      f"dask.distributed.Client, got {client!r}")
    if client is None:
        check_main_guard()


def run_cases(study, pending: list[tuple[int, dict]], client, record: Callable[[dict], None],
              progress: bool | None, total: int, done: int = 0) -> None:
    """Run the ``pending`` cases ``(index, parameters)`` of ``study`` (anything with
    ``run(index, parameters) -> row`` and ``outputs``, sent to the workers) in this
    process (``client="serial"``) or on Dask, and ``record`` each row (a dict with
    ``status``) as it finishes, under a bar counting ``total`` cases, ``done`` of them
    before."""
    with case_counter(total, done, progress) as counted:
        def keep(row: dict) -> None:
            record(row)
            counted(row["status"] == "ok")

        if not pending:
            return
        if client == "serial":
            for index, case in pending:
                keep(study.run(index, case))
        else:
            _on_dask(study, pending, keep, client)


def _on_dask(study, pending: list[tuple[int, dict]], record, client) -> None:
    """Run the cases on Dask as futures and ``record`` each row as it finishes; a case
    whose worker died is recorded as failed. An interrupt cancels what has not run."""
    if not find_spec("distributed"):
        raise OptionalDependencyError("studies on Dask need distributed: pip install "
                                      "'flexmbd[dask]'")
    from dask.distributed import as_completed

    with connected(client) as client:
        shared = client.scatter(study, broadcast=True)  # sent once, not with every case
        token = uuid.uuid4().hex[:8]
        futures = {client.submit(_run, shared, index, case, key=f"flexmbd-{token}-{index}",
                                 pure=False): (index, case) for index, case in pending}
        try:
            for future in as_completed(futures):
                try:
                    row = future.result()
                except Exception as failure:  # a lost worker fails its case
                    index, case = futures[future]
                    row = {"case": index, **case, **dict.fromkeys(study.outputs, math.nan),
                           "status": "failed", "error": f"worker: {describe(failure)}",
                           "wall_time": math.nan}
                record(row)
                future.release()
        finally:
            client.cancel(list(futures))


def _run(study, index: int, case: dict) -> dict:
    """One case on a worker."""
    return study.run(index, case)
