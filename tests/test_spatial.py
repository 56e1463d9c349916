"""Spatial models on the one engine, against closed forms and the planar model
(the verification cases of the spatial theory, section 8).

The element kernels themselves are checked against their definitions in
``test_elements.py``; here whole models: kinematics and inverse dynamics of a
slider-crank of spatial elements, the flexible slider-crank of spatial beams against
the planar one, and a spatial cantilever's compliance and frequencies.
"""

import math

import numpy as np
import pytest
from flexmbd.examples import slider_crank_flex as planar_flex
from flexmbd.examples import slider_crank_flex_spatial as spatial_flex

import flexmbd as fm

R, L = 0.15, 0.30   # crank and rod [m]
OMEGA = 150.0       # crank speed [rad/s]


def slider_crank(masses=(0.2, 0.3)) -> fm.Model:
    """Crank O-A and rod A-B as two rigid spatial beams, a driven hinge at O and a pin at
    A (spatial hinges about Z), slider B on the x axis (its y fixed; z follows from the
    hinges, fixing it too would over-constrain)."""
    b = fm.ModelBuilder("spatial slider-crank")
    b.add_node(1, 0, 0, 0).add_node(2, R, 0, 0).add_node(3, R + L, 0, 0)
    b.add_spatial_beam(1, 1, 12, 2, 13, orientation=(0, 0, 1))
    b.add_spatial_beam(2, 2, 14, 3, 15, orientation=(0, 0, 1))
    b.add_spatial_hinge(3, 11, 12).add_spatial_hinge(4, 13, 14)
    b.fix(1).fix(11).fix(3, "y")
    b.input_deformation(3, 1, law=fm.Polynomial(0.0, OMEGA))
    b.release(4, 1)
    b.add_point_mass(2, masses[0]).add_point_mass(3, masses[1])
    return b.build()


def slider_position(phi):
    """``x_B`` and its first two derivatives with respect to the crank angle."""
    s, c = np.sin(phi), np.cos(phi)
    root = np.sqrt(L**2 - R**2 * s**2)
    x = R * c + root
    dx = -R * s - R**2 * s * c / root
    ddx = -R * c - R**2 * (c**2 - s**2) / root - R**4 * s**2 * c**2 / root**3
    return x, dx, ddx


def test_spatial_slider_crank_follows_the_closed_form_through_two_turns():
    """Positions, velocities and accelerations of the slider to round-off while the
    driven hinge angle passes pi and 2 pi (its atan2 is kept continuous), z stays 0."""
    model = slider_crank()
    t = np.linspace(0.0, 4 * np.pi / OMEGA, 97)
    result = fm.kinematic_analysis(model, t)
    x, dx, ddx = slider_position(OMEGA * t)
    i = model.coordinate_index("x3.1")
    np.testing.assert_allclose(result.x[:, i], x, atol=1e-14)
    np.testing.assert_allclose(result.xd[:, i], dx * OMEGA, atol=1e-11)
    np.testing.assert_allclose(result.xdd[:, i], ddx * OMEGA**2, atol=1e-8)
    np.testing.assert_array_equal(result.x[:, model.coordinate_index("x3.3")], 0.0)
    np.testing.assert_allclose(result.e[:, model.deformation_index("e3.1")], OMEGA * t,
                               atol=1e-12)
    # the Euler parameters stay normalized
    for node in (12, 13, 14, 15):
        lam = result.x[:, [model.coordinate_index(f"x{node}.{k}") for k in range(1, 5)]]
        np.testing.assert_allclose(np.sum(lam**2, axis=1), 1.0, atol=1e-12)


def test_spatial_slider_crank_driving_torque():
    """At constant crank speed only the slider's kinetic energy changes: the driving
    torque is ``m_B x_B' x_B'' omega^2``: on 5-degree steps its largest value is the
    theory's 127.967 N m (the continuous maximum is 128.238 N m)."""
    model = slider_crank()
    t = np.linspace(0.0, 2 * np.pi / OMEGA, 73)
    driving = fm.inverse_dynamics(model, t).driving[:, 0]
    _, dx, ddx = slider_position(OMEGA * t)
    np.testing.assert_allclose(driving, 0.3 * dx * ddx * OMEGA**2, atol=1e-11)
    assert np.max(np.abs(driving)) == pytest.approx(127.967, abs=5e-4)


