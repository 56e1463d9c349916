"""Moments on spatial rotational nodes: a global moment ``M`` loads the Euler parameters
with ``2 E(lam)^T M``, formed at every state (the spatial theory, sections 5 and 6).

Checked against a different formulation (the planar beam, whose torque is a plain
generalized force on its angle), a closed form (a rigid rotor spun up by a constant
moment through several re-partitions) and finite differences (the static tangent's load
stiffness)."""

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.analysis.linearization import load_stiffness, static_tangent
from flexmbd.engine import Workspace

SPAN, EA, GIT, EIY, EIZ = 1.3, 2e7, 30.0, 50.0, 80.0


def spatial_cantilever(n: int, moment=(0.0, 0.0, 0.0)) -> fm.Model:
    """``n`` spatial beams along X (orientation Y), clamped at node 1, a global moment at
    the tip's rotational node ``2 n + 2``; elongations rigid, bending-linked terms off."""
    b = fm.ModelBuilder("spatial cantilever")
    for k in range(n + 1):
        b.add_node(1 + 2 * k, SPAN * k / n, 0, 0)
    for k in range(n):
        b.add_spatial_beam(k + 1, 1 + 2 * k, 2 + 2 * k, 3 + 2 * k, 4 + 2 * k,
                           orientation=(0, 1, 0), bending_linked=False)
        b.set_stiffness(k + 1, torsion=GIT, bending_y=EIY, bending_z=EIZ)
        b.dynamic_deformation(k + 1, 2, 3, 4, 5, 6)
    b.fix(1).fix(2)
    if any(moment):
        b.add_force(2 * n + 2, *moment)
    return b.build()


def planar_cantilever(n: int, torque: float) -> fm.Model:
    b = fm.ModelBuilder("planar cantilever")
    for k in range(n + 1):
        b.add_node(1 + 2 * k, SPAN * k / n, 0)
    for k in range(n):
        b.add_beam(k + 1, 1 + 2 * k, 2 + 2 * k, 3 + 2 * k, 4 + 2 * k)
        b.set_stiffness(k + 1, bending=EIZ)
        b.dynamic_deformation(k + 1, 2, 3)
    b.fix(1).fix(2)
    b.add_force(2 * n + 2, torque)
    return b.build()


def test_end_moment_bends_the_spatial_cantilever_as_the_planar_one():
    """A moment about Z large enough to turn the tip by about 1.2 rad, in 6 load steps:
    the spatial beams follow the planar ones (the same deformations in the plane) to
    round-off at every step."""
    torque = 1.2 * EIZ / SPAN
    n, steps = 4, 6
    spatial = fm.static_equilibrium(spatial_cantilever(n), steps=steps,
                                    load_increment={f"x{2 * n + 2}.4": torque})
    planar = fm.static_equilibrium(planar_cantilever(n, 0.0), steps=steps,
                                   load_increment={f"x{2 * n + 2}.1": torque})
    for axis in (1, 2):
        np.testing.assert_allclose(spatial[f"x{2 * n + 1}.{axis}"],
                                   planar[f"x{2 * n + 1}.{axis}"], atol=1e-10)
    np.testing.assert_allclose(spatial[f"x{2 * n + 1}.3"], 0.0, atol=1e-12)
    angle = fm.axis_angle(spatial.euler_parameters(2 * n + 2))[1]
    np.testing.assert_allclose(angle, planar[f"x{2 * n + 2}.1"], atol=1e-10)
    assert angle[-1] > 1.0


def test_constant_moment_of_the_model_equals_the_same_load_given_to_the_run():
    """``add_force`` on a rotational node (the model's XF) and ``loads`` of
    ``static_equilibrium`` are the same global moment."""
    moment = (0.4, -0.9, 2.0)
    own = fm.static_equilibrium(spatial_cantilever(3, moment))
    given = fm.static_equilibrium(spatial_cantilever(3),
                                  loads={f"x8.{k + 2}": m for k, m in enumerate(moment)})
    np.testing.assert_allclose(own.x, given.x, atol=1e-13)
    assert np.abs(own.x[0] - own.model.x0).max() > 0.01


def test_static_tangent_includes_the_load_stiffness_of_a_moment():
    """At a state loaded by a skew moment the tangent ``K0 + G0`` equals central
    differences of the out-of-balance loads along every ``q``."""
    model = spatial_cantilever(2, (3.0, -20.0, 40.0))
    x = fm.static_equilibrium(model).x[0]
    engine = Workspace(model)
    loads = np.zeros(model.n_coordinates)
    state, tangent = static_tangent(engine, x, loads)
    q0, h = state["q"], 1e-6
    differences = np.empty_like(tangent)
    for j in range(model.n_dof):
        columns = []
        for sign in (1, -1):
            q = q0.copy()
            q[j] += sign * h
            moved = engine.positions(q, x)
            columns.append(static_tangent(engine, moved, loads)[0]["driving"])
        differences[:, j] = (columns[0] - columns[1]) / (2 * h)
    np.testing.assert_allclose(tangent, differences, atol=1e-6 * np.abs(tangent).max())
    # the moment's own share, - F_q^T (df/dx) F_q, is what makes it exact
    F_q = engine.transfer(state["x"])
    share = F_q.T @ load_stiffness(engine, loads) @ F_q
    assert np.abs(tangent + share - differences).max() > 1e-3 * np.abs(tangent).max()


