# The compiled core (_core.pyx, a Cython binding of csrc/), as type checkers see it: every
# name the binding defines, with the types its memoryviews take (C-contiguous float64, or
# int32 where noted). Kept with the binding: a name missing here is a call mypy refuses.
from collections.abc import Callable
from enum import IntEnum
from typing import TypedDict

import numpy as np
import numpy.typing as npt

from .spec import CoreSpec

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int32]

class FmStatus(IntEnum):
    """The statuses of csrc/core.h's enum FmStatus (their one definition)."""

    FM_OK = 0
    FM_NOT_CONVERGED = 1
    FM_SINGULAR = 2
    FM_SINGULAR_TOLERANCE = 3
    FM_MASSLESS = 4
    FM_NOT_FINITE = 5
    FM_STEP_FAILED = 6
    FM_PYTHON = 7
    FM_NO_MEMORY = 8
    FM_PARTITION = 9
    FM_STEP_TOO_SMALL = 10

class FmLawKind(IntEnum):
    """How an entry of q moves in a run: csrc/core.h's enum FmLawKind."""

    FM_LAW_POLYNOMIAL = 0
    FM_LAW_CALLBACK = 1
    FM_LAW_INTEGRATED = 2

class RunStatus(TypedDict):
    """What a run, or a failed evaluation (``CoreError.args[0]``), ends with."""

    reached: int
    code: FmStatus
    time: float
    iterations: int
    residual: float
    worst: int
    conditioning: float
    limit: float
    step: float
    nfev: int
    njev: int
    nlu: int
    nsteps: int
    nrejected: int
    exception: BaseException | None

class CoreError(RuntimeError):
    args: tuple[RunStatus]

KEYWORDS: tuple[str, ...]
KERNEL_SIZES: tuple[tuple[int, int, int], ...]
DEFINITIONS_HASH: str
BUILD: str
OUTPUTS: tuple[str, ...]
FIELDS: tuple[str, ...]

class Core:
    def __init__(self, spec: CoreSpec) -> None: ...
    def settings(self, tolerance: float, max_iterations: int, regularity_limit: float,
                 reference_conditioning: float) -> None: ...
    def bands(self) -> dict[str, int]: ...
    def prepare(self, law_kind: Ints, law_coef: Floats, outputs: dict[str, Floats],
                n_outputs: int, dynamics: bool, law_callback: Callable[[float], None] | None = ...,
                law_values: Floats | None = ..., forces: Callable[[float], None] | None = ...,
                force_x: Floats | None = ..., force_xd: Floats | None = ...,
                force_f: Floats | None = ..., progress: Callable[[float], None] | None = ...
                ) -> None: ...
    def reset(self, start: Floats | None = ...) -> None: ...
    def kinematic_run(self, times: Floats) -> RunStatus: ...
    def alpha_run(self, times: Floats, q0: Floats, v0: Floats, *, step: float, rho_inf: float,
                  rtol: float, atol: float, iterations: int, renew_every: int, adaptive: bool,
                  max_step: float, near: float,
                  watch: Ints | None = ..., end: Floats | None = ...) -> RunStatus: ...
    def accelerations(self, t: float, y: Floats, out: Floats) -> None: ...
    def residual(self, t: float, y: Floats, a: Floats, r: Floats) -> None: ...
    def correction(self, c_q: float, c_v: float, r: Floats, da: Floats) -> None: ...
    def output(self, k: int, t: float, y: Floats) -> None: ...
    def state(self, t: float, q: Floats, qd: Floats, qdd: Floats, guess: Floats, x: Floats,
              xd: Floats, xdd: Floats, e: Floats, ed: Floats, edd: Floats) -> None: ...
    def equilibrium(self, t: float, q: Floats, qd: Floats, qdd: Floats, guess: Floats,
                    loads: Floats, outputs: dict[str, Floats]) -> None: ...
    def mass_matrix(self, x: Floats, xd: Floats, M: Floats, h: Floats, f: Floats) -> None: ...
    def masses(self, x: Floats, M: Floats) -> None: ...
    def element_values(self, name: str, x: Floats, out: Floats) -> None: ...
    def gravity_slopes(self, x: Floats, out: Floats) -> None: ...
    def inertia_slopes(self, x: Floats, q: Floats, qd: Floats, qdd: Floats, step: Floats,
                       rates: bool, out: Floats) -> None: ...
    def factor(self, x: Floats) -> float: ...
    def solve(self, rhs: Floats, transposed: bool) -> None: ...
    def static_saddle(self, x: Floats, q: Floats, mu: Floats, loads: Floats,
                      r: Floats) -> None: ...
    def static_solve(self, rhs: Floats, transposed: bool = ...) -> None: ...
    def mass_regular(self, x: Floats) -> bool: ...
    def free_mass_times(self, v: Floats, out: Floats) -> None: ...
    def configuration(self, x: Floats) -> None: ...

def csv_write(fd: int, columns: list[Floats]) -> None: ...
def format_17g(x: float) -> str: ...
def kernel(type: int, name: str, c: Floats, p: Floats, v: Floats | None, g: Floats | None,
           out: Floats) -> None: ...
def banded_lu(a: Floats, kl: int, ku: int, rhs: Floats, how: str = ...
              ) -> tuple[int, Ints, Floats, float, float]: ...
