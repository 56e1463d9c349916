"""What a sandbox's processes use together, read from ``/proc``: their resident memory and
their CPU time.

A graded file may start processes, and a process that detaches (``setsid``, a double
fork) stays in the tree of the sandbox's first process, whose init adopts it. The tree's
CPU time is what the file's parts are charged (so a file that keeps both cores busy with
processes does not make a classmate's parts run out of time), and its resident memory is
held to the sandbox's memory limit (a limit per process alone would let every one of 64
processes take it).
"""

from __future__ import annotations

import os
from pathlib import Path

#: clock ticks per second and bytes per page, as /proc counts them
TICK = os.sysconf("SC_CLK_TCK")
PAGE = os.sysconf("SC_PAGE_SIZE")


def available() -> bool:
    """Whether this kernel lists each thread's children (``CONFIG_PROC_CHILDREN``): a tree
    is then measured whole; without it, runs are timed by the wall clock."""
    return os.path.exists(f"/proc/self/task/{os.getpid()}/children")


def _stat(pid: int) -> list[str] | None:
    """The fields of ``/proc/PID/stat`` after the command name, or ``None``."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text.rpartition(")")[2].split()


def tree(pid: int) -> list[int]:
    """``pid`` and every process below it (the children of each of its threads)."""
    found, pending = [], [pid]
    while pending:
        current = pending.pop()
        found.append(current)
        try:
            tasks = os.listdir(f"/proc/{current}/task")
        except OSError:
            continue
        for task in tasks:
            try:
                children = Path(f"/proc/{current}/task/{task}/children").read_text()
            except OSError:
                continue
            pending += [int(child) for child in children.split()]
    return found


def usage(pid: int) -> tuple[int, float]:
    """The resident memory [bytes] and CPU time [s] of the tree of ``pid``: its live and
    ended processes (an ended process counts in the one that reaped it)."""
    resident, ticks = 0, 0
    for member in tree(pid):
        fields = _stat(member)
        if fields is None or len(fields) < 22:
            continue
        # fields 14-17 of stat(5): utime, stime, cutime, cstime; 24: rss (pages)
        ticks += sum(int(value) for value in fields[11:15])
        resident += int(fields[21]) * PAGE
    return resident, ticks / TICK
