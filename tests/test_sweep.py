"""Parameter studies (flexmbd.sweep, flexmbd sweep): cases against the plain serial loop,
failed cases as rows, resuming an interrupted study, a scheduler and workers started as
separate processes, and the .dat parameter names."""

import functools
import json
import math
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import cloudpickle
import numpy as np
import pandas as pd
import pytest
from flexmbd.examples import EXAMPLES_DIR
from flexmbd.examples import slider_crank_flex as flex

import flexmbd as fm
from flexmbd.io.dat import dat_from_text
from flexmbd.io.dat.parameters import DatTemplate
from flexmbd.studies import cases, parse_values
from flexmbd.studies.case import Study

# the workers of a cluster started apart do not import the tests: send their functions
cloudpickle.register_pickle_by_value(sys.modules[__name__])

FLEX_DAT = EXAMPLES_DIR / "slider_crank_flex.dat"
GUIDE_DAT = EXAMPLES_DIR / "parallel_guide.dat"
#: a quarter crank turn: each case a few milliseconds
ANALYSIS = functools.partial(flex.run, revolutions=0.25)
OUTPUTS = {"peak": flex.peak_deflection, "v": flex.deflection}
#: seconds a cluster may take to start, a worker to register (generous: on a loaded
#: machine dask's worker processes have taken more than a minute; past it, the tests of
#: separate worker processes skip and say so)
STARTUP = 180.0


def serial_loop(grid: dict) -> list[dict]:
    """What a user writes without flexmbd.sweep: a loop over the cases."""
    rows = []
    for case in cases(grid):
        result = ANALYSIS(flex.build_model(**case))
        rows.append({**case, "peak": flex.peak_deflection(result), "v": flex.deflection(result)})
    return rows


def assert_same_cases(data, rows: list[dict]) -> None:
    assert list(data["status"].values) == ["ok"] * len(rows)
    for k, row in enumerate(rows):
        assert data["nbeams"].values[k] == row["nbeams"]
        assert data["peak"].values[k] == pytest.approx(row["peak"], rel=1e-12)
        v = data["v"].values[k]
        np.testing.assert_allclose(v[~np.isnan(v)], row["v"], rtol=1e-12, atol=1e-15)


# --- grids and value syntax --------------------------------------------------------------

def test_grid_product_order_and_list():
    assert cases({"a": [1, 2], "b": ["x", "y"]}) == [
        {"a": 1, "b": "x"}, {"a": 1, "b": "y"}, {"a": 2, "b": "x"}, {"a": 2, "b": "y"}]
    assert cases([{"a": np.int64(3), "b": np.float64(0.5)}]) == [{"a": 3, "b": 0.5}]


@pytest.mark.parametrize("grid, words", [
    ({}, "no cases"), ({"a": []}, "no values"), ({"a": 3}, "list of values"),
    ([{"a": 1}, {"b": 2}], "same parameters"), ({"status": [1]}, "column of every"),
    ({"a": [[1, 2]]}, "numbers, strings"), ({"a": [math.inf]}, "not finite"),
    ("abc", "mapping"),
])
def test_grid_errors(grid, words):
    with pytest.raises(fm.ArgumentError, match=words):
        cases(grid)


def test_value_syntax():
    assert parse_values("1,2,5.5") == [1, 2, 5.5]
    assert parse_values("3..6") == [3, 4, 5, 6]
    assert parse_values("0.1..0.5/5") == pytest.approx([0.1, 0.2, 0.3, 0.4, 0.5])
    assert parse_values("log:1..100/3") == pytest.approx([1, 10, 100])
    for text, words in (("1..x", "is not"), ("5..1", "empty"), ("0.1..1", "number of values"),
                        ("log:0..1/3", "positive"), ("log:1,2", "is not"), ("", "is not"),
                        ("1..3/0", "is not")):
        with pytest.raises(fm.ArgumentError, match=words):
            parse_values(text)


# --- .dat values by name ------------------------------------------------------------------

def test_dat_names_pick_the_value_and_vary_it():
    template = DatTemplate.read(FLEX_DAT)
    assert template.locate("ESTIFF:2:2").argument == "stiffness"
    assert template.locate("INPUTX:2:3") == template.locate("INPUTX:2:1:2")  # v0 of block 2
    assert template.locate("TIMESTEP:1").argument == "t_end"
    # independently: the same change made by hand in the text, read as a file
    by_hand = FLEX_DAT.read_text().replace("12.72   # EA", "20.5   # EA").replace(
        "INPUTX   2 1  0.0 150.0", "INPUTX   2 1  0.0 120.0")
    model, settings = dat_from_text(by_hand, FLEX_DAT)
    varied, varied_settings = template(**{"ESTIFF:2:2": 20.5, "INPUTX:2:3": 120.0})
    times = settings.output_times()[:60]
    a, b = fm.simulate(model, times), fm.simulate(varied, times)
    assert b["e2.2"][-1] != 0.0
    np.testing.assert_array_equal(a.q, b.q)
    assert varied_settings == settings


