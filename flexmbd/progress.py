"""Progress bars for long runs (tqdm when wanted, silent otherwise)."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np

#: runs of at least this many output points or steps show a bar when ``progress=None``
AUTO_THRESHOLD = 2000


@contextmanager
def progress_bar(times: np.ndarray, description: str, enabled: bool | None = None,
                 work: int | None = None) -> Iterator[Callable[[float], None] | None]:
    """Yield ``advance(t)``, which moves a bar over ``[times[0], times[-1]]`` to time ``t``
    [s], or ``None`` when no bar is shown.

    ``enabled=None`` shows a bar for long runs (``work``, default the number of
    output times, of at least :data:`AUTO_THRESHOLD`) on an interactive terminal
    only, so that scripts, tests and CI logs stay clean.
    """
    if enabled is None:
        enabled = max(work or 0, len(times)) >= AUTO_THRESHOLD and sys.stderr.isatty()
    if not enabled or len(times) < 2:
        yield None
        return
    from tqdm import tqdm

    start, span = float(times[0]), float(times[-1] - times[0])
    bar = tqdm(total=1000, desc=description, unit="‰", leave=False)

    def advance(t: float) -> None:
        done = min(1000, int(1000 * (t - start) / span))
        if done > bar.n:
            bar.update(done - bar.n)

    try:
        yield advance
    finally:
        bar.close()
