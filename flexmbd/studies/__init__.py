"""Parameter studies: :func:`sweep` runs a grid of cases on Dask (a local cluster by
default) and returns one table row per case; ``flexmbd sweep`` does it for a SPACAR file.

Dask, pandas, pyarrow and xarray come with ``pip install 'flexmbd[dask]'``; nothing
here imports them before a study runs.
"""

from .case import ANALYSES, STATISTICS
from .grid import cases, parse_values
from .sweep import sweep

__all__ = ["ANALYSES", "STATISTICS", "cases", "parse_values", "sweep"]