@pytest.mark.parametrize("name, words", [
    ("ESTIFF", "KEYWORD:NUMBER"), ("ESTIFF:2", "element first"), ("ESTIFF:3:1", "no ESTIFF 3"),
    ("ESTIFF:2:5", "2 value"), ("INPUTX:2:1", "matches lines 15, 23"),
    ("DYNE:2:1", "deformation number"), ("FOO:1", "not a keyword"), ("X:1:0", "KEYWORD"),
])
def test_dat_name_errors(name, words):
    with pytest.raises(fm.ArgumentError, match=words):
        DatTemplate.read(FLEX_DAT).locate(name)


def test_varied_file_errors_name_the_line():
    with pytest.raises(fm.InputFileError, match=r"slider_crank_flex.dat:21: .*negative"):
        DatTemplate.read(FLEX_DAT)(**{"ESTIFF:2:2": -1.0})
    with pytest.raises(fm.ArgumentError, match="takes a number"):
        DatTemplate.read(FLEX_DAT)(**{"ESTIFF:2:2": "stiff"})


# --- the study ------------------------------------------------------------------------------

def test_local_cluster_equals_the_serial_loop():
    grid = {"nbeams": [1, 2, 3, 4, 5]}
    data = fm.sweep(flex.build_model, grid, ANALYSIS, OUTPUTS)  # the default local cluster
    assert_same_cases(data, serial_loop(grid))
    assert data["v"].dims == ("case", "step")
    assert np.all(data["wall_time"].values > 0)


def test_failed_cases_are_rows_with_their_message():
    def analysis(model):
        if flex.nbeams_of(model) == 3:
            return 1 / 0
        return ANALYSIS(model)

    data = fm.sweep(flex.build_model, {"nbeams": [1, 0, 2, 3]}, analysis,
                    {"peak": flex.peak_deflection, "size": lambda r: r.x.shape[1] / 0},
                    "serial")
    assert list(data["status"]) == ["failed"] * 4  # every output 'size' fails
    assert data["error"][1] == "build: invalid model: nbeams must be at least 1, got 0"
    assert data["error"][3] == "analysis: ZeroDivisionError: division by zero"
    assert data["error"][0].startswith("output 'size': ZeroDivisionError")
    # what could be computed is kept: the peak of the runs that ran
    assert data["peak"][0] == pytest.approx(flex.peak_deflection(ANALYSIS(flex.build_model(1))))
    assert math.isnan(data["peak"][1])


def test_a_run_that_stops_early_keeps_its_rows(tmp_path):
    # a crank acceleration of 2e6 rad/s^2, which the rod cannot follow, and none
    data = fm.sweep(FLEX_DAT, {"INPUTX:2:4": [2e6, 0.0]}, "dynamic",
                    ["absmax:e2.2", "t"], "serial")
    assert list(data["status"].values) == ["failed", "ok"]
    assert re.search(r"the GeneralizedAlpha integrator.* at t = ", data["error"].values[0])
    stopped = data["t"].values[0]
    assert 0 < np.count_nonzero(~np.isnan(stopped)) < data["t"].sizes["step"]


def test_named_modes_analysis_against_the_file_edited_by_hand():
    """The stage's mass (XM) of the leaf-spring guide lowers its first frequency; each case
    equals the modes of the file with that line changed by hand."""
    from flexmbd.analysis.modes import vibration_modes
    from flexmbd.analysis.statics import file_equilibrium

    template = DatTemplate.read(GUIDE_DAT)
    line = template.locate("ESTIFF:1:2").line
    data = fm.sweep(GUIDE_DAT, {"ESTIFF:1:2": [0.04375, 0.02]}, "modes", ["f1", "f2"],
                    "serial")
    for k, ei in enumerate((0.04375, 0.02)):
        lines = GUIDE_DAT.read_text().splitlines()
        lines[line - 1] = f"ESTIFF 1 2100000.0 {ei}"
        model, settings = dat_from_text("\n".join(lines), GUIDE_DAT)
        modes = vibration_modes(file_equilibrium(model, settings).linearization(), 2)
        assert data["f1"][k] == pytest.approx(modes.frequencies[0], rel=1e-12)
        assert data["f2"][k] == pytest.approx(modes.frequencies[1], rel=1e-12)
    assert data["f1"][1] < data["f1"][0]  # a softer beam at the base: a slower sway


