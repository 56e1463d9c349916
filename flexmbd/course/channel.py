"""The channel a child's records come back on, read strictly and timed.

The runner (:mod:`flexmbd.course.runner`) writes one JSON record per line. Here each line
is parsed and checked against the protocol (:func:`parse`): a line that is not a
well-formed record, an integer of more digits than any answer has, a line longer than
:data:`LINE_CAP` or a channel longer than :data:`CHANNEL_CAP` is the failure of the call
it came in, never the grader's. :func:`follow` reads the records as they come and stops a
run whose part has used its time, its CPU time for a metered run (all its processes,
:mod:`flexmbd.course.usage`), or whose processes hold more memory than allowed.
"""

from __future__ import annotations

import json
import os
import select
import time
from dataclasses import dataclass, field

from . import usage

#: bytes a runner may send before the check stops reading it (a forged flood)
CHANNEL_CAP = 64 * 2**20
#: the longest line of the channel [bytes]
LINE_CAP = 16 * 2**20

@dataclass(frozen=True)
class Stop:
    """Why a process stopped in a call: ``reason`` (time, memory, killed, error) and what
    happened, in words."""

    reason: str
    words: str


@dataclass
class Outcome:
    """What the runs of one file gave: the records by call id, the load problem, and per
    call that stopped its process why, and how much the file had printed by then."""

    records: dict = field(default_factory=dict)
    problem: str | None = None
    load_stop: Stop | None = None
    loaded: bool = False
    stopped: dict = field(default_factory=dict)
    printed: dict = field(default_factory=dict)


def _bounded_int(text: str) -> int:
    if len(text.lstrip("-")) > 30:
        raise ValueError("an integer of more than 30 digits")
    return int(text)


#: the fields a record may have, and their types
_FIELDS: dict[str, type | tuple[type, ...]] = {
    "id": int, "started": bool, "loaded": bool, "problem": (str, type(None)), "printed": int,
    "printing": int, "missing": bool, "none": bool, "not_done": str, "error": str,
    "kind": str, "garbage": str, "array": (list, float, int), "shape": list, "dtype": str,
    "tuple": list, "sympy": dict, "uses": list}


def parse(line: bytes) -> dict | None:
    """A record of the channel, or ``None`` for anything that is not one."""
    try:
        record = json.loads(line, parse_int=_bounded_int)
    except (ValueError, RecursionError, UnicodeDecodeError):
        return None
    if not isinstance(record, dict) or not record:
        return None
    for key, value in record.items():
        kind = _FIELDS.get(key)
        if kind is None or not isinstance(value, kind) or \
                (kind is int and isinstance(value, bool)):
            return None
    if not all(isinstance(u, str) for u in record.get("uses", [])):
        return None
    return record


#: how often a metered run's memory and CPU time are read [s]
POLL = 0.05
#: a metered part's wall-clock limit, in times its CPU time limit (a part that waits
#: without computing, sleeping or blocked, uses no CPU time)
WALL_FACTOR = 3.0


class Meter:
    """The time a run is charged and what it holds: the CPU time [s] and resident memory
    [bytes] of the process tree of ``pid`` (:mod:`flexmbd.course.usage`), or, for a run
    that is not metered, the wall clock."""

    def __init__(self, pid: int | None) -> None:
        self.pid = pid

    def read(self) -> tuple[float, float, int]:
        """(charged time, wall time, resident memory)."""
        wall = time.monotonic()
        if self.pid is None:
            return wall, wall, 0
        resident, cpu = usage.usage(self.pid)
        return cpu, wall, resident


def follow(read: int, calls: list[dict], part_of: dict, timeout: float,
            outcome: Outcome, meter: Meter,
            memory: int | None) -> tuple[int | None, str, Stop | None]:
    """Read the runner's records as they come, ending the run when the call running has
    used its part's time (its CPU time, for a metered run, within a wall-clock limit of
    :data:`WALL_FACTOR` times that) or the run holds more than ``memory`` bytes. Returns
    the call that stopped the run early (or ``None``), how (``"stopped"``, ``"ended"``:
    the channel closed or overflowed, or ``"done"``) and why it was stopped."""
    metered = meter.pid is not None
    wall_limit = timeout * (WALL_FACTOR if metered else 1.0)
    expected = iter(calls)
    current = None        # the call running, after its "started" record
    spent: dict = {}      # (charged, wall) seconds each part has run; None: loading
    printed = 0           # characters the file has printed so far
    segment = meter.read()
    buffer, total = b"", 0

    def close_segment(key):
        nonlocal segment
        now = meter.read()
        charged, wall = spent.get(key, (0.0, 0.0))
        spent[key] = (charged + now[0] - segment[0], wall + now[1] - segment[1])
        segment = now

    def stopping(stop: Stop) -> tuple[int | None, str, Stop]:
        nonlocal current
        if current is None and outcome.loaded:   # between calls: the next one is charged
            current = next(expected, {"id": None})["id"]
        if current is not None:
            outcome.printed[current] = printed
        return current, "stopped", stop

    while True:
        key = part_of[current] if current is not None else None
        now = meter.read()
        charged, wall = spent.get(key, (0.0, 0.0))
        charged, wall = charged + now[0] - segment[0], wall + now[1] - segment[1]
        if memory is not None and now[2] > memory:
            return stopping(Stop("memory", f"its processes held more than "
                                           f"{memory / 2**30:g} GB of memory together"))
        if metered and charged >= timeout:
            return stopping(Stop("time", f"its processes used {timeout:g} s of CPU time"))
        if wall >= wall_limit:
            return stopping(Stop("time", f"it waited {wall_limit:g} s without finishing"
                                 if metered else ""))
        wait = min(wall_limit - wall, POLL) if metered else wall_limit - wall
        ready, _, _ = select.select([read], [], [], max(wait, 0.0))
        if not ready:
            continue
        chunk = os.read(read, 65536)
        total += len(chunk)
        if not chunk or total > CHANNEL_CAP or len(buffer) > LINE_CAP:
            if not outcome.loaded:
                return None, "ended", None
            if current is None:
                following = next(expected, None)
                if following is None:
                    return None, "done", None
                current = following["id"]
            outcome.printed[current] = printed
            return current, "ended", None
        buffer += chunk
        *lines, buffer = buffer.split(b"\n")
        for line in lines:
            record = parse(line)
            if record is None:
                if current is not None:   # a forged or broken line: this call's failure
                    outcome.records[current] = {"malformed": True}
                continue
            if "printing" in record:
                printed = max(printed, record["printing"])
            elif "loaded" in record and not outcome.loaded:
                outcome.loaded = True
                problem = record.get("problem")
                outcome.problem = str(problem) if problem else None
                segment, spent[None] = meter.read(), (0.0, 0.0)
            elif record.get("started") and current is None:
                following = next(expected, None)
                if following is None or record.get("id") != following["id"]:
                    continue  # not the call that comes next: not the runner's
                close_segment(None)
                spent[None] = (0.0, 0.0)
                current = following["id"]
            elif current is not None and record.get("id") == current:
                close_segment(part_of[current])
                outcome.records.setdefault(current, record)
                outcome.printed[current] = printed
                current = None
