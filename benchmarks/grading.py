"""Grading a class as a lecturer does: ``flexmbd exercise grade`` on a folder of
submissions of exercise 2, some of which loop forever in one part.

    python benchmarks/grading.py [--students 30] [--loops 3] [--timeout 10]

The honest submissions are the solution with one part broken in turn (a wrong sign, a
transpose, a missing term) or whole; the looping ones hang in a different part each.
Prints the wall time of the command, which the target (30 submissions, 3 looping, under
2 minutes on 2 cores) is about.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from flexmbd.course import exercise  # noqa: E402
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--students", type=int, default=30)
    parser.add_argument("--loops", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=10.0)
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
    print(f"{args.students} submissions ({args.loops} looping), per-part limit "
          f"{args.timeout:g} s: {seconds:.1f} s wall, exit {done.returncode}")


if __name__ == "__main__":
    main()