def test_sweep_command_keeps_as_many_frequencies_as_the_file_has_modes(tmp_path, capsys):
    """The one-beam slider-crank has two dynamic degrees of freedom (the crank angle is an
    input): the default metrics of a modes study are f1 and f2, equal to the file's modes."""
    from flexmbd.analysis.modes import vibration_modes
    from flexmbd.analysis.statics import file_equilibrium
    from flexmbd.cli import main

    out = tmp_path / "modes.parquet"
    assert main(["sweep", str(FLEX_DAT), "--analysis", "modes", "--vary", "ESTIFF:2:2=20",
                 "--serial", "--out", str(out)]) == 0
    table = pd.read_parquet(out)
    assert [c for c in table.columns if c.startswith("f")] == ["f1", "f2"]
    model, settings = DatTemplate.read(FLEX_DAT)(**{"ESTIFF:2:2": 20})
    modes = vibration_modes(file_equilibrium(model, settings).linearization())
    np.testing.assert_allclose(table[["f1", "f2"]].to_numpy()[0], modes.frequencies, rtol=1e-12)


@pytest.mark.parametrize("call, words", [
    (dict(outputs={"nbeams": "peak"}), "also a parameter"),
    (dict(outputs={"peak": "median:x5.1"}), "not one of"),
    (dict(outputs=[]), "at least one"),
    (dict(analysis="transient"), "one of auto"),
    (dict(client=3), "scheduler address"),
    (dict(out="table.csv"), r"\.parquet"),
])
def test_study_errors_before_any_case(call, words, tmp_path):
    arguments = dict(build=flex.build_model, grid={"nbeams": [1]}, analysis=ANALYSIS,
                     outputs=OUTPUTS, client="serial")
    arguments.update(call)
    if "out" in call:
        arguments["out"] = tmp_path / call["out"]
    with pytest.raises(fm.ArgumentError, match=words):
        fm.sweep(**arguments)


def test_resume_skips_finished_cases_and_refuses_another_study(tmp_path):
    out = tmp_path / "study.parquet"
    grid = {"nbeams": [1, 2, 3]}
    first = fm.sweep(flex.build_model, {"nbeams": [1, 2]}, ANALYSIS, {"peak": flex.peak_deflection},
                     "serial", out=out)
    # the same file with one more case of the same study would disagree on case ids only if
    # the grid changed; a grid extended at the end runs only the new case
    calls = []

    def counted(model):
        calls.append(flex.nbeams_of(model))
        return ANALYSIS(model)

    study = fm.sweep(flex.build_model, grid, counted, {"peak": flex.peak_deflection}, "serial",
                     out=out)
    assert calls == [3]
    assert list(study["peak"][:2]) == list(first["peak"])
    with pytest.raises(fm.ArgumentError, match="holds case 0 with"):
        fm.sweep(flex.build_model, {"nbeams": [4, 5]}, ANALYSIS, {"peak": flex.peak_deflection},
                 "serial", out=out)
    with pytest.raises(fm.ArgumentError, match="columns"):
        fm.sweep(flex.build_model, grid, ANALYSIS, {"top": flex.peak_deflection}, "serial",
                 out=out)
    again = fm.sweep(flex.build_model, {"nbeams": [4, 5]}, ANALYSIS,
                     {"peak": flex.peak_deflection}, "serial", out=out, restart=True)
    assert list(again["nbeams"]) == [4, 5]


def _sweep_command(out: Path, *extra: str) -> list[str]:
    return [sys.executable, "-m", "flexmbd.cli", "sweep", str(FLEX_DAT), "--vary",
            "ESTIFF:2:2=10..40", "--vary", "TIMESTEP:2=800", "--out", str(out), *extra]


def _default_interrupt() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _interrupted(command: list[str], out: Path, sig: int) -> int:
    """Start ``command``, send ``sig`` once finished cases are on disk; its exit code."""
    # a shell's background job starts with SIGINT ignored, and Python then installs no
    # KeyboardInterrupt handler: the study gets Ctrl-C's default, as at a terminal
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               text=True, preexec_fn=_default_interrupt)
    parts = out.with_name(out.name + ".partial")
    deadline = time.monotonic() + STARTUP
    try:
        while not any(parts.glob("*.parquet")) and time.monotonic() < deadline:
            if process.poll() is not None:
                pytest.fail(f"the study ended before it was interrupted: "
                            f"{process.stderr.read()}")
            time.sleep(0.02)
        process.send_signal(sig)
        return process.wait(timeout=30)
    finally:
        process.kill()
        process.stderr.close()


