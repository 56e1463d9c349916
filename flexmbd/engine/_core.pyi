# The compiled core (_core.pyx, a Cython binding of csrc/), seen by type checkers.
from typing import Any

import numpy as np

from .spec import CoreSpec

# the statuses of csrc/core.h's enum FmStatus (an IntEnum made by Cython; one definition)
FmStatus: Any

class CoreError(RuntimeError): ...

KEYWORDS: tuple[str, ...]
KERNEL_SIZES: tuple[tuple[int, int, int], ...]
DEFINITIONS_HASH: str
BUILD: str
OUTPUTS: tuple[str, ...]
FIELDS: tuple[str, ...]

class Core:
    def __init__(self, spec: CoreSpec) -> None: ...
    def __getattr__(self, name: str) -> Any: ...

def csv_write(fd: int, columns: list[np.ndarray]) -> None: ...
def format_17g(x: float) -> str: ...
def kernel(type: int, name: str, c: np.ndarray, p: np.ndarray, v: np.ndarray | None,
           g: np.ndarray | None, out: np.ndarray) -> None: ...
