"""The byte layout of SPACAR's binary result files (``.sbd``, ``.sbm``, ``.ltv``).

A file is a sequence of records, little-endian. Each record starts with a 20-byte head: a
4-character name (space-padded), then four int32: the type (1 int32, 2 float64, 3
characters, 0 a marker), the size of one value in bytes, the rows and the columns. The
values follow, ``rows * cols`` of them, row after row.

* The first record names the file: ``"SBD "`` (or ``"SBM "``, ``"LTV "``), characters,
  holding e.g. ``"SBD version 0.0"``.
* Then the tables, records with their values.
* Then the marker ``TDEF`` (its rows: the number of stored steps), the heads of the
  per-step records without values, and the marker ``TDAT``.
* Then, for each step, the values of every per-step record in the order of their heads.

This module reads and writes that layout for any content; :mod:`.records` decides what a
flexmbd run puts in it.
"""

from __future__ import annotations

import os
import struct
import warnings
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import InputFileError, LabelError, ResultFileWarning

_HEAD = struct.Struct("<4s4i")
#: record types: code -> (numpy dtype, bytes per value)
_TYPES = {1: ("<i4", 4), 2: ("<f8", 8), 3: ("S1", 1)}
_MARKER = 0
#: the identification records SPACAR writes, by file kind
KINDS = {"SBD": "SBD version 0.0", "SBM": "SBM version 0.0", "LTV": "LTV version 0.0."}
#: largest rows, columns or steps a file may claim (a damaged or hostile file cannot make
#: the reader allocate more than the file holds: sizes are checked against the file length)
_LARGEST = 2**31 - 1


def record_key(name: str) -> str:
    """The record a name asks for, as SPACAR's ``getfrsbf`` matches it: case-insensitive,
    on its first four characters (``"nddof"`` is ``NDDO``)."""
    return name.strip().upper()[:4]


@dataclass(frozen=True, eq=False)
class SpacarFile(Mapping[str, np.ndarray]):
    """The records of a SPACAR binary result file (:func:`read_sbd`).

    A mapping from record name to values: ``f["LNP"]``, ``f["x"]``, ``f["nddof"]`` (names
    as SPACAR's ``getfrsbf`` takes them: any case, the first four characters count).

    Attributes:
        path: the file read (``None`` for one made in memory).
        kind: ``"SBD"``, ``"SBM"`` or ``"LTV"``.
        version: the file's identification text, e.g. ``"SBD version 0.0"``.
        tables: the records stored once, shape ``(rows, cols)`` as in the file (a count
            such as ``NX`` is ``(1, 1)``); int32 or float64.
        steps: the per-step records, shape ``(n_steps, rows, cols)``.
        n_steps: the number of stored steps.
    """

    path: Path | None
    kind: str
    version: str
    tables: Mapping[str, np.ndarray]
    steps: Mapping[str, np.ndarray] = field(default_factory=dict)
    n_steps: int = 0

    def __getitem__(self, name: str) -> np.ndarray:
        key = record_key(name)
        for group in (self.tables, self.steps):
            if key in group:
                return group[key]
        raise LabelError(f"{name!r}: {self.kind} file {self._where()}has no record {key!r} "
                         f"(it has {', '.join(self)})")

    def __iter__(self) -> Iterator[str]:
        yield from self.tables
        yield from self.steps

    def __len__(self) -> int:
        return len(self.tables) + len(self.steps)

    def step(self, name: str, k: int) -> np.ndarray:
        """Record ``name`` at step ``k`` (1-based, as ``getfrsbf(file, name, k)``),
        shape ``(rows, cols)``."""
        values = self[name]
        if record_key(name) not in self.steps:
            raise LabelError(f"{name!r} is a table of {self._where()}stored once, not per step")
        if not 1 <= k <= self.n_steps:
            raise LabelError(f"step {k} of {name!r}: {self._where()}has steps 1 .. "
                             f"{self.n_steps}")
        return values[k - 1]

    def _where(self) -> str:
        return f"{self.path} " if self.path is not None else ""

    def __repr__(self) -> str:
        return (f"<SpacarFile {self.kind} {self._where()}: {len(self.tables)} tables, "
                f"{len(self.steps)} records x {self.n_steps} steps>")