def flexible_slider_crank(nbeams: int, bending_linked: bool) -> fm.Model:
    """EXERCISES 4's flexible slider-crank of spatial beams and hinges in the XY plane."""
    return spatial_flex.build_model(nbeams, bending_linked)


@pytest.fixture(scope="module")
def planar_run():
    t = np.linspace(0.0, 2 * np.pi / OMEGA, 41)
    model = planar_flex.build_model(2)
    return model, fm.simulate(model, t, method="GeneralizedAlpha", step=t[-1] / 400)


@pytest.mark.parametrize("linked", [False, True], ids=["basic", "bending-linked"])
def test_flexible_slider_crank_of_spatial_beams_equals_the_planar_model(planar_run, linked):
    """Without the bending-linked terms and with rigid elongations, deformations, mass
    and stiffness coincide term by term: the same motion to round-off (the in-plane
    pair is minus the planar one). With the terms on, the rigid elongation holds the
    arc length instead of the chord: the rod shortens by ``c1``, of the order
    ``(8/3)(v/l)^2 l``, and the motion differs at that order."""
    planar, reference = planar_run
    model = flexible_slider_crank(2, linked)
    run = fm.simulate(model, reference.t, method="GeneralizedAlpha",
                      step=reference.t[-1] / 400)
    difference, size, arc = 0.0, 0.0, 0.0
    for element in (2, 3):
        e3, e4 = (run.e[:, model.deformation_index(f"e{element}.{k}")] for k in (3, 4))
        arc = arc + (2 * e3**2 + e3 * e4 + 2 * e4**2) / (30 * L / 2)  # c1 of each beam
        for k_planar, e_spatial in ((2, e3), (3, e4)):
            e_planar = reference.e[:, planar.deformation_index(f"e{element}.{k_planar}")]
            difference = max(difference, np.max(np.abs(e_planar + e_spatial)))
            size = max(size, np.max(np.abs(e_planar)))
    slider = (reference.x[:, planar.coordinate_index("x5.1")]
              - run.x[:, model.coordinate_index("x5.1")])
    if not linked:
        assert difference < 1e-10 * L and np.max(np.abs(slider)) < 1e-10 * L
    else:  # the rod is shorter by the arc beyond its beams' chords: the slider comes closer
        assert 0.5 < np.max(np.abs(slider)) / np.max(arc) < 2.0
        assert np.max(arc) > 1e-5
        assert difference < 0.1 * size


SPAN, EA, GIT, EIY, EIZ = 1.3, 2e7, 30.0, 50.0, 80.0


def cantilever(n: int, shear=(0.0, 0.0), mass: bool = False) -> fm.Model:
    """``n`` spatial beams along X (orientation Y: ``EIz`` bends in the XY plane), clamped
    at node 1 with its rotational node 2; the tip is node ``2 n + 1``."""
    b = fm.ModelBuilder("spatial cantilever")
    for k in range(n + 1):
        b.add_node(1 + 2 * k, SPAN * k / n, 0, 0)
    for k in range(n):
        b.add_spatial_beam(k + 1, 1 + 2 * k, 2 + 2 * k, 3 + 2 * k, 4 + 2 * k,
                           orientation=(0, 1, 0))
        b.set_stiffness(k + 1, axial=EA, torsion=GIT, bending_y=EIY, bending_z=EIZ,
                        shear_y=shear[0], shear_z=shear[1])
        if mass:
            b.set_mass(k + 1, 2.0, section_inertia=(0.0026, 0.0, 0.0, 0.0))
        b.dynamic_deformation(k + 1)
    b.fix(1).fix(2)
    return b.build()


@pytest.mark.parametrize("n", [1, 3])
@pytest.mark.parametrize("shear", [(0.0, 0.0), (2e-5, 3e-5)], ids=["Euler-Bernoulli",
                                                                   "Timoshenko"])
