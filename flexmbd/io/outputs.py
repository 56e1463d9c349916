"""Output files checked before any computing: their type, their directory, the extra that
writes them. A run is never computed to be lost to a name that cannot be written."""

from __future__ import annotations

import os
import sys
from importlib.util import find_spec
from pathlib import Path

from ..errors import ArgumentError, OptionalDependencyError

#: file types by what they hold, with the module each needs and its pip extra
RESULT_TYPES = (".csv", ".npz", ".h5", ".hdf5", ".sbd")
PLOT_TYPES = (".png", ".pdf", ".svg", ".jpg")
MOVIE_TYPES = (".gif", ".mp4")
TABLE_TYPES = (".csv",)
#: the linearized equations of every load step, as SPACAR stores them
LINEAR_TYPES = (".csv", ".sbm")
MATRIX_TYPES = (".npz",)
STUDY_TYPES = (".parquet",)
TYPES = {"results": RESULT_TYPES, "plot": PLOT_TYPES, "movie": MOVIE_TYPES,
         "table": TABLE_TYPES, "linear": LINEAR_TYPES, "matrices": MATRIX_TYPES,
         "study": STUDY_TYPES,
         "table or study": TABLE_TYPES + STUDY_TYPES}
_NEEDS = {".h5": ("h5py", "hdf5", "write .csv or .npz"),
          ".hdf5": ("h5py", "hdf5", "write .csv or .npz"),
          ".mp4": ("imageio_ffmpeg", "movie", "save a .gif, which needs nothing extra"),
         ".parquet": ("pyarrow", "dask", None)}


def check_output(path: str | os.PathLike, what: str, option: str) -> Path:
    """Refuse an output file ``path`` holding ``what`` (a key of :data:`TYPES`: ``"results"``,
    ``"plot"``, ``"movie"``, ``"table"``, ...) that could not be written, naming the
    ``option`` that gave it.

    Raises:
        ArgumentError: a file type that is not one of :data:`TYPES` ``[what]``, a
            directory that does not exist or cannot be written, a path that is a
            directory or lies under a file.
        OptionalDependencyError: the type needs an extra that is not installed.
    """
    path = Path(path)
    types = TYPES[what]
    if path.suffix.lower() not in types:
        raise ArgumentError(option, f"{str(path)!r} must end in {', '.join(types)}")
    if path.is_dir():
        raise ArgumentError(option, f"{str(path)!r} is a directory; give a file name")
    directory = path.parent
    for above in (directory, *directory.parents):  # the first part of it that exists
        if above.exists():
            break
    if not above.is_dir():
        raise ArgumentError(option, f"cannot write {str(path)!r}: {str(above)!r} is a file, "
                            f"not a directory")
    if above != directory:
        raise ArgumentError(option, f"cannot write {str(path)!r}: the directory "
                            f"{str(directory)!r} does not exist")
    if not os.access(directory, os.W_OK | os.X_OK) or (path.exists() and
                                                        not os.access(path, os.W_OK)):
        raise ArgumentError(option, f"cannot write {str(path)!r}: permission denied")
    module, extra, instead = _NEEDS.get(path.suffix.lower(), (None, None, None))
    if module and not find_spec(module):
        raise OptionalDependencyError(f"{option} {path.name}: writing {path.suffix} needs "
                                      f"{module}: pip install 'flexmbd[{extra}]'" +
                                      (f" (or {instead})" if instead else ""))
    return path


#: matplotlib backends that draw into files only
_FILE_BACKENDS = {"agg", "pdf", "ps", "svg", "pgf", "cairo", "template"}


def check_display() -> None:
    """Refuse to open windows (``--show``) where none can open: no display on Linux, or a
    matplotlib backend that only writes files."""
    backend = os.environ.get("MPLBACKEND", "").lower()
    if backend in _FILE_BACKENDS or backend.startswith("module://matplotlib_inline"):
        raise ArgumentError("--show", f"the matplotlib backend {backend!r} cannot open "
                                      f"windows; save with --plot/--movie instead")
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or
                                                 os.environ.get("WAYLAND_DISPLAY")):
        raise ArgumentError("--show", "no display to open windows on (DISPLAY is not set); "
                                      "save with --plot/--movie instead")
