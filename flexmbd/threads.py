"""Keep BLAS single-threaded for the many small solves of a run.

The matrices of a planar mechanism are small; a multi-threaded BLAS spends
more time waking its threads than solving. Measured on the 2-core machine
with the flexible slider-crank (2 beams, RK45): 10 % slower on 2 OpenBLAS
threads than on 1 when idle, 2.5 times slower while another process was busy.
"""

from __future__ import annotations

from contextlib import contextmanager

#: models with more coordinates than this keep the BLAS threads
SMALL_MODEL = 400


@contextmanager
def blas_threads_for(n_coordinates: int):
    """Limit BLAS to one thread while a run over a small model is under way."""
    if n_coordinates > SMALL_MODEL:
        yield
        return
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # a core dependency, but never essential
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield
