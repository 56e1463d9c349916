"""The table of a study in a Parquet file, written as cases finish and read back to resume.

While a study runs, finished cases go to small Parquet files in ``NAME.partial/`` next
to the table, each written whole and then renamed into place, so a study killed at
any moment loses at most the cases of the last second. When the study ends (also by
an interrupt or an error) everything is written to ``NAME`` and the parts are
removed. A later run with the same file reads both and runs only the cases missing.

Histories (outputs that are arrays) are list columns; metrics are float columns.
"""

from __future__ import annotations

import math
import os
import shutil
import time
from pathlib import Path

import numpy as np

from ..errors import ArgumentError
from .grid import RESERVED

#: seconds between the part files of finished cases (the first case is written at once)
FLUSH_INTERVAL = 1.0


def table(rows: list[dict], outputs: list[str]):
    """Rows as a pandas DataFrame sorted by case; a history output's cells are float
    arrays, empty where the case kept none."""
    import pandas as pd

    frame = pd.DataFrame(sorted(rows, key=lambda row: row["case"]))
    for name in history_columns(frame, outputs):
        frame[name] = [np.asarray(v, dtype=float) if isinstance(v, (np.ndarray, list))
                       else np.zeros(0) for v in frame[name]]
    return frame.reset_index(drop=True)


def history_columns(frame, outputs: list[str]) -> list[str]:
    """The outputs that are histories: a column where some case kept an array."""
    return [name for name in outputs if name in frame and
            any(isinstance(v, (np.ndarray, list)) for v in frame[name])]


class Journal:
    """The finished cases of a study at ``path`` (a ``.parquet`` file).

    Args:
        path: the table's file.
        cases: the study's cases, ``{name: value}`` each, in order.
        outputs: the study's output names.
    """

    def __init__(self, path: str | os.PathLike, cases: list[dict], outputs: list[str]):
        self.path = Path(path)
        self.parts = self.path.with_name(self.path.name + ".partial")
        self.cases, self.outputs = cases, outputs
        self.pending: list[dict] = []
        # the first finished case goes to disk at once: a study killed early shows it ran
        self.last_flush = -math.inf

    def discard(self) -> None:
        """Forget an earlier run: remove the table and its parts."""
        self.path.unlink(missing_ok=True)
        shutil.rmtree(self.parts, ignore_errors=True)

    def load(self) -> list[dict]:
        """The rows an earlier run finished, checked to belong to this study.

        Raises:
            ArgumentError: the file holds a study of other parameters or outputs, or is
                not a study table.
        """
        import pandas as pd

        files = ([self.path] if self.path.exists() else []) + sorted(self.parts.glob("*.parquet"))
        frames = []
        for file in files:
            try:
                frames.append((file, pd.read_parquet(file)))
            except Exception as error:  # any unreadable file is refused alike
                raise ArgumentError("out", f"{str(file)!r} is not a readable Parquet table "
                                           f"({type(error).__name__}); give another file or "
                                           f"restart") from None
        rows = {}
        for file, frame in frames:
            self._check_columns(frame, file)
            for row in frame.to_dict("records"):
                rows[int(row["case"])] = self._check_row(row)
        return list(rows.values())

    def _check_columns(self, frame, file: Path) -> None:
        parameters = list(self.cases[0])
        expected = {*RESERVED, *parameters, *self.outputs}
        if set(frame.columns) != expected:
            raise ArgumentError("out", f"{str(file)!r} holds a study with the columns "
                                       f"{sorted(frame.columns)}, this one has "
                                       f"{sorted(expected)}; give another file, or restart "
                                       f"to overwrite it")

    def _check_row(self, row: dict) -> dict:
        index = int(row["case"])
        case = self.cases[index] if 0 <= index < len(self.cases) else None
        if case is None or any(_stored(row[name]) != value for name, value in case.items()):
            stored = {name: _stored(row[name]) for name in self.cases[0]}
            raise ArgumentError("out", f"{str(self.path)!r} holds case {index} with {stored}, "
                                       f"this study's case {index} is {case}; give another "
                                       f"file, or restart to overwrite it")
        return {**row, "case": index, **{name: _stored(row[name]) for name in case}}

    def add(self, row: dict) -> None:
        """Keep a finished case; written at the next :meth:`flush`."""
        self.pending.append(row)
        if time.monotonic() - self.last_flush >= FLUSH_INTERVAL:
            self.flush()

    def flush(self) -> None:
        """Write the pending cases as one part file."""
        if not self.pending:
            return
        self.parts.mkdir(exist_ok=True)
        first = min(row["case"] for row in self.pending)
        _write(table(self.pending, self.outputs),
               self.parts / f"part-{time.time_ns()}-{first}.parquet")
        self.pending, self.last_flush = [], time.monotonic()

    def close(self, rows: list[dict]) -> None:
        """Write all ``rows`` (earlier and new) to the table and remove the parts; with no
        rows (a study stopped before its first case), write nothing."""
        if rows:
            _write(table(rows, self.outputs), self.path)
        self.pending = []
        shutil.rmtree(self.parts, ignore_errors=True)


def _stored(value):
    """A value read back from Parquet as the plain Python scalar it was written as."""
    return value.item() if isinstance(value, np.generic) else value


def _write(frame, path: Path) -> None:
    """Write ``frame`` to ``path`` whole or not at all."""
    partial = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    frame.to_parquet(partial, index=False)
    os.replace(partial, path)