@pytest.fixture(scope="module")
def whole_table(tmp_path_factory) -> pd.DataFrame:
    """The study of :func:`_sweep_command` run through, serially."""
    whole = tmp_path_factory.mktemp("whole") / "whole.parquet"
    assert subprocess.run(_sweep_command(whole, "--serial"), capture_output=True,
                          timeout=300).returncode == 0
    return pd.read_parquet(whole)


@pytest.mark.xdist_group("interrupted study")   # one worker: the whole table made once
@pytest.mark.parametrize("sig, where", [(signal.SIGINT, []), (signal.SIGKILL, ["--serial"])])
def test_an_interrupted_study_resumes_to_the_same_table(tmp_path, whole_table, sig, where):
    """Ctrl-C on a local cluster (the table is written on the way out) and a hard kill of a
    serial run (the part files are all that is left): both resume to the full table."""
    out = tmp_path / "cut.parquet"
    code = _interrupted(_sweep_command(out, *where), out, sig)
    assert code == (130 if sig == signal.SIGINT else -signal.SIGKILL)
    kept = pd.concat([pd.read_parquet(p) for p in
                      [out, *out.with_name(out.name + ".partial").glob("*.parquet")]
                      if p.exists()])
    assert 0 < len(kept) < 31
    resumed = subprocess.run(_sweep_command(out, *where), capture_output=True, text=True,
                             timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert not out.with_name(out.name + ".partial").exists()
    pd.testing.assert_frame_equal(whole_table.drop(columns="wall_time"),
                                  pd.read_parquet(out).drop(columns="wall_time"))


# --- a scheduler and two workers as separate processes --------------------------------------

@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """``dask scheduler`` and two ``dask worker`` processes on the loopback address, stopped
    at the end; a failed case is not retried (a worker that dies fails its case at once).
    Each worker holds one case at a time: with dask's default saturation a worker also
    holds the next case, which a death without retries would fail along with its own."""
    folder = tmp_path_factory.mktemp("cluster")
    info = folder / "scheduler.json"
    env = {**os.environ, "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0",
           "DASK_DISTRIBUTED__SCHEDULER__WORKER_SATURATION": "1.0"}
    bin_dir = Path(sys.executable).parent
    processes = [subprocess.Popen(
        [str(bin_dir / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0",
         "--no-dashboard", "--scheduler-file", str(info)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=folder)]
    try:
        deadline = time.monotonic() + STARTUP
        while not info.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        if not info.exists():
            pytest.skip(f"the dask scheduler did not start within {STARTUP:g} s on this "
                        f"machine: it is too loaded to test a study on separate workers")
        address = json.loads(info.read_text())["address"]
        for _ in range(2):
            processes.append(subprocess.Popen(
                [str(bin_dir / "dask"), "worker", address, "--nthreads", "1",
                 "--no-dashboard", "--host", "127.0.0.1"],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=folder))
        from dask.distributed import Client

        try:
            with Client(address, timeout=STARTUP) as client:
                client.wait_for_workers(2, timeout=STARTUP)
        except (OSError, TimeoutError) as error:
            pytest.skip(f"two dask worker processes did not start within {STARTUP:g} s on "
                        f"this machine ({type(error).__name__}): it is too loaded to test "
                        f"a study on separate workers")
        yield address
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()


def test_a_study_on_a_scheduler_and_two_worker_processes(scheduler):
    grid = {"nbeams": [1, 2, 3, 4, 5, 6]}
    data = fm.sweep(flex.build_model, grid, ANALYSIS, {**OUTPUTS, "pid": lambda r: os.getpid()},
                    scheduler)
    assert_same_cases(data, serial_loop(grid))
    pids = set(data["pid"].values)
    assert os.getpid() not in pids and len(pids) == 2  # ran on both workers, not here


def test_a_worker_that_dies_fails_its_case_only(scheduler):
    def analysis(model):
        if flex.nbeams_of(model) == 2:
            os._exit(3)  # a crash in compiled code, an out-of-memory kill
        return ANALYSIS(model)

    data = fm.sweep(flex.build_model, {"nbeams": [1, 2, 3]}, analysis,
                    {"peak": flex.peak_deflection}, scheduler)
    assert list(data["status"]) == ["ok", "failed", "ok"]
    assert data["error"][1].startswith("worker: ")


def test_sweep_command_on_the_scheduler(scheduler, tmp_path):
    out = tmp_path / "t.parquet"
    done = subprocess.run([sys.executable, "-m", "flexmbd.cli", "sweep", str(FLEX_DAT),
                           "--vary", "ESTIFF:2:2=log:10..100/3", "--vary", "TIMESTEP:2=100",
                           "--keep", "e2.2", "--metric", "absmax:e2.3", "--out", str(out),
                           "--scheduler", scheduler], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    table = pd.read_parquet(out)
    assert list(table.columns) == ["case", "ESTIFF:2:2", "TIMESTEP:2", "absmax:e2.3", "e2.2",
                                   "status", "error", "wall_time"]
    model, settings = DatTemplate.read(FLEX_DAT)(**{"ESTIFF:2:2": 100.0, "TIMESTEP:2": 100})
    direct = fm.simulate(model, settings.output_times(), rtol=settings.rtol, atol=settings.atol)
    np.testing.assert_allclose(table["e2.2"][2], direct["e2.2"], rtol=1e-9, atol=1e-12)
    assert table["absmax:e2.3"][2] == pytest.approx(np.abs(direct["e2.3"]).max(), rel=1e-9)


# --- the command line and the example ------------------------------------------------------

@pytest.mark.parametrize("arguments, words", [
    (["--vary", "ESTIFF:2:2"], "NAME=VALUES"),
    (["--vary", "ESTIFF:2:2=1..x"], "is not a list"),
    (["--vary", "ESTIFF:9:2=1,2"], "no ESTIFF 9 line"),
    (["--vary", "ESTIFF:2:2=1,2", "--vary", "ESTIFF:2:2=3"], "varied twice"),
    (["--vary", "ESTIFF:2:2=1,2", "--metric", "peak:e2.2"], "not one of"),
])
def test_sweep_command_errors(arguments, words, tmp_path):
    done = subprocess.run([sys.executable, "-m", "flexmbd.cli", "sweep", str(FLEX_DAT),
                           *arguments, "--out", str(tmp_path / "t.parquet"), "--serial"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert words in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "t.parquet").exists()


def test_example_study_matches_single_runs(tmp_path):
    plot, out = tmp_path / "study.png", tmp_path / "study.parquet"
    code = flex.main(["--nbeams", "1..3", "--revolutions", "0.5", "--plot", str(plot),
                      "--out", str(out)])
    assert code == 0 and plot.stat().st_size > 10_000
    table = pd.read_parquet(out)
    for n in (1, 2, 3):
        single = flex.simulate(n, revolutions=0.5)
        assert table["peak"][n - 1] == pytest.approx(flex.peak_deflection(single), rel=1e-12)
        np.testing.assert_allclose(table["v_over_l2"][n - 1], flex.deflection(single),
                                   rtol=1e-12, atol=1e-15)


def test_an_unguarded_script_is_told_how_to_fix_it(tmp_path):
    script = tmp_path / "study.py"
    script.write_text("import flexmbd as fm\n"
                      "from flexmbd.examples import slider_crank_flex as flex\n"
                      "fm.sweep(flex.build_model, {'nbeams': [1]}, flex.run, ['x5.1'],\n"
                      "         out='t.parquet')\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path)
    assert done.returncode == 1
    assert not (tmp_path / "t.parquet").exists()  # nothing ran: no table to resume
    assert 'study.py, line 3: a study on a local cluster' in done.stderr
    assert 'if __name__ == "__main__":' in done.stderr


def test_the_core_imports_no_study_dependencies():
    probe = ("import sys, flexmbd, flexmbd.studies, flexmbd.cli; "
             "print(sorted({m.split('.')[0] for m in sys.modules} & "
             "{'dask', 'distributed', 'pandas', 'pyarrow', 'xarray'}))")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=60)
    assert done.stdout.strip() == "[]", done.stderr


def test_study_serializes_as_sent_to_workers():
    """The study and a .dat template survive pickling (what Dask does with them)."""
    study = Study(DatTemplate.read(FLEX_DAT), "dynamic", {"m": "absmax:e2.2"})
    again = cloudpickle.loads(cloudpickle.dumps(study))
    assert again.build.text == study.build.text
    assert again.run(0, {"ESTIFF:2:2": 50.0, "TIMESTEP:2": 20})["status"] == "ok"
