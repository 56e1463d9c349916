"""Failures end cleanly and early: output files, columns and settings are checked before
any computing; an interrupted run writes what it computed; long runs report progress."""

import csv
from pathlib import Path

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import checks, outputs, progress
from flexmbd.cli import main as cli

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
FLEX = str(EXAMPLES / "slider_crank_flex.dat")
BAR = str(EXAMPLES / "sliding_bar.dat")


def _refused_before_running(capsys, argv, option, words, code=2):
    """``argv`` exits with ``code`` naming ``option`` and ``words``, before any analysis."""
    assert cli(argv) == code
    captured = capsys.readouterr()
    assert "analysis of" not in captured.out and "simulation:" not in captured.out
    assert captured.err.count("\n") <= 2 and "Traceback" not in captured.err
    assert option in captured.err and words in captured.err, captured.err


@pytest.mark.parametrize("where, words", [
    ("missing/r.csv", "does not exist"),
    ("file.txt/r.csv", "is a file, not a directory"),
    (".", "must end in"),
    ("adir.csv", "is a directory"),
])
def test_unwritable_outputs_are_refused_before_the_run(tmp_path, capsys, where, words):
    (tmp_path / "file.txt").write_text("x")
    (tmp_path / "adir.csv").mkdir()
    for option in ("--out", "--plot", "--movie"):
        name = where if option == "--out" or where in (".",) else where.replace(
            ".csv", ".png" if option == "--plot" else ".gif")
        if option != "--out" and where == "adir.csv":
            continue
        _refused_before_running(capsys, ["run", FLEX, option, str(tmp_path / name)], option,
                                words)


def test_example_outputs_are_refused_before_the_run(tmp_path, capsys):
    for argv, words in ((["--out", str(tmp_path / "no" / "f.csv")], "does not exist"),
                        (["--out", str(tmp_path / "ex.xlsx")], "must end in .csv"),
                        (["--plot", str(tmp_path / "no" / "v.png")], "does not exist")):
        assert cli(["example", "slider-crank-flex", *argv]) == 2
        captured = capsys.readouterr()
        assert words in captured.err and "simulation:" not in captured.out


