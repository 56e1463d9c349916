"""Parameter studies: :func:`sweep` runs a grid of cases on Dask (a local cluster by
default) and returns one table row per case; ``flexmbd sweep`` does it for a SPACAR file.

Dask, pandas, pyarrow and xarray come with ``pip install 'flexmbd[dask]'``; nothing
here imports them before a study runs. The grid helpers load alone (a command's option
parser uses them); the study machinery loads on first use of its names.
"""

from .grid import cases, parse_values

__all__ = ["ANALYSES", "STATISTICS", "cases", "parse_values", "sweep"]

#: names loaded on first use, by module
_LAZY = {"case": ("ANALYSES", "STATISTICS"), "sweep": ("sweep",)}


def __getattr__(name: str):
    import importlib

    for module, names in _LAZY.items():
        if name in names:
            # kept here, in place of the submodule of the same name the import binds
            value = globals()[name] = getattr(importlib.import_module(f".{module}", __name__),
                                              name)
            return value
    raise AttributeError(f"module 'flexmbd.studies' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
