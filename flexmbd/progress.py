"""Progress bars for long runs (tqdm when installed and wanted, silent otherwise)."""

from __future__ import annotations

import sys
from contextlib import contextmanager

#: runs with at least this many output points show a bar when ``progress=None``
AUTO_THRESHOLD = 2000


@contextmanager
def progress_bar(total: int, description: str, enabled: bool | None = None):
    """Yield an object with ``update(n)``; a tqdm bar when enabled.

    ``enabled=None`` shows a bar for long runs on an interactive terminal only,
    so that scripts, tests and CI logs stay clean.
    """
    if enabled is None:
        enabled = total >= AUTO_THRESHOLD and sys.stderr.isatty()
    bar = None
    if enabled:
        try:
            from tqdm import tqdm
        except ImportError:  # tqdm is a core dependency, but a bar is never essential
            bar = None
        else:
            bar = tqdm(total=total, desc=description, unit="step", leave=False)
    try:
        yield bar if bar is not None else _Silent()
    finally:
        if bar is not None:
            bar.close()


class _Silent:
    def update(self, n: int = 1) -> None:
        pass
