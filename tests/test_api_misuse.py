"""Misuse of the Python API ends in flexmbd's own errors, which name the argument, and in
bounded time; laws may be given as expressions in t."""

import math
import os
import time
from pathlib import Path

import numpy as np
import pytest
import sympy
from flexmbd.examples.slider_crank_flex import build_model
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import flexmbd as fm

from .models import two_beam_column

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

MODEL = build_model(1)
TIMES = np.linspace(0.0, 0.004, 5)
REST = np.zeros(MODEL.n_dof)


#: the column pressed along its axis, linearized
LINEAR = fm.linearize(two_beam_column(), loads={"x5.1": -1.0})
#: no single call may take longer than this [s]
BOUND = 10.0

BAD = [None, True, "x", "tight", -1, 0, 0.5, 2.5, 10**9, -1e-300, math.nan, math.inf, 1e300,
       [], [1.0, 2.0], np.zeros((2, 2)), {}, {"x9.1": 1.0}, {"e2.2": (math.nan, 0.0)},
       {"e2.2": "a"}, (1, 2, 3), lambda *a: None, lambda *a: 1 / 0, object()]

#: the analyses and the arguments that a user may get wrong, with what the message names
CALLS = {
    "simulate": (lambda **kw: fm.simulate(MODEL, TIMES, **kw),
                 ["rtol", "atol", "max_step", "method", "tolerance", "max_iterations",
                  "outputs", "initial", "inputs", "forces", "on_failure", "progress",
                  "with_reactions"]),
    "simulate_alpha": (lambda **kw: fm.simulate(MODEL, TIMES, method="GeneralizedAlpha", **kw),
                       ["step", "iterations", "renew_every", "rho_inf", "rtol", "atol",
                        "first_step", "max_step"]),
    "kinematic_analysis": (lambda **kw: fm.kinematic_analysis(MODEL, TIMES, **kw),
                           ["tolerance", "max_iterations", "inputs", "on_failure"]),
    "inverse_dynamics": (lambda **kw: fm.inverse_dynamics(MODEL, TIMES, **kw),
                         ["tolerance", "max_iterations", "inputs", "forces", "on_failure",
                          "with_reactions", "progress"]),
    "static_equilibrium": (lambda **kw: fm.static_equilibrium(MODEL, **kw),
                           ["loads", "load_increment", "input_increment", "steps",
                            "tolerance", "max_iterations", "on_failure", "progress",
                            "method"]),
    "linearize": (lambda **kw: fm.linearize(MODEL, **kw),
                  ["x", "qd", "qdd", "loads", "tolerance", "max_iterations", "workspace",
                   "e"]),
    "vibration_modes": (lambda count: fm.vibration_modes(LINEAR, count), ["count"]),
    "buckling": (lambda count: fm.buckling(LINEAR, count), ["count"]),
    "compliance": (lambda labels: fm.compliance(LINEAR, labels), ["labels"]),
    "state_space": (lambda **kw: fm.state_space(LINEAR, **{"inputs": ["x5.2"], **kw}),
                    ["inputs", "outputs", "rate_outputs", "damping_ratio"]),
    "times": (lambda times: fm.simulate(MODEL, times), ["times"]),
    "velocities": (lambda x=MODEL.x0, qd=REST: fm.velocities(MODEL, x, qd), ["x", "qd"]),
    "solve_position": (lambda q=REST, x_guess=None: fm.solve_position(MODEL, q, x_guess),
                       ["q", "x_guess"]),
    "mass_matrix": (lambda x: fm.mass_matrix(MODEL, x), ["x"]),
}


def _names_its_source(error: fm.FlexmbdError, argument: str) -> bool:
    """The message names the argument, a label of the model, or the time of a failure."""
    text = str(error)
    failed_run = isinstance(error, fm.SimulationError) and error.time is not None
    labels = (*MODEL.coordinate_labels, *MODEL.q_labels)
    return argument in text or failed_run or any(label in text for label in labels)


@settings(max_examples=300 if os.environ.get("CI") else 150, deadline=None,
          derandomize=bool(os.environ.get("CI")), suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(sorted(CALLS)), st.data())
def test_misuse_raises_only_flexmbd_errors_naming_the_argument(call, data):
    function, arguments = CALLS[call]
    argument = data.draw(st.sampled_from(arguments))
    value = data.draw(st.sampled_from(BAD))
    start = time.perf_counter()
    try:
        function(**{argument: value})
    except fm.FlexmbdError as error:
        assert _names_its_source(error, argument), (call, argument, value, str(error))
    except (fm.AnalysisWarning, fm.ModelWarning) as warning:   # the suite raises warnings:
        assert argument in str(warning), (call, argument, value, str(warning))  # a caveat
    except Exception as error:  # anything else is what the test is about
        pytest.fail(f"{call}({argument}={value!r}) raised {type(error).__name__}: {error}")
    assert time.perf_counter() - start < BOUND


