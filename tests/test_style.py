"""The code stays ruff-clean (the configuration is in pyproject.toml)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_ruff_is_clean():
    beside_python = Path(sys.executable).with_name("ruff")
    ruff = str(beside_python) if beside_python.exists() else shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is not installed (it comes with the test extra)")
    done = subprocess.run([ruff, "check", "flexmbd", "examples", "tests", "benchmarks", "docs",
                           ".ci", "lecturer"],
                          cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def _lint_imports(root: Path) -> subprocess.CompletedProcess:
    beside_python = Path(sys.executable).with_name("lint-imports")
    command = str(beside_python) if beside_python.exists() else shutil.which("lint-imports")
    if command is None:
        pytest.skip("import-linter is not installed (it comes with the test extra)")
    return subprocess.run([command, "--config", str(ROOT / "pyproject.toml")], cwd=root,
                          capture_output=True, text=True, env={**os.environ,
                                                                "PYTHONPATH": str(root)})


def test_imports_flow_one_way():
    """The layers of pyproject.toml ([tool.importlinter]): cli, course and studies, io,
    analysis, results, plot, builder, engine, model, elements, the small modules; no
    circle among the modules of any folder."""
    done = _lint_imports(ROOT)
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_circle_breaks_the_import_contract(tmp_path):
    """The contract is not a formality: the engine importing an analysis (a circle, as
    ``diagnosis`` -> ``dynamics`` -> ``engine`` once was) fails it."""
    copy = tmp_path / "flexmbd"
    shutil.copytree(ROOT / "flexmbd", copy, ignore=shutil.ignore_patterns(
        "__pycache__", "*.so", "csrc"))
    with open(copy / "engine" / "assembly.py", "a") as module:
        module.write("\nfrom ..analysis import kinematics  # noqa: E402, F401\n")
    done = _lint_imports(tmp_path)
    assert done.returncode != 0 and "flexmbd.engine is not allowed to import " \
        "flexmbd.analysis" in done.stdout


@pytest.mark.mypy
def test_mypy_is_clean():
    """mypy at its default strictness on the package ([tool.mypy] in pyproject.toml):
    annotated functions are checked, and no error is left."""
    beside_python = Path(sys.executable).with_name("mypy")
    mypy = str(beside_python) if beside_python.exists() else shutil.which("mypy")
    if mypy is None:
        pytest.skip("mypy is not installed (it comes with the test extra)")
    done = subprocess.run([mypy], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
