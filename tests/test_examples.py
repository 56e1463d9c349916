"""Every example runs (without windows) and reproduces the numbers of EXERCISES 1-2."""

import math

import numpy as np
import pytest
from flexmbd.examples import (
    EXAMPLES,
    slider_crank_dynamics,
    slider_crank_kinematics,
    sliding_bar,
)


def by_name(checks):
    return {c.name.split(" [")[0]: c for c in checks}


def test_sliding_bar_truss_numbers():
    checks = by_name(sliding_bar.truss_checks(sliding_bar.truss_model()))
    assert checks["y_q"].computed == pytest.approx(1.0, rel=1e-12)
    assert checks["ydot_q"].computed == pytest.approx(4 * math.sqrt(3), rel=1e-12)
    assert checks["yddot_q"].computed == pytest.approx(-64.0, rel=1e-12)
    assert all(c.passed for c in checks.values())


def test_sliding_bar_rigid_beam_numbers():
    checks = by_name(sliding_bar.rigid_beam_checks(sliding_bar.rigid_beam_model()))
    assert checks["xdot_p"].computed == pytest.approx(4.0, rel=1e-12)
    assert checks["omegadot"].computed == pytest.approx(-16 * math.sqrt(3), rel=1e-12)
    assert abs(checks["xddot_p"].computed) < 1e-12  # "with omegadot" row
    assert all(c.passed for c in checks.values())


def test_slider_crank_example_checks_and_revolution():
    model = slider_crank_kinematics.build_model()
    assert all(c.passed for c in slider_crank_kinematics.checks(model))
    r = slider_crank_kinematics.drawn_configuration(model)
    assert math.degrees(r["x4.1"][0]) == pytest.approx(-30.0, abs=1e-10)
    assert r["x5.1"][0] == pytest.approx(2.0, rel=1e-14)  # l1 cos 60 + l2 cos 30 = 2 l1
    times = np.linspace(0.0, 0.7, 50)
    import flexmbd as fm

    assert slider_crank_kinematics.revolution_error(fm.kinematic_analysis(model, times)) < 1e-10


#: arguments that keep each example's run short in the tests
QUICK = {"slider-crank-flex": ["--revolutions", "0.1"], "parallel-guide": ["--nbeams", "4"],
         "cross-spring-pivot": ["--nbeams", "2"], "flexures": [],
         "rotating-beam": ["--nbeams", "3", "--points", "20"],
         "slider-crank-dyn": ["--revolutions", "0.5", "--points", "40"]}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_every_example_runs_and_saves_plot_and_movie(name, tmp_path, capsys):
    import importlib

    module_name, preset, _ = EXAMPLES[name]
    module = importlib.import_module(f"flexmbd.examples.{module_name}")
    plot, movie = tmp_path / "plot.png", tmp_path / "movie.gif"
    quick = QUICK.get(name, ["--points", "30"])
    code = module.main([*preset, *quick, "--plot", str(plot), "--movie", str(movie)])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "checks passed" in out and "NOT all" not in out
    assert plot.stat().st_size > 10_000 and movie.stat().st_size > 10_000


