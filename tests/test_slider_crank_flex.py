"""EXERCISES 4: the flexible slider-crank converges under refinement and behaves as expected.

The histories of ``v/l2`` over two revolutions are computed once per beam count
(linearly implicit generalized-alpha at the example's 400 steps per turn: within about
2e-4 of the step-converged history, as its help states) and shared by the tests.
"""

import math

import numpy as np
import pytest
from flexmbd.examples import slider_crank_flex as example

import flexmbd as fm

_RUNS: dict[int, fm.SimulationResult] = {}


def run(nbeams: int) -> fm.SimulationResult:
    """Two revolutions at 400 points per turn (cached)."""
    if nbeams not in _RUNS:
        result = example.simulate(nbeams, revolutions=2.0)
        assert result.success and len(result.t) == 801
        _RUNS[nbeams] = result
    return _RUNS[nbeams]


def history(nbeams: int) -> np.ndarray:
    """``v/l2`` over two revolutions."""
    result = run(nbeams)
    return example.midpoint_deflection(result.model, result.x)


def test_refinement_converges():
    assert np.max(np.abs(history(4) - history(8))) < 5e-4
    assert np.max(np.abs(history(2) - history(8))) < 2e-3


def test_energy_changes_only_by_the_work_of_the_drive():
    # kinetic + elastic energy against the integral of torque times crank speed
    assert example.energy_balance(run(8)) < 1e-3


def test_odd_beam_counts_use_the_hermite_mid_point():
    # 3 beams: the mid-point lies inside beam 3; the curve sits between 2 and 8 beams'
    result = example.simulate(3, revolutions=1.0)
    v3 = example.midpoint_deflection(result.model, result.x)
    assert np.max(np.abs(v3 - history(8)[:401])) < 1e-3


def test_expected_behaviour_of_the_exercise():
    v = history(8)
    phi = np.linspace(0.0, 4 * math.pi, 801)
    assert 0.0145 < v.max() < 0.0165 and -0.0165 < v.min() < -0.0145
    first_half = phi <= math.pi
    assert 40.0 < math.degrees(phi[first_half][np.argmax(v[first_half])]) < 55.0
    # the free vibration on top: about 130 Hz
    t = phi / example.OMEGA
    trend = np.convolve(v, np.ones(31) / 31, mode="same")
    wiggle = (v - trend)[50:-50]
    crossings = np.count_nonzero(np.diff(np.sign(wiggle)) != 0)
    frequency = crossings / 2 / (t[-51] - t[50])
    assert 100.0 < frequency < 160.0


def test_one_beam_matches_an_error_controlled_run_and_the_closed_form_deflection():
    ga = example.simulate(1, revolutions=1.0)
    rk = example.simulate(1, revolutions=1.0, method="RK45", rtol=1e-8)
    v_ga = example.midpoint_deflection(ga.model, ga.x)
    v_rk = example.midpoint_deflection(rk.model, rk.x)
    assert np.max(np.abs(v_ga - v_rk)) < 2e-4  # the accuracy the example's help states
    # one beam, rigid elongation: v = (e2 + e3) / 8 (THEORY section 10)
    np.testing.assert_allclose(v_rk, (rk["e2.2"] + rk["e2.3"]) / 8 / example.L2, atol=1e-15)


def test_flexible_elongation_oscillates_about_the_rigid_rod_force():
    times, step = example.output_times(0.5), example.turn_time(1.0) / 800
    rigid = fm.simulate(example.build_model(2), times, method="GeneralizedAlpha", step=step,
                        with_reactions=True)
    flexible = fm.simulate(example.build_model(2, eps1flex=True), times,
                           method="GeneralizedAlpha", step=step)
    assert flexible.model.n_dof == rigid.model.n_dof + 2
    # the constraint force of the rigid elongation (THEORY 8) against the elastic force
    constraint, elastic = rigid["sig2.1"], flexible["sig2.1"]
    np.testing.assert_allclose(elastic, example.EA / 0.15 * flexible["e2.1"], rtol=1e-12)
    peak = np.abs(constraint).max()
    assert abs(elastic.mean() - constraint.mean()) < 0.02 * peak
    # undamped, from an unstretched start: at most twice the quasi-static force
    assert peak < np.abs(elastic).max() < 2.1 * peak
    v_rigid = example.midpoint_deflection(rigid.model, rigid.x)
    v_flexible = example.midpoint_deflection(flexible.model, flexible.x)
    assert np.max(np.abs(v_rigid - v_flexible)) < 2e-4


def test_csv_has_the_exercise_columns_at_400_points_per_revolution(tmp_path, capsys):
    out = tmp_path / "v.csv"
    assert example.main(["--nbeams", "2", "--revolutions", "0.25", "--out", str(out)]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert header[:3] == ["t", "phi", "v_over_l2"]
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape[0] == 101
    np.testing.assert_allclose(data[:, 1], example.OMEGA * data[:, 0], rtol=1e-12)
    # the same steps as the longer run; only the last step's Newton matrix may differ
    # (renewed when round-off shortens that step), a change far below the step error
    assert np.max(np.abs(data[:, 2] - history(2)[:101])) < 1e-10


def test_the_rod_breaks_with_a_clean_error_and_the_rows_before_it(tmp_path, capsys):
    out = tmp_path / "broken.csv"
    code = example.main(["--alpha", "2e6", "--revolutions", "3", "--out", str(out)])
    printed = capsys.readouterr().out
    assert code == 1
    assert "simulation: " in printed and "at t = " in printed
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    assert 10 < len(rows) < 1200


def test_any_number_of_beams_builds():
    for nbeams in (1, 5, 10, 13):
        model = example.build_model(nbeams, eps1flex=True)
        assert model.n_dof == 1 + 3 * nbeams
    with pytest.raises(fm.ModelError, match="at least 1"):
        example.build_model(0)