def test_cantilever_deflections_and_twist(n, shear):
    """Tip force ``Fy`` bends by ``Fy L^3/(3 EIz)`` (+ ``Fy L sz/EIz`` with shear), ``Fz`` by
    ``Fz L^3/(3 EIy)`` (+ ``Fz L sy/EIy``), a torque twists by ``T L/GIt``; exact for every
    n. The labels of a rotational node's ``lam1..lam3`` stand for its rotations and the
    moments about x, y and z: the twist per unit torque is read directly."""
    tip_node, tip_rotation = 2 * n + 1, 2 * n + 2
    model = cantilever(n, shear)
    labels = [f"x{tip_node}.2", f"x{tip_node}.3", f"x{tip_rotation}.2"]
    C = fm.compliance(fm.linearize(model), labels)
    sy, sz = shear
    (fy, fz, torque) = (1.0, -0.7, 0.3)
    deflections = C[:2, :2] @ [fy, fz]
    expected = [fy * SPAN**3 / (3 * EIZ) + fy * SPAN * sz / EIZ,
                fz * SPAN**3 / (3 * EIY) + fz * SPAN * sy / EIY]
    np.testing.assert_allclose(deflections, expected, rtol=1e-12)
    if shear == (0.0, 0.0):
        np.testing.assert_allclose(deflections, [0.0091541667, -0.0102526667], rtol=1e-8)
    else:
        np.testing.assert_allclose(deflections, [0.0091546542, -0.0102530307], rtol=1e-8)
    assert C[2, 2] * torque == pytest.approx(0.013, rel=1e-12)


def test_cantilever_nodal_compliance_in_translations_and_rotations():
    """The tip's 6 x 6 compliance in ``(dr, dtheta)``: a moment about z turns the tip by
    ``M L/EIz`` and moves it by ``M L^2/(2 EIz)``, reciprocally; about y likewise with
    the sign of the right-hand rule; the twist is ``T L/GIt`` and the stretch ``F L/EA``."""
    n = 3
    tip, rotation = 2 * n + 1, 2 * n + 2
    labels = [f"x{tip}.{k}" for k in (1, 2, 3)] + [f"x{rotation}.{k}" for k in (2, 3, 4)]
    C = fm.compliance(fm.linearize(cantilever(n)), labels)
    np.testing.assert_allclose(C, C.T, atol=1e-15)
    expected = np.zeros((6, 6))
    expected[0, 0] = SPAN / EA
    expected[1, 1], expected[2, 2] = SPAN**3 / (3 * EIZ), SPAN**3 / (3 * EIY)
    expected[3, 3], expected[4, 4], expected[5, 5] = SPAN / GIT, SPAN / EIY, SPAN / EIZ
    expected[1, 5] = expected[5, 1] = SPAN**2 / (2 * EIZ)
    expected[2, 4] = expected[4, 2] = -SPAN**2 / (2 * EIY)
    np.testing.assert_allclose(C, expected, atol=1e-12 * np.abs(expected).max())
    with pytest.raises(fm.ArgumentError, match="lam0 of a spatial rotational node"):
        fm.compliance(fm.linearize(cantilever(n)), [f"x{rotation}.1"])


def test_cantilever_frequencies_converge_to_the_continuum():
    """Eight beams: the first bending in each plane within 2.5e-6 (rad/s) of the
    continuum, ``beta^2 sqrt(EI/(rho A L^4))``, the second within 1e-4 (the error goes as
    ``(beta n^-1)^4``), and the first torsion, ``(pi/(2 L)) sqrt(GIt/Jxx)`` with the lumped
    rotary inertia, within 2e-3 (``n^-2``)."""
    modes = fm.vibration_modes(fm.linearize(cantilever(8, mass=True)), 7)
    omega = np.sort(2 * np.pi * modes.frequencies)
    np.testing.assert_allclose(omega[:2], [10.402412, 13.158126], rtol=2.5e-6)
    np.testing.assert_allclose(omega[2:4], [65.190803, 82.460569], rtol=1e-4)
    assert not np.allclose(omega[2:4], [65.190803, 82.460569], rtol=1e-5)  # n^-4, not exact
    torsion = (math.pi / (2 * SPAN)) * math.sqrt(GIT / 0.0026)
    assert torsion == pytest.approx(129.79276, rel=1e-7)
    nearest = omega[np.argmin(np.abs(omega - torsion))]
    assert abs(nearest / torsion - 1) < 2e-3


def test_a_model_of_planar_and_spatial_elements_is_refused():
    b = fm.ModelBuilder("mixed")
    b.add_node(1, 0, 0).add_node(2, 1, 0)
    b.add_truss(1, 1, 2).add_spatial_hinge(2, 3, 4)
    with pytest.raises(fm.ModelError, match=r"mixes planar and spatial elements \(truss 1, "
                                            r"spatial hinge 2\)"):
        b.build()


