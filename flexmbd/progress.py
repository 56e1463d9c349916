"""Progress of long runs: a tqdm bar on a terminal, a line every so often in a log."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np

from .checks import flag

#: runs of at least this many output points or steps show a bar when ``progress=None``
AUTO_THRESHOLD = 2000
#: seconds between the progress lines written when stderr is not a terminal (a log file)
LOG_INTERVAL = 10.0


@contextmanager
def progress_bar(times: np.ndarray, description: str, enabled: bool | None = None,
                 work: int | None = None) -> Iterator[Callable[[float], None] | None]:
    """Yield ``advance(t)``, which reports progress over ``[times[0], times[-1]]`` up to time
    ``t`` [s], or ``None`` when nothing is reported.

    ``enabled=None`` shows a bar for long runs (``work``, default the number of
    output times, of at least :data:`AUTO_THRESHOLD`) on an interactive terminal
    only, so that scripts, tests and CI logs stay clean. ``enabled=True`` reports
    every run: a bar on a terminal; where stderr is not a terminal (a log file) a
    line every :data:`LOG_INTERVAL` seconds, so a long run never looks like a hang.
    """
    enabled = flag(enabled, "progress", allow_none=True)
    terminal = sys.stderr.isatty()
    if enabled is None:
        enabled = max(work or 0, len(times)) >= AUTO_THRESHOLD and terminal
    if not enabled or len(times) < 2:
        yield None
        return
    start, span = float(times[0]), float(times[-1] - times[0])
    if not terminal:
        yield _log_lines(description, start, span)
        return
    from tqdm import tqdm

    bar = tqdm(total=1000, desc=description, unit="‰", leave=False)

    def advance(t: float) -> None:
        done = min(1000, int(1000 * (t - start) / span))
        if done > bar.n:
            bar.update(done - bar.n)

    try:
        yield advance
    finally:
        bar.close()


def _log_lines(description: str, start: float, span: float) -> Callable[[float], None]:
    """``advance(t)`` writing ``description: 42 % (t = 1.2 s), 30 s elapsed`` to stderr at
    most every :data:`LOG_INTERVAL` seconds."""
    began = time.monotonic()
    last = began

    def advance(t: float) -> None:
        nonlocal last
        now = time.monotonic()
        if now - last >= LOG_INTERVAL:
            last = now
            print(f"{description}: {100 * (t - start) / span:.0f} % (t = {t:.6g} s), "
                  f"{now - began:.0f} s elapsed", file=sys.stderr, flush=True)

    return advance


@contextmanager
def case_counter(total: int, done: int, enabled: bool | None = None,
                 description: str = "sweep") -> Iterator[Callable[[bool], None]]:
    """Yield ``finished(ok)``, to be called as each case of a study finishes, which shows
    the cases done, failed and remaining out of ``total`` (``done`` of them finished
    before, in an earlier run).

    ``enabled=None`` shows a bar on an interactive terminal only; ``enabled=True`` also
    writes a line every :data:`LOG_INTERVAL` seconds where stderr is not a terminal.
    """
    enabled = flag(enabled, "progress", allow_none=True)
    terminal = sys.stderr.isatty()
    counts = {"done": done, "failed": 0}

    def line() -> str:
        return (f"{counts['done']} of {total} cases done, {counts['failed']} failed, "
                f"{total - counts['done']} remaining")

    if not (terminal if enabled is None else enabled):
        yield lambda ok: None
        return
    if not terminal:
        last = time.monotonic()

        def finished(ok: bool) -> None:
            nonlocal last
            counts["done"] += 1
            counts["failed"] += not ok
            if time.monotonic() - last >= LOG_INTERVAL or counts["done"] == total:
                last = time.monotonic()
                print(f"{description}: {line()}", file=sys.stderr, flush=True)
        yield finished
        return
    from tqdm import tqdm

    bar = tqdm(total=total, initial=done, desc=description, unit="case", leave=False)

    def advance_bar(ok: bool) -> None:
        counts["failed"] += not ok
        bar.set_postfix(failed=counts["failed"], refresh=False)
        bar.update(1)

    try:
        yield advance_bar
    finally:
        bar.close()