def test_mp4_movie(tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    movie = tmp_path / "bar.mp4"
    assert sliding_bar.main(["--variant", "beam", "--points", "12", "--movie", str(movie)]) == 0
    assert movie.read_bytes()[4:8] == b"ftyp"  # an MP4 container


def test_sliding_bar_asked_to_go_on_says_why(capsys):
    code = sliding_bar.main(["--t-end", "1.0", "--points", "50"])
    err = capsys.readouterr().err
    assert code == 1
    assert "singular configuration at t = 1 s" in err and "x2.2 (node 2, y)" in err


def test_slider_crank_symbolic_output(capsys):
    pytest.importorskip("sympy")
    assert slider_crank_kinematics.main(["--points", "10", "--symbolic"]) == 0
    out = capsys.readouterr().out
    assert "e2.1 = sqrt((-x3_1 + x5_1)**2 + (-x3_2 + x5_2)**2) - sqrt(3)" in out
    assert "dx4.1/dphi2 =" in out


@pytest.mark.parametrize("gravity", [False, True])
def test_slider_crank_dynamics_checks(gravity):
    # Mbar lumped = consistent = closed-form J; torque = Lagrange; momentum balance
    checks = slider_crank_dynamics.checks(gravity)
    assert len(checks) == 7 and all(c.passed for c in checks), checks


def test_pd_controlled_crank_is_consistent_with_inverse_dynamics():
    result, torque, law = slider_crank_dynamics.pd_simulation(revolutions=1.0, gravity=True,
                                                              points=100)
    assert result.success
    replay = slider_crank_dynamics.replay_torque(result, gravity=True)
    assert np.max(np.abs(torque - replay)) < 1e-8 * np.max(np.abs(torque))
    # the crank is free: its driving column is zero, the controller torque is applied
    assert np.max(np.abs(result.driving)) < 1e-8 * np.max(np.abs(torque))
    # the controller keeps up: the error stays a small share of a turn
    phi_ref = np.array([law.value(t) for t in result.t])
    assert np.max(np.abs(phi_ref - result["x2.1"])) < 0.2


def test_parallel_guide_checks_and_its_spacar_file():
    """The flexure's four checks pass at 8 beams per leaf, and its .dat file is the same
    model: equal coordinates, frequencies, compliance and stroke."""
    from flexmbd.examples import EXAMPLES_DIR, parallel_guide

    import flexmbd as fm

    model = parallel_guide.build_model()
    found = parallel_guide.analyse(model)
    assert all(c.passed for c in parallel_guide.checks(found))
    read, settings = fm.read_dat(EXAMPLES_DIR / "parallel_guide.dat")
    assert read.q_labels == model.q_labels
    np.testing.assert_allclose(read.x0, model.x0, rtol=0, atol=1e-15)  # the file rounds
    statics = fm.static_equilibrium(read, load_increment=dict(settings.load_increment),
                                    steps=settings.load_steps)
    np.testing.assert_allclose(statics.x, found["statics"].x, rtol=0, atol=1e-13)
    # equal to the Newton tolerance (1e-10 of the size: the stresses to about 1e-5)
    lin = statics.linearization(0)
    np.testing.assert_allclose(fm.vibration_modes(lin, 4).frequencies,
                               found["modes"].frequencies, rtol=1e-6)
    assert 1 / fm.compliance(lin, ["x17.1"])[0, 0] == pytest.approx(found["stiffness"],
                                                                      rel=1e-6)


@pytest.mark.parametrize("nbeams, eps1flex, second_order",
                         [(1, False, False), (1, True, True), (4, False, False)])
def test_rod_frequencies_at_rest_are_pinned_pinned(nbeams, eps1flex, second_order):
    """At rest the EXERCISES 4 rod is a pinned-pinned beam: one Hermite beam gives
    sqrt(120) and sqrt(2520) exactly, four beams the continuous (k pi)^2 within 0.11
    (k/4)^4; in motion the first frequency swings around it, except for one chord beam,
    whose rotations do not change its elongation (no effect of the axial force)."""
    from flexmbd.examples import slider_crank_flex, slider_crank_modes

    import flexmbd as fm

    model = slider_crank_flex.build_model(nbeams, eps1flex, second_order=second_order)
    along = fm.modes_along(slider_crank_modes.motion(model, 13, False, 150.0), 2)
    rest = slider_crank_modes.frequencies_at_rest(model, along.t, 2)
    scale = math.sqrt(slider_crank_flex.EI * slider_crank_flex.L2
                      / slider_crank_flex.M2 / slider_crank_flex.L2**4) / (2 * math.pi)
    if nbeams == 1:
        np.testing.assert_allclose(rest, np.broadcast_to(scale * np.sqrt([120, 2520]),
                                                         rest.shape), rtol=1e-9)
    else:
        np.testing.assert_allclose(rest / scale, np.broadcast_to(
            [math.pi**2, 4 * math.pi**2], rest.shape), rtol=0.11 / 16)
    first = along.frequencies[:, 0]
    if nbeams > 1 or second_order:
        assert first.min() < 0.95 * rest[0, 0] and first.max() > 1.05 * rest[0, 0]
    else:
        assert np.ptp(first) < 0.01 * rest[0, 0]
    np.testing.assert_allclose(along.frequencies, along.frequencies[::-1], rtol=1e-10)


def test_cross_spring_pivot_checks_and_its_rotation():
    """The spatial flexure's checks pass at 4 beams per leaf, its body turns by the 30
    degrees of its Euler-parameter input, and the two leaves bend alike (the pivot's
    symmetry): the same largest deflection from their chords."""
    from flexmbd.examples import cross_spring_pivot as pivot

    found = pivot.analyse(4)
    assert all(c.passed for c in pivot.checks(found))
    angle, moment = found["curve"]
    assert np.degrees(angle[-1]) == pytest.approx(30.0, abs=1e-3)
    assert np.all(np.diff(moment) > 0)
    statics = found["statics"]
    bending = [np.abs(statics[f"e{element}.3"][-1]) + np.abs(statics[f"e{element}.4"][-1])
               for element in (1 + 1, pivot.SECOND + 3)]   # mirror images in the two leaves
    assert bending[0] == pytest.approx(bending[1], rel=1e-6)


def test_flexures_through_the_front_door(capsys):
    """SPACAR Light's examples ported (their checks: 2EI/L, the guide's gain and
    stiffness, Rayleigh's frequency, four wires' buckling), and the guide study's
    support stiffness 2EA/L at zero stroke and FLEXURES 7's 7.877e7 N/m at 1 mm, its
    stress 3Etu/L^2 to 2 % at a small stroke."""
    from flexmbd.examples import flexures

    assert flexures.main([]) == 0
    assert "all 5 checks passed" in capsys.readouterr().out
    data = flexures.guide_study([0.0, 1e-4, 1e-3], [0.5e-3], client="serial", progress=False)
    assert list(data["status"]) == ["ok"] * 3
    stiffness, stress = data["support_stiffness"].to_numpy(), data["peak_stress"].to_numpy()
    E, L, t = flexures.STEEL_E, flexures.LENGTH, 0.5e-3
    assert stiffness[0] == pytest.approx(2 * E * flexures.WIDTH * t / L, rel=1e-9)
    assert stiffness[2] == pytest.approx(7.877e7, rel=1e-3)
    assert stress[1] == pytest.approx(3 * E * t * 1e-4 / L**2, rel=2e-2)


def test_a_planar_movie_redraws_only_what_moves(tmp_path):
    """The planar path draws axes, ticks and legend once: every frame of the GIF is there,
    the axes' labels sit still and the mechanism moves between frames."""
    from flexmbd.examples.slider_crank_flex import build_model
    from PIL import Image

    import flexmbd as fm
    from flexmbd import plot

    run = fm.simulate(build_model(nbeams=2), np.linspace(0.0, 0.04, 13))
    assert plot.animate(run, tmp_path / "crank.gif") is None
    frames = []
    with Image.open(tmp_path / "crank.gif") as movie:
        assert movie.n_frames == 13 and movie.size == (700, 550)
        for k in (0, 12):
            movie.seek(k)
            frames.append(np.asarray(movie.convert("L"), dtype=float))
    assert np.abs(frames[0][500:, :] - frames[1][500:, :]).max() < 40   # x-axis label
    assert np.abs(frames[0][80:480, 80:640] - frames[1][80:480, 80:640]).max() > 100
