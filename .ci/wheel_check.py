"""A regular install, as a user gets it: build the wheel, install it in a fresh virtualenv
outside the checkout, import every package the source tree has, and run one example from
each front door (the command line, ``flexmbd.light``, the course with its sandbox).

    python .ci/wheel_check.py

Exits non-zero, naming the step, when any of it fails. An editable install cannot notice
a package left out of the wheel; this does.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def packages() -> list[str]:
    """Every package of the source tree: each folder of flexmbd/ with an __init__.py, and
    flexmbd.examples (the folder examples/)."""
    found = sorted(".".join(p.parent.relative_to(ROOT).parts)
                   for p in (ROOT / "flexmbd").rglob("__init__.py"))
    return [*found, "flexmbd.examples"]


def step(name: str, command: list[str], cwd: Path) -> str:
    print(f"wheel check: {name}", flush=True)
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True)
    if done.returncode:
        print(done.stdout[-4000:], done.stderr[-4000:], sep="\n")
        raise SystemExit(f"wheel check: {name} failed (exit {done.returncode})")
    return done.stdout


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="flexmbd-wheel-") as tmp:
        tmp_path = Path(tmp)
        step("build the wheel", [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q",
                                 "-w", str(tmp_path / "dist"), str(ROOT)], tmp_path)
        wheel = next((tmp_path / "dist").glob("flexmbd-*.whl"))
        venv.create(tmp_path / "venv", with_pip=True)
        bin_dir = tmp_path / "venv" / "bin"
        python = str(bin_dir / "python")
        step("install it", [python, "-m", "pip", "install", "-q", f"{wheel}[symbolic]"],
             tmp_path)
        work = tmp_path / "work"
        work.mkdir()
        imports = "; ".join(f"import {name}" for name in packages())
        step(f"import its {len(packages())} packages",
             [python, "-c", f"{imports}; import flexmbd; "
                            f"assert '{ROOT}' not in flexmbd.__file__, flexmbd.__file__"],
             work)
        flexmbd = str(bin_dir / "flexmbd")
        step("the command line: flexmbd example sliding-truss",
             [flexmbd, "example", "sliding-truss"], work)
        step("flexmbd.light: flexmbd example flexures", [flexmbd, "example", "flexures"], work)
        step("the course: a template", [flexmbd, "exercise", "start", "2", str(work)], work)
        solution = work / "solved.py"
        solution.write_text((ROOT / "lecturer" / "solutions" /
                             "slider_crank_kinematics.py").read_text())
        printed = step("the course: a graded check in the sandbox",
                       [flexmbd, "exercise", "check", "2", str(solution), "--graded"], work)
        if "score 9/9" not in printed:
            raise SystemExit(f"wheel check: the graded solution did not score 9/9:\n{printed}")
    print("wheel check: passed")


if __name__ == "__main__":
    main()