def rotor() -> fm.Model:
    """A rigid body turning freely about the fixed point 1 (three dynamic Euler
    parameters), ``Jb = diag(1, 2, 3)``."""
    b = fm.ModelBuilder("rotor")
    b.add_node(1, 0, 0, 0).add_node(3, 1, 0, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 1, 0))
    b.fix(1).dynamic_coordinate(2, 2, 3, 4)
    b.add_rotary_inertia(2, 1.0, 0, 0, 2.0, 0, 3.0)
    return b


@pytest.mark.parametrize("given", ["model", "forces"])
def test_constant_moment_spins_a_rotor_up(given):
    """A moment of 1.5 N m about Z on ``Jzz = 3`` turns the body by ``M t^2/(2 Jzz)``:
    two turns in 7.1 s, through re-partitions, whether the moment is the model's or a
    run's ``forces``."""
    b, moment = rotor(), 1.5
    forces = None
    if given == "model":
        b.add_force(2, 0.0, 0.0, moment)
    else:
        def forces(t, x, xd):
            return {"x2.4": moment}
    model = b.build()
    t = np.linspace(0, 7.1, 72)
    result = fm.simulate(model, t, forces=forces, method="DOP853", rtol=1e-12, atol=1e-14)
    angle = moment * t**2 / (2 * 3.0)
    lam = result.euler_parameters(2)
    np.testing.assert_allclose(lam[:, 0], np.cos(angle / 2), atol=1e-9)
    np.testing.assert_allclose(lam[:, 3], np.sin(angle / 2), atol=1e-9)
    np.testing.assert_allclose(result.angular_velocity(2)[:, 2], moment * t / 3.0, atol=1e-9)
    assert angle[-1] > 4 * np.pi and result.stats["repartitions"] == 4


def test_a_load_on_lam0_is_refused():
    model = rotor().build()
    with pytest.raises(fm.ArgumentError, match=r"loads: a load on x2\.1, lam0 of a spatial "
                                               r"rotational node.*x2\.2 to x2\.4"):
        fm.static_equilibrium(model, loads={"x2.1": 1.0})


def test_reactions_on_a_rotational_node_are_moments():
    """A skew tip force on the cantilever: the clamp's reactions are the force ``-F`` and
    the moment ``-(r x F)`` (its lam0 entry zero), the planar model's torque in the plane."""
    n, force = 3, np.array([0.3, 1.0, -0.7])
    loaded = fm.static_equilibrium(spatial_cantilever(n), loads={
        f"x{2 * n + 1}.{k + 1}": f for k, f in enumerate(force)})
    tip = np.array([loaded[f"x{2 * n + 1}.{k}"][0] for k in (1, 2, 3)])
    support = np.array([loaded[f"f1.{k}"][0] for k in (1, 2, 3)])
    moment = np.array([loaded[f"f2.{k}"][0] for k in (2, 3, 4)])
    np.testing.assert_allclose(support, -force, atol=1e-9)
    np.testing.assert_allclose(moment, -np.cross(tip, force), atol=1e-9)
    assert loaded["f2.1"][0] == 0.0
    planar = fm.static_equilibrium(planar_cantilever(n, 0.0), loads={f"x{2 * n + 1}.2": 1.0})
    straight = fm.static_equilibrium(spatial_cantilever(n), loads={f"x{2 * n + 1}.2": 1.0})
    assert straight["f2.4"][0] == pytest.approx(planar["f2.1"][0], abs=1e-9)


def test_a_moment_turns_a_spring_hinge_through_two_turns_in_load_steps():
    """A spatial hinge with a rotational spring ``k`` under a growing moment about its axis
    turns by ``M/k`` at every load step, through 2.2 turns: statics and the linearization
    of its last row keep the rotation beyond half a turn (``x`` alone gives it only
    within half a turn), so the spring's stress and the equilibrium stay right."""
    k, turns, steps = 2.0, 2.2, 24
    b = fm.ModelBuilder("spring hinge")
    b.add_spatial_hinge(1, 1, 2).fix(1).dynamic_deformation(1, 1).set_stiffness(1, hinge=k)
    model = b.build()
    moment = k * turns * 2 * np.pi
    statics = fm.static_equilibrium(model, load_increment={"x2.4": moment}, steps=steps)
    np.testing.assert_allclose(statics["e1.1"], statics["load"] * moment / k, atol=1e-9)
    np.testing.assert_allclose(statics["sig1.1"], statics["load"] * moment, atol=1e-8)
    lin = statics.linearization()
    np.testing.assert_allclose(lin.driving, 0.0, atol=1e-8)
    assert 1 / fm.compliance(lin, ["x2.4"])[0, 0] == pytest.approx(k, rel=1e-12)
