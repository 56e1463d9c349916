"""Spatial dynamics against closed forms (the verification cases of the spatial theory,
section 8): the torque-free body's invariants and its instability about the intermediate
axis, the heavy top's steady precession, the spherical pendulum's period, conical motion
and energy through half turns, and the energy of flexible spatial beams. Free rotations
re-choose their calculable Euler parameter on the way (``flexmbd.analysis.free_rotations``);
the orientation readings are checked against scipy's rotations.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import flexmbd as fm

G = 9.81
TIGHT = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-14}


def pivoted_body(inertia, tip=None, section=None, gravity=False, tip_mass=0.0):
    """A rigid spatial beam from the fixed point 1 to node 3 at ``tip``, whose rotational
    node 2 turns freely (three dynamic Euler parameters) and carries ``inertia``
    ``(Jxx, Jyy, Jzz)`` in its body frame."""
    tip = (1.0, 0.0, 0.0) if tip is None else tip
    b = fm.ModelBuilder("pivoted body")
    b.add_node(1, 0, 0, 0).add_node(3, *tip)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 1, 0))
    b.fix(1).dynamic_coordinate(2, 2, 3, 4)
    if inertia is not None:
        b.add_rotary_inertia(2, inertia[0], 0, 0, inertia[1], 0, inertia[2])
    if section is not None:
        b.set_mass(1, section[0], section_inertia=section[1])
    if tip_mass:
        b.add_point_mass(3, tip_mass)
    if gravity:
        b.set_gravity(0, 0, -G)
    return b.build()


def start(lam, rates):
    """``initial`` of the three dynamic Euler parameters of node 2."""
    return {f"x2.{k}": (lam[k - 1], rates[k - 1]) for k in (2, 3, 4)}


def test_torque_free_body_keeps_energy_and_angular_momentum():
    """THEORY-SPATIAL 8: over 5 s the kinetic energy and the global angular momentum
    ``R Jb omega'`` stay constant while the body tumbles through six re-partitions."""
    J = np.array([[2, .1, -.2], [.1, 3, .05], [-.2, .05, 4.5]])
    b = fm.ModelBuilder("torque-free body")
    b.add_node(1, 0, 0, 0).add_node(3, 1, 0, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 1, 0))
    b.fix(1).dynamic_coordinate(2, 2, 3, 4)
    b.add_rotary_inertia(2, J[0, 0], J[0, 1], J[0, 2], J[1, 1], J[1, 2], J[2, 2])
    model = b.build()
    identity = np.array([1.0, 0, 0, 0])
    rates = fm.euler_rates(identity, [1.3, -2.1, 3.4], frame="body")
    result = fm.simulate(model, np.linspace(0, 5, 51), initial=start(identity, rates),
                         **TIGHT)
    w = result.angular_velocity(2, frame="body")
    energy = 0.5 * np.einsum("ni,ij,nj->n", w, J, w)
    momentum = np.einsum("nij,nj->ni", result.rotation_matrix(2), w @ J)
    assert np.abs(energy - energy[0]).max() < 1e-9 * energy[0]
    assert np.abs(momentum - momentum[0]).max() < 1e-9 * np.linalg.norm(momentum[0])
    assert result.stats["repartitions"] == 6
    lam = result.euler_parameters(2)
    np.testing.assert_allclose(np.sum(lam**2, axis=1), 1.0, atol=1e-12)
    assert lam[:, 0].min() < 0.0 < lam[:, 0].max()   # it turned through a half turn
    # the q columns keep the model's labels: lam1..3 of node 2 across the partitions
    for k in (2, 3, 4):
        np.testing.assert_array_equal(result.q[:, model.q_labels.index(f"x2.{k}")],
                                      result[f"x2.{k}"])
    np.testing.assert_array_equal(result.driving, 0.0)


def test_generalized_alpha_repartitions_too():
    """The compiled integrator stops at a spent partition and continues in the new one:
    the same tumbling body, energy within its truncation error."""
    J = (2.0, 3.0, 4.5)
    model = pivoted_body(J)
    identity = np.array([1.0, 0, 0, 0])
    rates = fm.euler_rates(identity, [1.3, -2.1, 3.4], frame="body")
    result = fm.simulate(model, np.linspace(0, 5, 101), initial=start(identity, rates),
                         method="GeneralizedAlpha", step=1e-3, rtol=1e-10, atol=1e-12)
    w = result.angular_velocity(2, frame="body")
    energy = 0.5 * np.sum(w**2 * J, axis=1)
    assert result.stats["repartitions"] >= 3
    assert np.abs(energy - energy[0]).max() < 1e-5 * energy[0]
    reference = fm.simulate(model, result.t, initial=start(identity, rates), **TIGHT)
    np.testing.assert_allclose(result.x, reference.x, atol=1e-4)


