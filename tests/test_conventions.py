"""One argument convention across the analyses: the model and its grid or state by
position, everything else by name, spelled alike; the old spellings work for a release
with a DeprecationWarning that says what to write instead."""

import inspect

import numpy as np
import pytest
from flexmbd.examples import parallel_guide
from flexmbd.examples.slider_crank_flex import build_model

import flexmbd as fm
from flexmbd import checks
from flexmbd.engine import MAX_ITERATIONS

MODEL = build_model(1)
TIMES = np.linspace(0.0, 0.002, 3)
DRIVE = {"x2.1": fm.Polynomial(0.0, 100.0)}

#: the analyses and the parameters each takes by position
ANALYSES = {
    fm.kinematic_analysis: ("model", "times"),
    fm.simulate: ("model", "times"),
    fm.inverse_dynamics: ("model", "times"),
    fm.static_equilibrium: ("model",),
    fm.linearize: ("model", "x", "qd", "qdd"),
    fm.modes_along: ("result", "count"),
}


@pytest.mark.parametrize("analysis", list(ANALYSES), ids=lambda f: f.__name__)
def test_only_the_model_and_its_grid_or_state_go_by_position(analysis):
    parameters = inspect.signature(analysis).parameters.values()
    positional = tuple(p.name for p in parameters
                       if p.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD)
    assert positional == ANALYSES[analysis]


def test_shared_options_are_spelled_and_defaulted_alike():
    seen: dict[str, set] = {}
    for analysis in ANALYSES:
        for p in inspect.signature(analysis).parameters.values():
            if p.name in ("tolerance", "max_iterations", "on_failure", "progress", "inputs"):
                seen.setdefault(p.name, set()).add(p.default)
    assert seen["max_iterations"] == {MAX_ITERATIONS}
    assert seen["tolerance"] == {None} and seen["progress"] == {None}
    assert seen["on_failure"] == {"raise"} and seen["inputs"] == {None}
    # every run over a grid takes each of them
    for analysis in (fm.kinematic_analysis, fm.simulate, fm.inverse_dynamics):
        names = inspect.signature(analysis).parameters
        assert {"inputs", "tolerance", "max_iterations", "on_failure", "progress"} <= set(names)


@pytest.mark.parametrize("analysis", [fm.kinematic_analysis, fm.inverse_dynamics],
                         ids=lambda f: f.__name__)
def test_inputs_by_position_still_arrive_with_a_warning(analysis):
    by_name = analysis(MODEL, TIMES, inputs=DRIVE)
    with pytest.warns(DeprecationWarning, match="give inputs=... by name"):
        by_position = analysis(MODEL, TIMES, DRIVE)
    assert np.array_equal(by_position.x, by_name.x)
    # and they are the drive's, not the model's own law
    assert not np.array_equal(by_name.x, analysis(MODEL, TIMES).x)


def test_too_many_or_twice_given_arguments_are_refused():
    with pytest.raises(TypeError, match="positional"):
        fm.kinematic_analysis(MODEL, TIMES, DRIVE, None)
    with pytest.raises(TypeError, match="twice"):
        fm.kinematic_analysis(MODEL, TIMES, DRIVE, inputs=DRIVE)


def test_the_old_spellings_of_progress_and_the_workspace_warn():
    along_by_name = fm.modes_along(fm.kinematic_analysis(MODEL, TIMES), 1, progress=False)
    with pytest.warns(DeprecationWarning, match="progress"):
        along = fm.modes_along(fm.kinematic_analysis(MODEL, TIMES), 1, False)
    assert np.array_equal(along.frequencies, along_by_name.frequencies)
    workspace = fm.Workspace(MODEL)
    with pytest.warns(DeprecationWarning, match="workspace="):
        old = fm.linearize(MODEL, engine=workspace)
    assert np.array_equal(old.K0, fm.linearize(MODEL, workspace=workspace).K0)


def test_a_static_result_names_its_load_factor_load():
    guide = parallel_guide.build_model()
    statics = fm.static_equilibrium(guide, load_increment={"x5.1": 1.0}, steps=4)
    assert np.array_equal(statics.load, [0.0, 0.25, 0.5, 0.75, 1.0])
    assert np.array_equal(statics["load"], statics.load)
    with pytest.warns(DeprecationWarning, match="read it as .load"):
        old = statics.t
    assert np.array_equal(old, statics.load)


def test_a_deprecation_says_until_when():
    with pytest.warns(DeprecationWarning, match=checks.REFUSED_FROM):
        fm.kinematic_analysis(MODEL, TIMES, DRIVE)


def test_a_workspace_of_another_model_is_refused_by_name():
    other = fm.Workspace(parallel_guide.build_model())
    with pytest.raises(fm.ArgumentError, match="workspace: is a workspace of"):
        fm.linearize(MODEL, workspace=other)


def test_loads_a_model_lacks_are_argument_errors_naming_the_argument():
    guide = parallel_guide.build_model()
    for argument in ("loads", "load_increment"):
        with pytest.raises(fm.ArgumentError, match=rf"^{argument}: x77\.1: node 77"):
            fm.static_equilibrium(guide, **{argument: {"x77.1": 1.0}})
    with pytest.raises(fm.ArgumentError, match=r"^loads: x77\.1"):
        fm.linearize(guide, loads={"x77.1": 1.0})


def test_forces_of_the_wrong_shape_end_the_run_at_that_time():
    def forces(t, x, xd):
        return np.zeros(3 if t > 0.001 else len(x))

    said = r"^forces: must be loads \[N, N m\], an array \(9,\) .*, returned at t = "
    with pytest.raises(fm.SimulationError, match=said) as err:
        fm.simulate(MODEL, TIMES, forces=forces, method="GeneralizedAlpha", step=2.5e-4)
    assert 0.001 < err.value.time <= 0.001 + 2.5e-4
    assert err.value.partial_result.t[-1] <= 0.001 + 1e-12   # the run so far is kept


def test_loads_that_are_not_finite_are_refused_by_coordinate():
    guide = parallel_guide.build_model()
    with pytest.raises(fm.ArgumentError, match=r"^loads: the load on x5\.1 \(node 5, x\) "
                                               r"is nan"):
        fm.static_equilibrium(guide, loads={"x5.1": np.nan})
    loads = np.zeros(guide.n_coordinates)
    loads[guide.coordinate_index("x5.2")] = np.inf
    with pytest.raises(fm.ArgumentError, match=r"^load_increment: the load on x5\.2"):
        fm.static_equilibrium(guide, load_increment=loads)