def test_spatial_nodes_need_three_coordinates_and_the_euler_elements_are_automatic():
    b = fm.ModelBuilder("flat")
    b.add_node(1, 0, 0).add_node(3, 1, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 0, 1)).fix(1).fix(2)
    with pytest.raises(fm.ModelError, match=r"node 1 is spatial translational .* needs 3 "
                                            "coordinates"):
        b.build()
    b = fm.ModelBuilder("euler")
    b.add_node(1, 0, 0, 0).add_node(3, 1, 0, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 0, 1))
    b.fix(1).fix(2)
    model = b.build()
    euler = [e for e in model.elements.values() if e.type is fm.EulerNormalization]
    assert [(e.number, e.nodes) for e in euler] == [(2, (2,)), (3, (4,))]
    assert model.x0[list(model.nodes[4].coordinates)].tolist() == [1.0, 0.0, 0.0, 0.0]
    b.release(2)
    with pytest.raises(fm.ModelError, match="element 2 is the Euler normalization of node 2"):
        b.build()


def test_an_orientation_along_the_beam_is_refused():
    b = fm.ModelBuilder("along")
    b.add_node(1, 0, 0, 0).add_node(3, 1, 1, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(2, 2, 0)).fix(1).fix(2)
    with pytest.raises(fm.ModelError, match=r"orientation vector .* lies along the beam"):
        b.build()


def test_an_over_constrained_spatial_model_names_its_redundant_constraints():
    """The slider-crank of spatial hinges with its slider's z fixed too: the hinges already
    keep the mechanism in its plane, so one equation is too many, and the builder names
    the out-of-plane equations that depend on each other."""
    b = fm.ModelBuilder("over-constrained")
    b.add_node(1, 0, 0, 0).add_node(2, R, 0, 0).add_node(3, R + L, 0, 0)
    b.add_spatial_beam(1, 1, 12, 2, 13, orientation=(0, 0, 1))
    b.add_spatial_beam(2, 2, 14, 3, 15, orientation=(0, 0, 1))
    b.add_spatial_hinge(3, 11, 12).add_spatial_hinge(4, 13, 14)
    b.fix(1).fix(11).fix(3, "y", "z")
    b.input_deformation(3, 1, law=fm.Polynomial(0.0, OMEGA))
    b.release(4, 1)
    with pytest.raises(fm.ModelError, match=r"1 equation\(s\) too many.*linearly dependent") \
            as info:
        b.build()
    assert "e3.3 (spatial hinge 3, misalignment about z)" in str(info.value)
    assert "e1.3" not in str(info.value)   # the in-plane equations are independent


def test_spatial_column_buckles_at_euler_load_in_its_weaker_plane():
    """A compressive tip load on the clamped cantilever: the first buckling factor is
    Euler's ``pi^2 EIy/(4 L^2 P)`` (the weaker plane), the second ``pi^2 EIz/(4 L^2 P)``,
    through the geometric stiffness of the bending-linked terms."""
    model = cantilever(8)
    load = 10.0
    lin = fm.linearize(model, loads={"x17.1": -load})
    factors = fm.buckling(lin, 2).factors
    euler = np.pi**2 / (4 * SPAN**2 * load) * np.array([EIY, EIZ])
    np.testing.assert_allclose(factors, euler, rtol=1e-5)


def test_state_space_of_a_spatial_model_in_moments_and_rotations():
    """The static gain of the state space from a tip moment about z to the tip's rotation
    about z and its y deflection is the compliance, ``L/EIz`` and ``L^2/(2 EIz)``."""
    model = cantilever(4, mass=True)
    system = fm.state_space(fm.linearize(model), ["x10.4"], ["x10.4", "x9.2"])
    gain = system.D - system.C @ np.linalg.solve(system.A, system.B)
    np.testing.assert_allclose(gain[:, 0], [SPAN / EIZ, SPAN**2 / (2 * EIZ)], rtol=1e-9)


def test_symbolic_transfer_functions_refuse_spatial_models_at_once():
    """Closed-form transfer functions of a spatial model would take SymPy hours: refused
    with the numeric function to use; its deformation functions stay symbolic."""
    from flexmbd.analysis import symbolic

    model = slider_crank()
    for name in ("first_order_transfer", "second_order_transfer", "deformation_transfer"):
        with pytest.raises(fm.ModelError, match=f"flexmbd.{name}\\(model, x\\)"):
            getattr(symbolic, name)(model)
    e = symbolic.deformations(model)
    assert e.shape == (model.n_deformations, 1)
