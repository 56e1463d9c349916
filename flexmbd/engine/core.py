"""The compiled core, loaded: the one module that imports its binding (``_core.pyx``).

The package imports without the core (so that ``python -m flexmbd.engine.codegen`` can
make the kernels the core is built from); what needs it asks :func:`check_core` first,
which names what is missing. :data:`native` is the binding, typed by ``_core.pyi``; the
workspace (:mod:`flexmbd.engine.workspace`) is the only code that calls it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..elements import ELEMENT_TYPES

_MISSING = ""
if TYPE_CHECKING:
    from . import _core as native
    from ._core import RunStatus  # noqa: F401 - what a run ends with, for annotations
else:
    try:
        from . import _core as native
    except ImportError as error:  # no fallback: the core is the engine (see check_core)
        native, _MISSING = None, str(error)


def check_core() -> None:
    """Refuse to run without the compiled core, or on kernels compiled for other element
    types than the package's.

    Raises:
        ImportError: the core is not built, or built for other element types.
    """
    if native is None:
        raise ImportError(
            f"flexmbd's compiled core (flexmbd.engine._core) is not built or cannot be loaded "
            f"({_MISSING}); install flexmbd with `pip install -e .` from its folder, "
            f"which compiles it (needs a C compiler and the Python headers)")
    if tuple(ELEMENT_TYPES) != native.KEYWORDS:
        raise ImportError(
            f"flexmbd's compiled core has the element types {native.KEYWORDS}, the package "
            f"{tuple(ELEMENT_TYPES)}: regenerate the kernels (python -m "
            f"flexmbd.engine.codegen) and reinstall (pip install -e .)")


#: the failure of a single evaluation of the core (the binding's own class)
CoreError: type[Exception] = native.CoreError if native is not None else RuntimeError
#: the core's description of itself, e.g. ``"C, gcc -O3 ..."`` (``flexmbd --version``)
CORE_BUILD = native.BUILD if native is not None else "not built"
#: each element type's number in the core (its kernels' order)
TYPE_NUMBER = {cls: k for k, cls in enumerate(ELEMENT_TYPES.values())}