def read_records(path: str | os.PathLike) -> SpacarFile:
    """Read any SPACAR binary result file (``.sbd``, ``.sbm``, ``.ltv``).

    Raises:
        InputFileError: not such a file, or damaged; names the file, the byte offset and
            the record.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as error:
        raise InputFileError(f"cannot read: {error.strerror or error}", str(path)) from None
    return _parse(data, path)


def _parse(data: bytes, path: Path | None) -> SpacarFile:
    where = str(path) if path is not None else None

    def fail(offset: int, message: str) -> InputFileError:
        return InputFileError(f"byte {offset}: {message}", where)

    def head(offset: int) -> tuple[str, int, int, int, int]:
        if offset + _HEAD.size > len(data):
            raise fail(offset, f"the file ends inside a record head ({len(data)} bytes)")
        raw, kind, size, rows, cols = _HEAD.unpack_from(data, offset)
        try:
            name = raw.decode("ascii").strip()
        except UnicodeDecodeError:
            raise fail(offset, f"a record name must be 4 ASCII characters, got {raw!r}; "
                               f"not a SPACAR binary file") from None
        if kind != _MARKER:
            if kind not in _TYPES:
                raise fail(offset, f"record {name!r} has type {kind}; SPACAR's are 1 (int32), "
                                   f"2 (float64) and 3 (characters)")
            if size != _TYPES[kind][1]:
                raise fail(offset, f"record {name!r} of type {kind} must have {_TYPES[kind][1]}"
                                   f"-byte values, the file says {size}")
            if not (0 <= rows <= _LARGEST and 0 <= cols <= _LARGEST):
                raise fail(offset, f"record {name!r} claims {rows} x {cols} values")
        return name, kind, size, rows, cols

    def values(offset: int, name: str, kind: int, rows: int, cols: int) -> np.ndarray:
        end = offset + rows * cols * _TYPES[kind][1]
        if end > len(data):
            raise fail(offset, f"record {name!r} needs {end - offset} bytes of values, the "
                               f"file has {len(data) - offset} left")
        return np.frombuffer(data, _TYPES[kind][0], rows * cols, offset).reshape(rows, cols)

    if data[:4].decode("ascii", "replace").strip() not in KINDS:
        raise fail(0, f"starts with {data[:4]!r}, not SBD, SBM or LTV: not a SPACAR binary file")
    name, kind, _, rows, cols = head(0)
    if kind != 3:
        raise fail(0, f"starts with {data[:4]!r}, not SBD, SBM or LTV: not a SPACAR binary file")
    version = values(_HEAD.size, name, kind, rows, cols).tobytes().decode("ascii", "replace")
    offset = _HEAD.size + rows * cols
    tables: dict[str, np.ndarray] = {}
    steps: dict[str, np.ndarray] = {}
    n_steps = 0
    while offset < len(data):
        key, code, _, rows, cols = head(offset)
        if code == _MARKER:
            if key != "TDEF":
                raise fail(offset, f"marker {key!r} where TDEF or a table was expected")
            offset, n_steps, steps = _read_steps(data, offset + _HEAD.size, rows, head,
                                                 fail, where)
            continue
        tables[key] = values(offset + _HEAD.size, key, code, rows, cols).copy()
        offset += _HEAD.size + rows * cols * _TYPES[code][1]
    return SpacarFile(path, name, version, tables, steps, n_steps)


def _read_steps(data: bytes, offset: int, n_steps: int, head, fail, where: str | None
                ) -> tuple[int, int, dict[str, np.ndarray]]:
    """The heads after ``TDEF`` up to ``TDAT``, then ``n_steps`` blocks of their values
    (the whole ones, with a :class:`ResultFileWarning`, of a file that ends inside them):
    the offset after them, the steps read and the records."""
    heads = []
    while True:
        key, code, _, rows, cols = head(offset)
        offset += _HEAD.size
        if code == _MARKER:
            if key != "TDAT":
                raise fail(offset - _HEAD.size, f"marker {key!r} inside TDEF; TDAT expected")
            break
        if code != 2:
            raise fail(offset - _HEAD.size, f"per-step record {key!r} has type {code}; "
                                            f"SPACAR stores steps as float64 (type 2)")
        heads.append((key, rows, cols))
    per_step = sum(rows * cols for _, rows, cols in heads)
    need = n_steps * per_step * 8
    end = offset + need
    if end > len(data):
        complete = (len(data) - offset) // (per_step * 8) if per_step else 0
        if not complete:
            raise fail(offset, f"TDEF announces {n_steps} steps of {per_step} values "
                               f"({need} bytes); the file has {len(data) - offset} left, "
                               f"not one whole step")
        # a run stopped while writing: its whole steps are its result so far
        warnings.warn(f"{where or 'the file'}: TDEF announces {n_steps} steps, the file "
                      f"ends inside step {complete + 1}; read steps 1 .. {complete}",
                      ResultFileWarning, stacklevel=5)   # read_sbd's caller
        n_steps, need, end = complete, complete * per_step * 8, len(data)
    block = np.frombuffer(data, "<f8", n_steps * per_step, offset).reshape(n_steps, per_step)
    steps, column = {}, 0
    for key, rows, cols in heads:
        steps[key] = block[:, column:column + rows * cols].reshape(n_steps, rows, cols).copy()
        column += rows * cols
    return end, n_steps, steps


def write_records(path: str | os.PathLike, kind: str, tables: Mapping[str, np.ndarray],
                  steps: Mapping[str, np.ndarray] | None = None) -> Path:
    """Write a SPACAR binary result file.

    Args:
        path: the file to write.
        kind: ``"SBD"``, ``"SBM"`` or ``"LTV"``.
        tables: records stored once, name -> 2-D array (integer arrays are written as
            int32, others as float64).
        steps: per-step records, name -> ``(n_steps, rows, cols)`` float64, all with the same
            number of steps.
    """
    chunks = [_head(kind, 3, 1, len(KINDS[kind]), 1), KINDS[kind].encode("ascii")]
    for name, value in tables.items():
        array = np.asarray(value)
        if array.ndim != 2:
            raise ValueError(f"table {name!r} must be 2-D, got shape {array.shape}")
        integer = np.issubdtype(array.dtype, np.integer)
        chunks.append(_head(name, 1 if integer else 2, 4 if integer else 8, *array.shape))
        chunks.append(np.ascontiguousarray(array, "<i4" if integer else "<f8").tobytes())
    if steps:
        counts = {np.shape(v)[0] for v in steps.values()}
        if len(counts) != 1 or any(np.ndim(v) != 3 for v in steps.values()):
            raise ValueError("per-step records must be (n_steps, rows, cols) with one n_steps")
        n_steps = counts.pop()
        chunks.append(_head("TDEF", _MARKER, 0, n_steps, 1))
        chunks += [_head(name, 2, 8, *np.shape(v)[1:]) for name, v in steps.items()]
        chunks.append(_head("TDAT", _MARKER, 0, 0, 0))
        flat = [np.asarray(v, "<f8").reshape(n_steps, -1) for v in steps.values()]
        chunks.append(np.ascontiguousarray(np.hstack(flat)).tobytes())
    path = Path(path)
    path.write_bytes(b"".join(chunks))
    return path


def _head(name: str, kind: int, size: int, rows: int, cols: int) -> bytes:
    if len(name) > 4 or not name.isascii():
        raise ValueError(f"a record name is at most 4 ASCII characters, got {name!r}")
    return _HEAD.pack(name.ljust(4).encode("ascii"), kind, size, rows, cols)