def test_a_missing_extra_is_reported_before_the_run(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(outputs, "find_spec", lambda name: None)
    _refused_before_running(capsys, ["run", FLEX, "--movie", str(tmp_path / "m.mp4")],
                            "--movie", "pip install 'flexmbd[movie]'", code=1)


def test_columns_are_checked_before_the_run(tmp_path, capsys):
    plot = str(tmp_path / "p.png")
    _refused_before_running(capsys, ["run", FLEX, "--plot", plot, "--columns", "e2.9"],
                            "--columns", "'e2.9' is not a result column")
    _refused_before_running(capsys, ["run", FLEX, "--plot", plot, "--against", "phi"],
                            "--against", "'phi' is not a result column")
    _refused_before_running(capsys, ["run", FLEX, "--columns", "e2.2"], "--columns",
                            "add --plot")


def test_kinematic_mode_does_not_freeze_dynamic_degrees_of_freedom(capsys):
    _refused_before_running(capsys, ["run", FLEX, "--mode", "kinematic"], "--mode",
                            "e2.2, e2.3 are dynamic")


def test_show_without_a_display_is_a_usage_error(capsys, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setenv("MPLBACKEND", "TkAgg")
    assert cli(["example", "sliding-beam", "--show"]) == 2
    assert "no display" in capsys.readouterr().err
    monkeypatch.setenv("MPLBACKEND", "Agg")
    assert cli(["example", "sliding-beam", "--show"]) == 2
    assert "cannot open windows" in capsys.readouterr().err


@pytest.mark.parametrize("option, value", [("--points", "0"), ("--t-end", "-1"),
                                           ("--t-end", "nan"), ("--points", "2.5")])
def test_example_options_are_checked(capsys, option, value):
    assert cli(["example", "sliding-beam", option, value]) == 2
    err = capsys.readouterr().err
    assert option in err and "Traceback" not in err


@pytest.mark.parametrize("option, value", [("--omega", "nan"), ("--rtol", "-1"),
                                           ("--nbeams", "0"), ("--revolutions", "inf")])
def test_flexible_example_options_are_checked(capsys, option, value):
    assert cli(["example", "slider-crank-flex", option, value]) == 2
    assert option in capsys.readouterr().err


@pytest.mark.parametrize("method", ["GeneralizedAlpha", "RK45"])
def test_an_interrupted_run_writes_what_it_computed(tmp_path, capsys, monkeypatch, method):
    """Ctrl-C (a KeyboardInterrupt from the progress report) halfway: the rows before it
    are in every requested output, and the exit code says interrupted."""
    halfway = 0.04

    def interrupting(description, start, span):
        def advance(t):
            if t > halfway:
                raise KeyboardInterrupt
        return advance

    monkeypatch.setattr(progress, "_log_lines", interrupting)
    out, plot = tmp_path / "r.csv", tmp_path / "r.png"
    assert cli(["run", FLEX, "--method", method, "--steps", "4000", "--out", str(out),
                "--plot", str(plot)]) == 130
    assert "interrupted at t = " in capsys.readouterr().out
    with open(out) as file:
        rows = list(csv.DictReader(file))
    assert 10 < len(rows) < 4001 and float(rows[-1]["t"]) >= halfway - 0.01
    assert plot.stat().st_size > 0


def test_long_runs_report_progress_in_a_log(capsys, monkeypatch):
    monkeypatch.setattr(progress, "LOG_INTERVAL", 0.0)
    assert cli(["run", FLEX, "--steps", "1000"]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "%" in line]
    assert lines and "simulating (RK45): " in lines[0] and "elapsed" in lines[0]


def test_outputs_that_cannot_fit_in_memory_are_refused(monkeypatch, tmp_path):
    monkeypatch.setattr(checks, "available_memory", lambda: 2**20)
    model, _ = fm.read_dat(BAR)
    with pytest.raises(fm.ArgumentError, match=r"times: 10001 output times of \d+ values need"):
        fm.kinematic_analysis(model, np.linspace(0, 0.5, 10001))
    text = Path(BAR).read_text().replace("TIMESTEP", "TIMESTEP 1 100000000 #")
    path = tmp_path / "huge.dat"
    path.write_text(text)
    with pytest.raises(fm.InputFileError, match="TIMESTEP: steps: 100000001 output times"):
        fm.read_dat(path)


@pytest.mark.parametrize("options, argument", [
    ({"tolerance": 1e-300}, "tolerance: 1e-300 is below the round-off"),
    ({"tolerance": 10.0}, "tolerance: 10 is not small against the model's size"),
    ({"tolerance": "tight"}, "tolerance: must be a number"),
    ({"max_iterations": 10**8}, "max_iterations: must lie in 1 .. 1000"),
    ({"max_iterations": 2.5}, "max_iterations: must be a whole number"),
    ({"times": np.zeros((2, 3))}, "times: must be one-dimensional"),
    ({"times": [0.0, np.nan]}, "times: must be a non-empty sequence of finite times"),
])
def test_kinematic_settings_that_cannot_work_are_refused(options, argument):
    model, _ = fm.read_dat(BAR)
    times = options.pop("times", np.linspace(0, 0.5, 5))
    with pytest.raises(fm.ArgumentError) as info:
        fm.kinematic_analysis(model, times, **options)
    assert argument in str(info.value)


@pytest.mark.parametrize("options, argument", [
    ({"rtol": -1}, "rtol: -1 must lie in"),
    ({"rtol": "tight"}, "rtol: must be a number, got 'tight'"),
    ({"rtol": 1e-300}, "rtol: 1e-300 must lie in"),
    ({"atol": 1e10}, "atol: 1e+10 must be positive and small"),
    ({"max_step": 1e-15}, "max_step: 1e-15 s over 0.1 s makes"),
    ({"method": "GeneralizedAlpha", "step": 1e-15}, "step: 1e-15 s over 0.1 s makes"),
    ({"method": "GeneralizedAlpha", "rho_inf": "none"}, "rho_inf: must be a number"),
    ({"on_failure": "ignore"}, "on_failure: must be 'raise' or 'return'"),
])
def test_simulation_settings_that_cannot_work_are_refused(options, argument):
    model, _ = fm.read_dat(FLEX)
    with pytest.raises(fm.ArgumentError) as info:
        fm.simulate(model, np.linspace(0, 0.1, 5), **options)
    assert argument in str(info.value)