@pytest.mark.parametrize("axis, expected", [
    (2, lambda t: np.cosh(2.0 * np.sqrt(1 * 1 / (1 * 3)) * t)),   # intermediate: unstable
    (3, lambda t: np.cos(2.0 * np.sqrt(2 * 1 / (1 * 2)) * t)),     # largest: stable
])
def test_spin_about_a_principal_axis(axis, expected):
    """``Jb = diag(1, 2, 3)`` spinning at 2 rad/s plus 1e-6 about axis 1: about the
    intermediate axis ``omega1'`` grows as ``cosh(s t)``, ``s = 1.1547/s`` (50.6912 times
    at 4 s); about the largest it oscillates as ``cos(2 t)``."""
    eps = 1e-6
    omega = np.zeros(3)
    omega[axis - 1], omega[0] = 2.0, eps
    identity = np.array([1.0, 0, 0, 0])
    t = np.linspace(0, 4, 9)
    result = fm.simulate(pivoted_body((1.0, 2.0, 3.0)), t,
                         initial=start(identity, fm.euler_rates(identity, omega, "body")),
                         **TIGHT)
    w1 = result.angular_velocity(2, frame="body")[:, 0] / eps
    np.testing.assert_allclose(w1, expected(t), rtol=1e-6, atol=1e-6)
    if axis == 2:
        assert w1[-1] == pytest.approx(50.6912, abs=1e-4)


def test_heavy_top_precesses_steadily():
    """A symmetric top on a fixed point with its axis horizontal and spin 30 rad/s
    precesses at ``Omega = m g h/(C omega3)`` = 0.654 rad/s; its axis stays horizontal."""
    m, h, C, A0, spin = 1.0, 0.1, 0.05, 0.03, 30.0
    model = pivoted_body((C, A0, A0), tip=(h, 0, 0), gravity=True, tip_mass=m)
    omega = m * G * h / (C * spin)
    assert omega == pytest.approx(0.654)
    identity = np.array([1.0, 0, 0, 0])
    t = np.linspace(0, 5, 51)
    result = fm.simulate(model, t, initial=start(identity, fm.euler_rates(
        identity, [spin, 0, omega])), **TIGHT)
    x, y, z = (result[f"x3.{k}"] for k in (1, 2, 3))
    assert np.abs(z).max() < 1e-8 * h
    np.testing.assert_allclose(np.unwrap(np.arctan2(y, x)), omega * t, atol=1e-8)


PENDULUM_INERTIA = 1 + 0.5 / 3 + 0.01      # about the pivot [kg m^2]
PENDULUM_MGH = G * (1 + 0.5 / 2)           # [N m]


def pendulum() -> fm.Model:
    """A rigid beam of length 1 m and 0.5 kg (section inertia ``Jxx = 0.02``,
    ``Jyy = Jzz = 0.01`` per metre) hanging from a spherical joint, 1 kg at its tip."""
    return pivoted_body(None, tip=(0, 0, -1.0), section=(0.5, (0.02, 0.01, 0.01, 0.0)),
                        gravity=True, tip_mass=1.0)


def test_pendulum_period_of_small_swings():
    """``T = 2 pi sqrt(I_O/(m g h))`` = 1.9463327 s."""
    period = 2 * np.pi * np.sqrt(PENDULUM_INERTIA / PENDULUM_MGH)
    assert period == pytest.approx(1.9463327, abs=1e-7)
    lam = fm.euler_parameters([0, 1, 0], 1e-4)
    t = np.linspace(0, 2 * period, 201)
    x = fm.simulate(pendulum(), t, initial=start(lam, np.zeros(4)), **TIGHT)["x3.1"]
    crossing = np.flatnonzero(np.diff(np.sign(x)))
    zeros = t[crossing] - x[crossing] * (t[crossing + 1] - t[crossing]) / (
        x[crossing + 1] - x[crossing])
    assert 2 * np.mean(np.diff(zeros)) == pytest.approx(period, rel=1e-7)


def test_pendulum_conical_motion():
    """At 0.5 rad from the downward vertical the pendulum circles at
    ``Omega^2 = m g h/((A - C) cos alpha)``, 3.4756930 rad/s, keeping its tilt."""
    alpha = 0.5
    omega = np.sqrt(PENDULUM_MGH / ((PENDULUM_INERTIA - 0.02) * np.cos(alpha)))
    assert omega == pytest.approx(3.4756930, abs=1e-7)
    lam = fm.euler_parameters([0, 1, 0], alpha)
    t = np.linspace(0, 5, 51)
    result = fm.simulate(pendulum(), t, initial=start(lam, fm.euler_rates(lam, [0, 0, omega])),
                         **TIGHT)
    x, y, z = (result[f"x3.{k}"] for k in (1, 2, 3))
    np.testing.assert_allclose(np.arccos(-z), alpha, atol=1e-9)
    azimuth = np.unwrap(np.arctan2(y, x))
    np.testing.assert_allclose(azimuth - azimuth[0], omega * t, atol=1e-8)


