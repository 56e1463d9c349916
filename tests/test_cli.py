"""The command line: examples by name, one-line errors, exit codes."""

import subprocess
import sys

import pytest
from flexmbd.examples import sliding_bar

import flexmbd as fm
from flexmbd import cli


def test_list_examples(capsys):
    assert cli.main(["example", "--list"]) == 0
    out = capsys.readouterr().out
    for name in ("sliding-truss", "sliding-beam", "slider-crank-kin"):
        assert name in out


def test_example_help_without_a_name_lists_the_examples(capsys):
    assert cli.main(["example", "--help"]) == 0
    out = capsys.readouterr().out
    assert "usage: flexmbd example NAME" in out and "slider-crank-kin" in out


def test_unknown_example_is_a_usage_error(capsys):
    assert cli.main(["example", "nope"]) == 2
    assert "unknown example 'nope'" in capsys.readouterr().err


def test_bad_movie_type_fails_before_any_work(capsys):
    assert cli.main(["example", "sliding-beam", "--movie", "bar.avi"]) == 2
    assert "must end in .gif, .mp4" in capsys.readouterr().err


def test_library_errors_become_one_line(monkeypatch, capsys):
    def broken(argv, prog=None):
        raise fm.ModelError(["node 3 has no position", "truss 2 has zero length"])

    monkeypatch.setattr(sliding_bar, "main", broken)
    assert cli.main(["example", "sliding-truss"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("flexmbd: error: invalid model, 2 problems")
    assert "node 3 has no position; truss 2 has zero length" in err


def test_console_script_runs_an_example_without_traceback(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "flexmbd.cli", "example", "sliding-truss", "--t-end", "1.2",
         "--points", "40"],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )
    assert done.returncode == 1
    assert "Traceback" not in done.stderr
    assert "did not converge" in done.stderr or "singular configuration" in done.stderr


@pytest.mark.parametrize("argv", [["--version"], []])
def test_version_and_help(argv, capsys):
    try:
        code = cli.main(argv)
    except SystemExit as done:
        code = done.code
    out = capsys.readouterr().out
    if argv:  # the version names the compiled core in use
        assert f"flexmbd {fm.__version__} (core: C, " in out and "-O3" in out
    else:
        assert "example" in out and code == 2


def test_import_and_cli_start_load_no_optional_or_heavy_module():
    """Start-up cost: ``import flexmbd`` and the CLI load numpy only (no scipy,
    matplotlib, sympy, numba); the start-up time itself is in benchmarks/."""
    import subprocess
    import sys

    heavy = ("scipy", "matplotlib", "sympy", "numba", "h5py", "tqdm")
    probe = (
        "import sys, flexmbd, flexmbd.cli; "
        f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({heavy!r})))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"


def test_an_installed_example_file_is_written_next_to_you(tmp_path, monkeypatch, capsys):
    """Outside a clone the example input files are reachable by name: listed, written
    into the current folder (never over a file there) and runnable; a wrong name gets
    the closest ones."""
    monkeypatch.chdir(tmp_path)
    assert cli.main(["example", "--file"]) == 0
    assert "rotating_arm.dat" in capsys.readouterr().out
    assert cli.main(["example", "--file", "sliding_bar.dat"]) == 0
    assert (tmp_path / "sliding_bar.dat").read_text().startswith("% EXERCISES 1a-d")
    assert cli.main(["run", "sliding_bar.dat", "--out", "bar.csv"]) == 0
    assert cli.main(["example", "--file", "sliding_bar.dat"]) == 1
    assert "exists" in capsys.readouterr().err
    assert cli.main(["example", "--file", "slider_crank.dat"]) == 2
    assert "did you mean slider_crank_flex.dat" in capsys.readouterr().err
