"""Grading a class as a lecturer does: ``flexmbd exercise grade`` on a folder of
submissions of exercise 2, some of which loop forever in one part, each in its own
operating-system sandbox.

    python benchmarks/grading.py [--students 30] [--loops 3] [--timeout 10] [--starts 20]

The honest submissions are the solution with one part broken in turn (a wrong sign, a
transpose, a missing term) or whole; the looping ones hang in a different part each.
Prints the wall time of the command, which the target (30 submissions, 3 looping, under
2 minutes on 2 cores) is about, and the start-up cost of one graded process: the
median time from start to "loaded" of a file that imports NumPy, in the sandbox and as a
plain child process (the self-check's), over ``--starts`` runs each, taking turns.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from flexmbd.course import exercise  # noqa: E402
from flexmbd.course.launch import Unconfined, run  # noqa: E402
from flexmbd.course.sandbox import Bubblewrap  # noqa: E402
from flexmbd.course.templates import solution_source  # noqa: E402

#: edits of the solution that make typical wrong answers
WRONG = [("    return D\n    # END", "    return D.T\n    # END"),
         ("e += [np.hypot(*d) - l0, n_p @ d]", "e += [np.hypot(*d) - l0, -n_p @ d]"),
         ("+ second_order_transfer(phi2) * phi2d**2", "+ 0 * phi2d**2"),
         ("    return velocities(phi2, 1.0)[:, None]\n", "    return velocities(phi2, 1.0)\n")]
#: bodies that loop forever, each in another part
LOOPS = ["    return velocities(phi2, 1.0)[:, None]\n",
         "    return jacobian(configuration(phi2)) @ first_order_transfer(phi2)\n",
         "    return (first_order_transfer(phi2) * phi2dd + second_order_transfer(phi2) * "
         "phi2d**2)[:, 0]\n"]


def folder(students: int, loops: int, where: Path) -> Path:
    """A folder of ``students`` submissions, ``loops`` of them hanging."""
    source = solution_source(exercise(2))
    where.mkdir(parents=True, exist_ok=True)
    for k in range(students):
        text = source
        if k < loops:
            body = LOOPS[k % len(LOOPS)]
            text = text.replace(body, "    while True:\n        pass\n")
        elif k % 3:
            old, new = WRONG[k % len(WRONG)]
            text = text.replace(old, new)
        (where / f"student{k:02d}.py").write_text(text)
    return where


def start_up(runs: int) -> dict[str, float]:
    """Median seconds from start to a loaded file that imports NumPy, per launcher."""
    launchers = {"sandbox": Bubblewrap(), "plain child": Unconfined()}
    times: dict[str, list[float]] = {name: [] for name in launchers}
    for _ in range(runs):
        for name, launcher in launchers.items():   # taking turns
            begun = time.perf_counter()
            outcome = run(launcher, "probe.py", b"import numpy\n", [], {}, 60.0, 60.0)
            times[name].append(time.perf_counter() - begun)
            assert outcome.loaded and not outcome.problem, outcome
    return {name: statistics.median(values) for name, values in times.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--students", type=int, default=30)
    parser.add_argument("--loops", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=10.0)
    parser.add_argument("--starts", type=int, default=20)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        submissions = folder(args.students, args.loops, Path(tmp) / "submissions")
        begun = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "flexmbd.cli", "exercise", "grade", "2",
                               str(submissions), "--out", str(Path(tmp) / "grades.csv"),
                               "--timeout", str(args.timeout)],
                              capture_output=True, text=True, check=False)
        seconds = time.perf_counter() - begun
    summary = [line for line in done.stdout.splitlines() if not line.startswith("  [")]
    print("\n".join(summary))
    if done.returncode:
        print(done.stderr)
    print(f"{args.students} submissions ({args.loops} looping), per-part limit "
          f"{args.timeout:g} s: {seconds:.1f} s wall, exit {done.returncode}")
    costs = start_up(args.starts)
    print(f"start-up of one graded process (median of {args.starts}): "
          + ", ".join(f"{name} {value * 1e3:.0f} ms" for name, value in costs.items())
          + f"; the sandbox adds {(costs['sandbox'] - costs['plain child']) * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