@pytest.mark.parametrize("element_type", ["truss", "PLTRUSS", fm.Truss])
def test_element_types_by_name_or_keyword(element_type):
    b = fm.ModelBuilder("bar").add_node(1, 0.0, 0.0).add_node(2, 1.0, 0.0)
    b.add_element(1, element_type, (1, 2)).fix(1).fix(2, "y").dynamic_deformation(1)
    model = b.set_mass(1, 1.0).set_stiffness(1, axial=1.0).build()
    assert model.elements[1].type is fm.Truss
    with pytest.raises(fm.ModelError, match="the element type must be one of 'truss'"):
        fm.ModelBuilder("bar").add_element(1, "girder", (1, 2)).build()


def test_a_law_given_as_an_expression_in_t_has_its_derivatives():
    """``"0.5 + 150 t"`` is the polynomial law; a SymPy ``sin`` has the exact rate and
    acceleration (checked against ``cos`` and ``-sin``)."""
    by_text = fm.kinematic_analysis(MODEL, TIMES, inputs={"x2.1": "0.5 + 150*t"})
    by_law = fm.kinematic_analysis(MODEL, TIMES, inputs={"x2.1": fm.Polynomial(0.5, 150.0)})
    np.testing.assert_array_equal(by_text.x, by_law.x)
    t = sympy.Symbol("t")
    wave = fm.Expression(0.3 * sympy.sin(40 * t))
    for s in (0.0, 0.01, 0.02):
        assert wave(s) == pytest.approx((0.3 * math.sin(40 * s), 12 * math.cos(40 * s),
                                         -480 * math.sin(40 * s)), rel=1e-14, abs=1e-14)
    with pytest.raises(fm.ArgumentError, match="may depend on t only, not on omega"):
        fm.Expression("omega*t")
    with pytest.raises(fm.ModelError, match="is not an expression in t"):
        fm.ModelBuilder("x").add_node(1, 0, 0).input_coordinate(1, "x", law="t +* 2").build()


def test_a_failing_user_function_is_named_and_keeps_the_run():
    def law(t):
        if t > 0.002:
            raise ZeroDivisionError("division by zero")
        return (150 * t, 150.0, 0.0)

    result = fm.kinematic_analysis(MODEL, TIMES, inputs={"x2.1": law}, on_failure="return")
    assert not result.success and len(result.t) == 3
    assert "the law of x2.1 (node 2, phi) raised ZeroDivisionError" in result.message
    assert isinstance(result.error.__cause__, ZeroDivisionError)


@pytest.mark.parametrize("given, meant", [("X5.1", "'x5.1'"), ("phi2", "'x2.1'"),
                                          ("v5.1", "'xd5.1'"), ("acc5.2", "'xdd5.2'"),
                                          ("sigma2.2", "'sig2.2'"), ("x5.9", "'x5.1'"),
                                          ("e2.7", "'e2.3'"), ("t0", "'t'")])
def test_a_column_that_names_nothing_gets_the_closest_and_the_scheme(given, meant):
    """Other tools' names (v for a velocity, phi2 for node 2's angle), case and spelling:
    the closest real columns first, then how columns are named."""
    model = fm.read_dat(EXAMPLES / "slider_crank_flex.dat").model
    result = fm.simulate(model, np.linspace(0.0, 0.01, 5))
    with pytest.raises(fm.ColumnError) as caught:
        result[given]
    text = str(caught.value)
    assert f"did you mean {meant}" in text and "coordinates are x<node>.<k>" in text


def test_a_coordinate_label_by_direction_name_is_pointed_at_its_label():
    model = fm.read_dat(EXAMPLES / "slider_crank_flex.dat").model
    with pytest.raises(fm.LabelError, match=r"did you mean 'x5\.2'"):
        model.coordinate_index("y5")
    with pytest.raises(fm.LabelError, match=r"did you mean 'e2\.2'"):
        model.deformation_index("e2.22")


def test_a_misspelled_keyword_of_a_file_gets_the_closest(tmp_path):
    path = tmp_path / "arm.dat"
    path.write_text("PLBEM 1 1 2 3 4\nX 1 0 0\nX 3 1 0\nFIX 1\nFIX 2\nEND\nEND\n")
    with pytest.raises(fm.InputFileError, match="did you mean PLBEAM"):
        fm.read_dat(path)
