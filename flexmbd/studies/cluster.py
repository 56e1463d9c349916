"""The Dask cluster a study runs on: a new local one, or one the user gives."""

from __future__ import annotations

import ast
import logging
import os
import sys
import types
from contextlib import contextmanager
from pathlib import Path

from ..errors import ArgumentError
from .case import describe

#: seconds to wait for a scheduler given by address before giving up
CONNECT_TIMEOUT = 20.0


@contextmanager
def connected(client):
    """Yield a ``dask.distributed.Client``: ``client`` itself, one connected to the
    scheduler address ``client``, or (``None``) one of a new local cluster of one
    single-threaded worker process per core. What is opened here is closed here."""
    from dask.distributed import Client

    if client is not None and not isinstance(client, str):
        yield client
        return
    if client is None:
        own = local_client()
    else:
        try:
            own = Client(client, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as error:
            raise ArgumentError("scheduler", f"cannot reach {client!r}: {describe(error)}"
                                ) from None
    try:
        yield own
    finally:
        cluster = own.cluster
        own.close()
        if cluster is not None:
            cluster.close()


def local_client():
    """A client of a new local cluster: one single-threaded worker process per core, quiet
    logs; the scheduler's web server on a free port (the usual 8787 may be another
    cluster's)."""
    from dask.distributed import Client, LocalCluster

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    cluster = LocalCluster(n_workers=cores or 1, threads_per_worker=1, processes=True,
                           dashboard_address=":0", silence_logs=logging.ERROR)
    return Client(cluster)


def check_main_guard() -> None:
    """Refuse to start worker processes from the top level of a script that lacks ``if
    __name__ == "__main__":``: each worker process imports the script again, which would
    start the study again inside it (Python then fails with a long traceback per worker).

    Raises:
        ArgumentError: the study is started by a top-level statement of the script that
            is not under the guard.
    """
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if main is None or path is None:
        return  # an interactive session, a notebook, python -c: nothing is imported again
    frame: types.FrameType | None = sys._getframe(1)
    while frame is not None and frame.f_globals is not vars(main):
        frame = frame.f_back
    if frame is None or frame.f_code.co_name != "<module>":
        return
    try:
        tree = ast.parse(Path(path).read_text())
    except (OSError, SyntaxError, ValueError):
        return
    line = frame.f_lineno
    for statement in tree.body:
        if statement.lineno <= line <= (statement.end_lineno or statement.lineno):
            guarded = isinstance(statement, ast.If) and any(
                isinstance(node, ast.Name) and node.id == "__name__"
                for node in ast.walk(statement.test))
            if not guarded:
                raise ArgumentError("client", f"{Path(path).name}, line {line}: a study on a "
                                              f"local cluster starts worker processes, which "
                                              f"import this script again; put the study under "
                                              f'if __name__ == "__main__": (or pass '
                                              f"client='serial' to run it in this process)")
            return
