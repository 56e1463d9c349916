"""Failures end cleanly and early: output files, columns and settings are checked before
any computing; an interrupted run writes what it computed; long runs report progress."""

import csv
import warnings
from pathlib import Path

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import checks, progress
from flexmbd.analysis.linearization import linearize
from flexmbd.analysis.modes import vibration_modes
from flexmbd.cli import main as cli
from flexmbd.io import outputs
from flexmbd.io.dat import dat_from_text

from .models import andrews_squeezer, squeezer_angles

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
    assert lines and "simulating (GeneralizedAlpha): " in lines[0] and "elapsed" in lines[0]


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
    flex, _ = fm.read_dat(FLEX)
    with pytest.raises(fm.ArgumentError, match=r"steps: 1000001 output times of \d+ values"):
        fm.static_equilibrium(flex, loads={"x5.1": 1.0}, steps=10**6)


@pytest.mark.parametrize("method", ["RK45", "GeneralizedAlpha"])
def test_the_memory_estimate_is_what_a_run_holds_and_writing_adds_none(tmp_path, method):
    """The refusal above rests on :func:`output_bytes`: the memory a simulation holds per
    output time, measured by tracemalloc between runs of 10000 and 20000 outputs, is
    within 5 % of it (it was 2.3 times the old estimate, and CSV writing tripled it), and
    writing the CSV file takes the same few MB whatever the rows. The estimate counts the
    integrator's state at each output, which SciPy's methods keep and the core's
    generalized-alpha does not."""
    import tracemalloc

    from flexmbd.engine import output_bytes

    model, _ = fm.read_dat(FLEX)
    fm.simulate(model, np.linspace(0, 0.02, 11), method=method).save(tmp_path / "warm.csv")
    held, writing = [], []
    for rows in (10001, 20001):
        tracemalloc.start()
        try:
            result = fm.simulate(model, np.linspace(0, 0.02, rows), method=method)
            held.append(tracemalloc.get_traced_memory()[1])
            tracemalloc.reset_peak()
            before = tracemalloc.get_traced_memory()[0]
            result.save(tmp_path / "out.csv")
            writing.append(tracemalloc.get_traced_memory()[1] - before)
        finally:
            tracemalloc.stop()
    state = 8 * 2 * len(model.dynamic_q_labels) if method == "GeneralizedAlpha" else 0
    assert (held[1] - held[0]) / 10000 == pytest.approx(output_bytes(model) - state, rel=0.05)
    assert writing[1] < 1.1 * writing[0] + 2**16 and writing[1] < 2**24


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


def _flex_with(replacements: dict[str, str]) -> fm.Model:
    text = Path(FLEX).read_text()
    for old, new in replacements.items():
        assert old in text
        text = text.replace(old, new)
    return dat_from_text(text, "flex.dat").model


ROD_MASS = "EM       2  0.22253333333333333"
SLIDER_MASS = "XM       5  0.03338"
ROD_STIFFNESS = "ESTIFF   2  5654866.776461628 12.72"