def test_large_spherical_swing_keeps_its_energy_through_half_turns():
    """Released at 1 rad with 1.5 rad/s about the vertical, the pendulum keeps kinetic plus
    potential energy while its Euler parameters pass ``lam0 = 0``."""
    model = pendulum()
    lam = fm.euler_parameters([0, 1, 0], 1.0)
    t = np.linspace(0, 6, 241)
    result = fm.simulate(model, t, initial=start(lam, fm.euler_rates(lam, [0, 0, 1.5])),
                         **TIGHT)
    masses = fm.mass_matrix(model, result.x)
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", result.xd, masses, result.xd)
    z = result["x3.3"]
    potential = G * (1.0 * z + 0.5 * z / 2)
    energy = kinetic + potential
    assert np.abs(energy - energy[0]).max() < 1e-9 * np.abs(energy).max()
    lam0 = result.euler_parameters(2)[:, 0]
    assert lam0.min() < 0.0 < lam0.max() and result.stats["repartitions"] > 0


def test_flexible_spatial_beams_keep_their_energy():
    """Two flexible spatial beams clamped at one end (elongation rigid, the other five
    deformations dynamic), released with random deformation rates: kinetic plus strain
    energy is constant. This checks the mass, the velocity terms and the stiffness
    together."""
    b = fm.ModelBuilder("flexible cantilever")
    b.add_node(1, 0, 0, 0).add_node(3, 0.5, 0, 0).add_node(5, 1.0, 0, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 1, 0))
    b.add_spatial_beam(2, 3, 4, 5, 6, orientation=(0, 1, 0))
    b.fix(1).fix(2)
    for element in (1, 2):
        b.dynamic_deformation(element, 2, 3, 4, 5, 6)
        b.set_mass(element, 2.0, section_inertia=(0.0026, 1e-4, 2e-4, 0.0))
        b.set_stiffness(element, axial=2e7, torsion=30, bending_y=50, bending_z=80)
    model = b.build()
    rng = np.random.default_rng(3)
    rates = {f"e{el}.{k}": (0.0, float(rng.normal(0, 0.25)))
             for el in (1, 2) for k in (2, 3, 4, 5, 6)}
    result = fm.simulate(model, np.linspace(0, 0.5, 51), initial=rates, **TIGHT)
    masses = fm.mass_matrix(model, result.x)
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", result.xd, masses, result.xd)
    strain = 0.5 * np.sum(result.sigma * result.e, axis=1)
    energy = kinetic + strain
    assert kinetic[0] > 0 and strain.max() > 0.1 * kinetic[0]
    assert np.abs(result["x5.3"]).max() > 0.05   # large: tip motion near 10 % of L
    assert np.abs(energy - energy[0]).max() < 1e-9 * energy[0]


# --- readings ------------------------------------------------------------------------------
def test_orientation_readings_agree_with_scipy_rotations():
    rng = np.random.default_rng(0)
    axes, angles = rng.normal(size=(5, 3)), rng.uniform(0, np.pi, 5)
    lam = np.array([fm.euler_parameters(a, phi) for a, phi in zip(axes, angles, strict=True)])
    reference = Rotation.from_rotvec(axes / np.linalg.norm(axes, axis=1)[:, None]
                                     * angles[:, None])
    np.testing.assert_allclose(fm.rotation_matrix(lam), reference.as_matrix(), atol=1e-15)
    axis, angle = fm.axis_angle(-lam)   # the same rotations from the other branch
    np.testing.assert_allclose(axis * angle[:, None], reference.as_rotvec(), atol=1e-14)
    omega = rng.normal(size=(5, 3))
    rates = fm.euler_rates(lam, omega)
    np.testing.assert_allclose(fm.angular_velocity(lam, rates), omega, atol=1e-14)
    np.testing.assert_allclose(np.sum(lam * rates, axis=1), 0.0, atol=1e-15)
    body = fm.angular_velocity(lam, rates, frame="body")
    np.testing.assert_allclose(np.einsum("nij,nj->ni", fm.rotation_matrix(lam), body), omega,
                               atol=1e-14)
    # finite differences of R along lamdot give [omega x] R
    R = fm.rotation_matrix(lam[0])
    dR = (fm.rotation_matrix(lam[0] + 1e-7 * rates[0])
          - fm.rotation_matrix(lam[0] - 1e-7 * rates[0])) / 2e-7
    w = omega[0]
    skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    np.testing.assert_allclose(dR, skew @ R, atol=1e-7)


def test_orientation_readings_refuse_bad_input():
    with pytest.raises(fm.ArgumentError, match="Euler parameters"):
        fm.rotation_matrix([1, 0, 0])
    with pytest.raises(fm.ArgumentError, match="frame"):
        fm.angular_velocity([1, 0, 0, 0], [0, 0, 0, 0], frame="local")
    with pytest.raises(fm.ArgumentError, match="axis"):
        fm.euler_parameters([0, 0, 0], 1.0)
    result = fm.simulate(pivoted_body((1, 2, 3)), [0, 0.1],
                         initial=start([1, 0, 0, 0], [0, 0.1, 0, 0]))
    with pytest.raises(fm.ArgumentError, match="not a spatial rotational node"):
        result.angular_velocity(3)
    with pytest.raises(fm.ArgumentError, match="must be 0, 1 or 2"):
        result.euler_parameters(2, 3)
