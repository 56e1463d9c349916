"""Run the numerical tests again under other OpenBLAS kernels than this CPU's own.

OpenBLAS picks its kernels by CPU, so round-off differs from machine to machine; a test
that depends on the sign or exact value of round-off passes on one and fails on another.
``OPENBLAS_CORETYPE`` forces other kernels on this machine: two that the CPU can run and
that differ from its own, run side by side. The tests that do not touch BLAS (the style
check, the documentation build, parameter studies on Dask, the fuzzing of file syntax,
the examples' movies, the grader's sandbox and class table) are left out.
"""

from __future__ import annotations

import os
import subprocess
import sys

#: kernels to try, in order, and the CPU flags each needs
KERNELS = {"Zen": ("avx2", "fma"), "Prescott": ("pni",), "Haswell": ("avx2", "fma"),
           "Sandybridge": ("avx",), "Nehalem": ("sse4_2",)}
LEFT_OUT = ("test_docs.py", "test_style.py", "test_sweep.py", "test_dat_fuzz.py",
            "test_examples.py", "test_sandbox.py", "test_grading.py")


def own_kernels() -> set[str]:
    import numpy  # noqa: F401  (loads the OpenBLAS that threadpoolctl reports)
    import scipy.linalg  # noqa: F401
    from threadpoolctl import threadpool_info

    return {info.get("architecture") for info in threadpool_info()
            if info.get("internal_api") == "openblas"}


def cpu_flags() -> set[str]:
    try:
        with open("/proc/cpuinfo") as info:
            for line in info:
                if line.startswith("flags"):
                    return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


def main() -> int:
    own, flags = own_kernels(), cpu_flags()
    if not own:
        print("blas variants: NumPy and SciPy do not use OpenBLAS here; nothing to vary")
        return 0
    chosen = [name for name, needs in KERNELS.items()
              if name not in own and all(flag in flags for flag in needs)][:2]
    ignore = [f"--ignore=tests/{name}" for name in LEFT_OUT]
    runs = {}
    for name in chosen:
        print(f"blas variants: the numerical tests with OPENBLAS_CORETYPE={name} "
              f"(this CPU's own: {', '.join(sorted(own))})", flush=True)
        runs[name] = subprocess.Popen(
            # one process each: the two runs already share the cores side by side
            [sys.executable, "-m", "pytest", "-q", "-n", "0", "-p", "no:cacheprovider",
             *ignore],
            env={**os.environ, "OPENBLAS_CORETYPE": name}, stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT, text=True)
    failed = []
    for name, run in runs.items():
        output = run.communicate()[0]
        print(f"--- OPENBLAS_CORETYPE={name} ---\n{output[-3000:]}", flush=True)
        if run.returncode:
            failed.append(name)
    if failed:
        print(f"blas variants: failed under {', '.join(failed)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