@pytest.mark.parametrize("factor", [1e-8, 1e12, 1e40])
def test_the_motion_does_not_depend_on_the_unit_of_mass(factor):
    """Masses and stiffnesses scaled together leave the motion unchanged (the equations of
    motion are homogeneous in them): tonnes or grams, the run must give the same answer."""
    times = np.linspace(0.0, 0.01, 11)
    reference = fm.simulate(_flex_with({}), times, rtol=1e-8, atol=1e-12)
    scaled = _flex_with({ROD_MASS: f"EM 2 {0.22253333333333333 * factor!r}",
                         SLIDER_MASS: f"XM 5 {0.03338 * factor!r}",
                         ROD_STIFFNESS: f"ESTIFF 2 {5654866.776461628 * factor!r} "
                                        f"{12.72 * factor!r}"})
    result = fm.simulate(scaled, times, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(result.e, reference.e, rtol=0, atol=1e-9)


# --- stiffness and points an integrator cannot pass --------------------------------------
#: the flexible slider-crank with its rod's bending stiffness times 1e8: a bending mode of
#: about 4e7 rad/s that the outputs, 1e-4 s apart, cannot show
STIFF_ROD = {ROD_STIFFNESS: "ESTIFF 2 5654866.776461628 1.272e9"}


def test_the_spectral_radius_of_an_oscillator_is_its_highest_frequency():
    """Two masses on springs, y = [u; v], u'' = -K u: the power iteration on finite
    differences gives the highest omega of eig(K) to 1e-6."""
    from flexmbd.analysis.watch import spectral_radius

    K = np.array([[2e6, -1e6], [-1e6, 1e6]])

    def fun(t, y):
        return np.concatenate([y[2:], -K @ y[:2]])

    omega = np.sqrt(np.linalg.eigvalsh(K).max())
    assert spectral_radius(fun, 0.0, np.array([1e-3, 0.0, 0.0, 0.5])) == \
        pytest.approx(omega, rel=1e-6)


def test_a_stiff_model_under_an_explicit_method_is_named_stiff_at_once(monkeypatch):
    """RK45 on the rod made 1e8 times stiffer would crawl for minutes at steps of its
    stability limit; with the pace looked at every step (instead of every 2 s once a run
    is projected to take 30 s) it stops at its first step, says the model is stiff and
    which method fits, and keeps what it computed. The mode it names is the rod's
    highest vibration frequency at the start, computed from K and M."""
    from flexmbd.analysis import watch

    monkeypatch.setattr(watch, "STIFF_LOOK", 0.0)
    monkeypatch.setattr(watch, "STIFF_PROJECTED", 0.0)
    model = _flex_with(STIFF_ROD)
    for points in (11, 101, 2001):  # how often a run reports does not make it stiff
        result = fm.simulate(model, np.linspace(0.0, 0.01, points), method="RK45",
                             on_failure="return")
        assert isinstance(result.error, fm.StiffnessError) and len(result.t) >= 1
        assert "the model is stiff for RK45" in result.message
        assert "method='GeneralizedAlpha'" in result.message
        rate = float(result.message.split("a mode of ")[1].split(" rad/s")[0])
        highest = np.sqrt(vibration_modes(linearize(model)).omega2.max())
        assert rate == pytest.approx(highest, rel=0.05)  # three digits, where it stopped
    # the model as the course gives it: its fastest mode, 2e3 rad/s, sets RK45's steps
    # too, but the run takes a second, far from the projected half minute that stops one
    monkeypatch.setattr(watch, "STIFF_PROJECTED", 30.0)
    assert fm.simulate(_flex_with({}), np.linspace(0.0, 0.01, 101), method="RK45").success
    # BDF crawls too (steps of 1e-8 s, 8 % in 90 s): its finite-difference Jacobian does
    # not follow the stiff mode, so it does not step over it
    result = fm.simulate(model, np.linspace(0.0, 0.01, 101), method="BDF",
                         on_failure="return")
    assert isinstance(result.error, fm.StiffnessError)
    assert "the model is stiff for BDF" in result.message and "is not stepped over" in \
        result.message


def test_flexmbd_run_steps_over_a_stiff_file_unless_told_otherwise(
        tmp_path, monkeypatch, capsys):
    """The rod made 1e8 times stiffer: its fastest mode is 1e4 times faster than the
    course's. The default method steps over it (a few hundred steps for 0.01 s); RK45,
    asked for, is stopped as stiff."""
    from flexmbd.analysis import watch

    monkeypatch.setattr(watch, "STIFF_LOOK", 0.0)
    monkeypatch.setattr(watch, "STIFF_PROJECTED", 0.0)
    path = tmp_path / "stiff.dat"
    text = Path(FLEX).read_text().replace(ROD_STIFFNESS, STIFF_ROD[ROD_STIFFNESS])
    path.write_text(text.replace("TIMESTEP 0.08377580409572781 800", "TIMESTEP 0.01 100"))
    assert cli(["run", str(path), "--out", str(tmp_path / "a.csv")]) == 0
    out = capsys.readouterr().out
    assert "completed 101 points" in out
    steps = int(out.split("completed 101 points to t = 0.01 s (")[1].split(" steps")[0])
    assert steps < 1000
    assert cli(["run", str(path), "--method", "RK45", "--out", str(tmp_path / "b.csv")]) == 1
    assert "the model is stiff for RK45" in capsys.readouterr().out


def test_an_implicit_method_that_cannot_pass_aligned_bars_stops_within_seconds():
    """Radau at rtol 1e-10 reaches 3 parallelograms' aligned bars at t = 0.156 s and then
    takes steps of 1e-14 to 1e-9 s that never add up; it stops after a few thousand
    steps, naming the time (before, 158 000 steps and 78 s on ten loops)."""
    result = fm.simulate(parallelograms(3), np.linspace(0.0, 2.0, 201),
                         initial={"x2.1": (0.0, 11.0)}, method="Radau", rtol=1e-10,
                         atol=1e-12, on_failure="return")
    assert not result.success and result.stats["nsteps"] < 10_000
    assert "the Radau integrator cannot get past t = 0.15" in result.message


@pytest.mark.parametrize("replacements, words", [
    ({ROD_MASS: "EM 2 0"}, "no mass moves with e2.2 (beam 2, bending at p), e2.3"),
    ({SLIDER_MASS: "XM 5 1e300"}, "the masses span 1e+300 (node 5) to 0.0668 (element 2"),
])
def test_a_singular_mass_matrix_says_why(replacements, words):
    with warnings.catch_warnings():   # a massless rod is also said at build: not the point
        warnings.simplefilter("ignore", fm.ModelWarning)
        model = _flex_with(replacements)
    with pytest.raises(fm.SingularConfigurationError, match=r"at t = 0 s|span") as info:
        fm.simulate(model, np.linspace(0, 0.01, 3))
    assert words in str(info.value)


def test_negative_masses_are_refused_where_they_make_the_kinetic_energy_negative():
    # a small negative rotary inertia corrects a body modelled by point masses: allowed
    corrected = _flex_with({SLIDER_MASS: f"{SLIDER_MASS}\nXM 6 -1e-6"})
    assert corrected.nodal_masses[6] == -1e-6
    with pytest.raises(fm.InputFileError) as info:  # a crank pin of -1 kg is not
        _flex_with({SLIDER_MASS: "XM 3 -1"})
    assert info.value.line == 22 and "XM: the negative mass of node(s) 3 outweighs the mass " \
        "of element(s) 1, 2 there: the motion along x2.1 (node 2, phi), which moves x3.2 " \
        "(node 3, y), would have negative kinetic energy" in str(info.value)
    b = fm.ModelBuilder("pendulum")
    b.add_node(1, 0.0, 0.0).add_node(2, 1.0, 0.0).add_rigid_beam(1, 1, 3, 2).fix(1)
    b.dynamic_coordinate(3).set_mass(1, 1.0).add_point_mass(2, -2.0)
    with pytest.raises(fm.ModelError, match=r"negative mass of node\(s\) 2 outweighs"):
        b.build()


#: the IVP test set's solution of Andrews' squeezer at t = 0.03 s (PSIDE at 1e-14): beta,
#: theta, gamma, phi, delta, omega, epsilon [rad]
SQUEEZER_AT_003 = [0.1581077119629904e+2, -0.1575637105984298e+2, 0.4082224013073101e-1,
                   -0.5347301163226948, 0.5244099658805304, 0.5347301163226948,
                   0.1048080741042263e+1]


def test_a_lumped_rigid_body_with_negative_rotary_inertia_runs():
    """Andrews' squeezer with its bodies lumped into end masses and negative rotary
    inertias: no motion the rigid links allow has negative kinetic energy, so the model
    builds, and it reaches the test set's reference to 1e-10 of each angle."""
    model = andrews_squeezer()
    assert min(model.nodal_masses[n] for n in (12, 15, 17)) < 0
    result = fm.simulate(model, np.linspace(0.0, 0.03, 4), method="DOP853", rtol=1e-11,
                         atol=1e-13, tolerance=1e-13)
    np.testing.assert_allclose(squeezer_angles(result)[-1], SQUEEZER_AT_003, rtol=1e-10,
                               atol=1e-10)


def test_a_load_that_is_not_finite_is_named_and_the_run_returned():
    result = fm.simulate(_flex_with({}), np.linspace(0, 0.01, 5), on_failure="return",
                         forces=lambda t, x, xd: {"x5.1": np.nan if t > 0.004 else 0.0})
    assert not result.success and 2 <= len(result.t) < 5
    assert "the applied load on x5.1 (node 5, x) is not finite at t = 0.00" in result.message
    result = fm.simulate(_flex_with({}), np.linspace(0, 0.01, 5), on_failure="return",
                         forces=lambda t, x, xd: {"x5.1": np.nan})
    assert len(result.t) == 0 and "is not finite at t = 0 s" in result.message


def test_a_stiff_rod_under_rk45_gets_past_its_first_guessed_step():
    """The first step RK45 guesses for a rod of 16 beams with flexible elongations takes its
    stages beyond the reach of the position solve: the step is retried smaller instead of
    ending the run, and the motion agrees with generalized-alpha's."""
    from flexmbd.examples.slider_crank_flex import build_model, midpoint_deflection, turn_time

    model = build_model(16, eps1flex=True)
    times = np.linspace(0.0, turn_time(0.05), 6)
    explicit = fm.simulate(model, times, method="RK45", outputs="positions")
    implicit = fm.simulate(model, times, method="GeneralizedAlpha", step=turn_time(1) / 4000,
                           rho_inf=1.0, outputs="positions")
    np.testing.assert_allclose(midpoint_deflection(model, explicit.x),
                               midpoint_deflection(model, implicit.x), rtol=0, atol=2e-5)


def test_a_failure_of_an_explicit_method_on_a_stiff_model_suggests_generalized_alpha():
    from flexmbd.examples.slider_crank_flex import build_model, turn_time

    result = fm.simulate(build_model(8, eps1flex=True), np.linspace(0, turn_time(0.25), 91),
                         method="RK45", rtol=1e-2, atol=1e-5, on_failure="return")
    assert not result.success
    assert "stiff for an explicit method" in result.message
    assert "try method='GeneralizedAlpha'" in result.message
    assert "inputs cannot drive it" not in result.message


def flexible_rotor() -> fm.Model:
    """Two beams pinned at one end, spinning freely in the plane: no gravity, no damping,
    so ``T + U`` is constant. EI = 50 N m^2, rhoA = 1 kg/m, length 1 m."""
    b = fm.ModelBuilder("flexible rotor")
    b.add_node(1, 0.0, 0.0).add_node(3, 0.5, 0.0).add_node(5, 1.0, 0.0)
    for element, (p, phi_p, q, phi_q) in ((1, (1, 2, 3, 4)), (2, (3, 4, 5, 6))):
        b.add_beam(element, p, phi_p, q, phi_q).set_mass(element, 1.0)
        b.set_stiffness(element, axial=1e7, bending=50.0).dynamic_deformation(element, 2, 3)
    return b.fix(1).dynamic_coordinate(2).build()


ROTOR_START = {"x2.1": (0.0, 5.0), "e1.2": (0.0, 1.0), "e1.3": (0.0, -1.0)}
ROTOR_PERIOD = 0.02786  # s, of its first bending mode (zero crossings of e1.2 under DOP853)


def _energy(result) -> tuple[np.ndarray, float]:
    """``T + U`` over the run, and the largest kinetic energy ``T``."""
    M = fm.mass_matrix(result.model, result.x)
    kinetic = 0.5 * np.einsum("ti,tij,tj->t", result.xd, M, result.xd)
    return kinetic + 0.5 * np.sum(result.sigma * result.e, axis=1), float(kinetic.max())


@pytest.mark.parametrize("options", [{}, {"method": "GeneralizedAlpha"}])
def test_default_settings_keep_the_energy_of_a_conservative_flexible_system(options):
    """Energy drift <= 1e-4 of the kinetic energy over 100 periods of the lowest mode."""
    times = np.linspace(0.0, 100 * ROTOR_PERIOD, 100 * 40 + 1)
    result = fm.simulate(flexible_rotor(), times, initial=ROTOR_START, **options)
    energy, kinetic = _energy(result)
    assert np.max(np.abs(energy - energy[0])) <= 1e-4 * kinetic


def test_numerical_damping_is_asked_for_and_dissipates():
    times = np.linspace(0.0, 100 * ROTOR_PERIOD, 100 * 40 + 1)
    result = fm.simulate(flexible_rotor(), times, initial=ROTOR_START,
                         method="GeneralizedAlpha", rho_inf=0.8, step=ROTOR_PERIOD / 40)
    energy, kinetic = _energy(result)
    assert energy[-1] < energy[0] - 1e-4 * kinetic  # damped, as documented
    with pytest.raises(fm.ArgumentError, match="rho_inf: 1 with iterations=1: a fixed"):
        fm.simulate(flexible_rotor(), times, method="GeneralizedAlpha", iterations=1,
                    rho_inf=1.0)


@pytest.mark.parametrize("times", [[0.0, 0.1], [0.0, 1.0], [0.0, 0.5, 1.0], np.linspace(0, 1, 11)])
def test_the_output_grid_does_not_change_the_answer(times):
    """Outputs far apart (the crank turns 15 to 150 rad between them) give the rod angle
    of the closed form, asin(-l1 sin(phi) / l2), continuous, and the torque of a fine grid:
    the position solves take internal steps where the predictor would jump branches."""
    model, _ = fm.read_dat(EXAMPLES / "slider_crank_rigid.dat")
    coarse = fm.inverse_dynamics(model, times)
    phi = coarse["x2.1"]
    np.testing.assert_allclose(coarse["x4.1"], -np.arcsin(0.15 * np.sin(phi) / 0.30),
                               rtol=0, atol=1e-12)
    fine = fm.inverse_dynamics(model, np.linspace(0.0, times[-1], 2001))
    assert coarse["f2.1"][-1] == pytest.approx(fine["f2.1"][-1], rel=1e-9)


def deformation_units_from_definition(etype) -> tuple[str, ...]:
    """A deformation that changes with a translational coordinate, or scales with the
    element's length ``l0``, is a length ("m"); one that depends on rotations alone is an
    angle ("rad"), or dimensionless ("-", declared as such: an Euler normalization)."""
    import sympy as sp

    from flexmbd.elements.base import COORDINATES_PER_NODE, is_translational

    c = sp.symbols(f"c0:{etype.n_coordinates()}", real=True)
    p = list(sp.symbols(f"p0:{etype.reference}", real=True))
    translations, at = [], 0
    for role in etype.roles:
        if is_translational(role.kind):
            translations += list(c[at:at + COORDINATES_PER_NODE[role.kind]])
        at += COORDINATES_PER_NODE[role.kind]
    if etype.ends() is not None:
        translations.append(p[0])  # l0
    return tuple("m" if any(sp.diff(e, t) != 0 for t in translations)
                 else "-" if declared == "-" else "rad"
                 for e, declared in zip(etype.deformations(list(c), p, sp),
                                        etype.deformation_units, strict=True))


def test_plots_of_a_run_label_their_axes_with_units(tmp_path):
    from flexmbd.elements import ELEMENT_TYPES
    from flexmbd.plot import column_unit, plot_columns

    for etype in ELEMENT_TYPES.values():  # every element type declares them, correctly
        assert etype.deformation_units == deformation_units_from_definition(etype)
    model = _flex_with({})
    units = {name: column_unit(model, name) for name in
             ("t", "x5.1", "xd5.1", "xdd2.1", "e2.1", "ed2.2", "sig2.1", "sig2.3", "f2.1",
              "f1.2")}
    assert units == {"t": "s", "x5.1": "m", "xd5.1": "m/s", "xdd2.1": "rad/s^2", "e2.1": "m",
                     "ed2.2": "m/s", "sig2.1": "N", "sig2.3": "N", "f2.1": "N m",
                     "f1.2": "N"}
    result = fm.simulate(model, np.linspace(0, 0.01, 5))
    figure = plot_columns(result, ["e2.2", "e2.3"], "x2.1")
    axes = figure.axes[0]
    assert axes.get_ylabel() == "e2.2, e2.3 [m]" and axes.get_xlabel() == "x2.1 [rad]"


# --- redundant constraints: a chain of parallelograms whose bars align --------------------
BAR_LENGTH, SPACING, BAR_MASS, LINK_MASS, GRAVITY = 0.5, 1.0, 1.0, 0.5, 9.81


def parallelograms(loops: int) -> fm.Model:
    """``loops + 1`` equal bars (rigid beams of ``BAR_LENGTH`` m, ``BAR_MASS`` kg) pinned at
    ``x = 0, 1, 2 ...`` m and hanging straight down, their tips joined by trusses
    (``LINK_MASS`` kg): ``loops`` parallelograms moved by the first bar's angle. When the
    bars are horizontal, every bar, link and the ground line up: the constraints become
    redundant (D_c loses ``loops`` ranks) but stay consistent."""
    b = fm.ModelBuilder(f"{loops}-loop parallelogram")
    for k in range(loops + 1):
        base, angle, tip = 10 * k + 1, 10 * k + 2, 10 * k + 3
        b.add_node(base, SPACING * k, 0.0).add_node(tip, SPACING * k, -BAR_LENGTH).fix(base)
        b.add_rigid_beam(k + 1, base, angle, tip).set_mass(k + 1, BAR_MASS / BAR_LENGTH)
        if k:
            b.add_truss(100 + k, tip - 10, tip).set_mass(100 + k, LINK_MASS / SPACING)
    return b.dynamic_coordinate(2).set_gravity(0.0, -GRAVITY).build()


def test_a_simulation_goes_through_the_aligned_positions_of_redundant_loops():
    """Ten seconds of a 3-loop parallelogram turning over and over under gravity (about 23
    passages through aligned bars): positions within 1e-6 m of the one-degree-of-freedom
    motion ``J theta'' = -k cos(theta)`` (the bars turn together, the links translate;
    solved by DOP853 at 1e-12), energy kept to 1e-6 of the largest kinetic energy."""
    from scipy.integrate import solve_ivp

    loops, spin = 3, 11.0  # rad/s at the bottom: enough to go over the top
    inertia = (loops + 1) * BAR_MASS * BAR_LENGTH**2 / 3 + loops * LINK_MASS * BAR_LENGTH**2
    moment = GRAVITY * ((loops + 1) * BAR_MASS * BAR_LENGTH / 2 + loops * LINK_MASS * BAR_LENGTH)
    times = np.linspace(0.0, 10.0, 2001)
    one_dof = solve_ivp(lambda t, y: [y[1], -moment * np.cos(y[0]) / inertia],
                        (0.0, 10.0), [-np.pi / 2, spin], t_eval=times, method="DOP853",
                        rtol=1e-12, atol=1e-12).y[0]
    model = parallelograms(loops)
    result = fm.simulate(model, times, initial={"x2.1": (0.0, spin)}, method="RK45",
                         rtol=1e-10, atol=1e-12)
    for k in range(loops + 1):
        tip = 10 * k + 3
        np.testing.assert_allclose(result[f"x{tip}.1"], SPACING * k + BAR_LENGTH * np.cos(one_dof),
                                   rtol=0, atol=1e-6)
        np.testing.assert_allclose(result[f"x{tip}.2"], BAR_LENGTH * np.sin(one_dof), rtol=0,
                                   atol=1e-6)
    assert np.max(np.abs(np.cos(one_dof))) > 0.999999  # it did pass the aligned positions
    kinetic = 0.5 * np.einsum("ti,tij,tj->t", result.xd, fm.mass_matrix(model, result.x),
                              result.xd)
    energy = kinetic + moment * np.sin(-np.pi / 2 + result["x2.1"])
    assert np.max(np.abs(energy - energy[0])) <= 1e-6 * kinetic.max()


def test_outputs_between_steps_stay_on_the_branch_of_the_integration():
    """RK45 at its default tolerance through 4 parallelograms' aligned positions: each output
    is solved from the integration's extrapolated state, so none lands on the crossed
    branch (before, an output started from the last stage failed to converge at 4.2 s)."""
    model = parallelograms(4)
    result = fm.simulate(model, np.linspace(0.0, 10.0, 10001), initial={"x2.1": (0.0, 11.0)})
    for k in range(1, 5):  # every bar parallel to the first, every link horizontal
        np.testing.assert_allclose(result[f"x{10 * k + 3}.2"], result["x3.2"], rtol=0,
                                   atol=1e-8)


def energy_error(model: fm.Model, loops: int, result) -> float:
    """Largest change of the energy of ``parallelograms(loops)`` along ``result``, relative
    to its largest kinetic energy."""
    moment = GRAVITY * ((loops + 1) * BAR_MASS * BAR_LENGTH / 2 + loops * LINK_MASS * BAR_LENGTH)
    kinetic = 0.5 * np.einsum("ti,tij,tj->t", result.xd, fm.mass_matrix(model, result.x),
                              result.xd)
    energy = kinetic + moment * np.sin(-np.pi / 2 + result["x2.1"])
    return float(np.max(np.abs(energy - energy[0])) / kinetic.max())


@pytest.mark.parametrize("outputs", [2001, 5001])
@pytest.mark.parametrize("method, energy", [("RK45", 1e-4), ("GeneralizedAlpha", 5e-3)])
def test_default_runs_keep_every_output_on_the_branch_of_the_motion(outputs, method, energy):
    """RK45 and generalized-alpha at their default tolerances through 3 parallelograms'
    aligned positions: RK45's steps of 0.05 s put outputs and stages up to a step away from
    the solution they are predicted from, farther than the crossed branch is near the
    crossing. A solution whose velocities are off the motion's is solved again along the
    path from the last one, and a Newton step magnified by the nearly singular D_c is cut.
    Before, 2001 outputs had one row with 44 % more energy, and 5001 outputs stopped with
    a position solve diverging (residual 4e5). Generalized-alpha, second order, keeps the
    energy over the 23 passages to 2.5e-3 (its tolerance is relative to a crank angle that
    grows to 100 rad)."""
    model = parallelograms(3)
    result = fm.simulate(model, np.linspace(0.0, 10.0, outputs),
                         initial={"x2.1": (0.0, 11.0)}, method=method)
    assert energy_error(model, 3, result) <= energy
    for k in range(1, 4):
        np.testing.assert_allclose(result[f"xd{10 * k + 2}.1"], result["xd2.1"], rtol=0,
                                   atol=1e-6 * 11.0)


@pytest.mark.parametrize("iterations", [1, None])
def test_a_run_stopped_at_aligned_bars_is_named_a_singular_configuration(iterations):
    """A state on the crossing of 5 parallelograms, where the constraints are dependent and
    the saddle-point system has no unique multipliers, is a singular configuration with
    what to try, not "the reduced mass matrix is singular". One correction per step once
    landed a run on the crossing by round-off, which the quadratic velocity terms generated
    by jets no longer reproduce; the crossing is now given as the start, which reaches it
    every time."""
    with pytest.raises(fm.SingularConfigurationError, match="iterations=None") as caught:
        fm.simulate(parallelograms(5), np.linspace(0.0, 0.1, 11),
                    initial={"x2.1": (np.pi / 2, 11.0)}, method="GeneralizedAlpha",
                    iterations=iterations)
    assert "mass" not in str(caught.value)
    assert len(caught.value.partial_result.t) == 0


def test_generalized_alpha_keeps_the_branch_through_aligned_bars():
    """GeneralizedAlpha solves positions loosely (to its truncation error) where D_c is well
    conditioned; near aligned bars D_c magnifies that looseness into velocities of the
    crossed branch, so there the positions are solved tighter. Before, one output of this
    run gained 80 % energy and the run kept 0.5 % of it; now the energy holds to 1e-4."""
    model = parallelograms(2)
    result = fm.simulate(model, np.linspace(0.0, 10.0, 10001), initial={"x2.1": (0.0, 11.0)},
                         method="GeneralizedAlpha", step=1e-3)
    assert energy_error(model, 2, result) <= 1e-4
    np.testing.assert_allclose(result["xd22.1"], result["xd2.1"], rtol=0, atol=1e-3)


@pytest.mark.parametrize("method, options", [
    ("GeneralizedAlpha", {"step": 0.01, "iterations": 1}),
    ("GeneralizedAlpha", {"step": 0.01}),
    ("RK45", {}),
])
def test_a_diverging_motion_is_not_called_a_singular_configuration(method, options):
    """A load that drives the state out of the range of numbers makes the run fail where
    D_c or the saddle-point system can no longer be solved; the mechanism is regular
    there, so the run says that the motion diverged, not that the configuration is
    singular or the mass matrix singular."""
    b = fm.ModelBuilder("bar")
    b.add_node(1, 0, 0).add_node(3, 1, 0).add_rigid_beam(1, 1, 2, 3).fix(1)
    model = b.dynamic_coordinate(2).set_mass(1, 1.0).build()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # scipy's norms overflow too
        result = fm.simulate(model, np.linspace(0.0, 1.0, 11), method=method,
                             forces=lambda t, x, xd: {"x3.2": 1e200 * np.exp(1000 * t)},
                             on_failure="return", **options)
    assert type(result.error) is fm.SimulationError
    assert "diverge" in result.message and "singular" not in result.message
    assert len(result.t) == 1   # the start is kept
