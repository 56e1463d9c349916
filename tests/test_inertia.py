"""Element inertia against numerical integration over the interpolated body.

The position of the material point ``xi`` is interpolated here independently
of the kernels (linear for rods, cubic Hermite for beams, THEORY section 5);
its Jacobian and accelerations come from finite differences and the integrals
from Gauss-Legendre quadrature.
"""

import numpy as np
import pytest

from flexmbd.elements import Beam, RigidBeam, Truss

GAUSS_XI, GAUSS_W = np.polynomial.legendre.leggauss(8)
GAUSS_XI, GAUSS_W = 0.5 * (GAUSS_XI + 1.0), 0.5 * GAUSS_W


def rod_point(xe, ref, xi, cls):
    (p0, p1), (q0, q1) = cls.ends
    rp, rq = xe[[p0, p1]], xe[[q0, q1]]
    return (1 - xi) * rp + xi * rq


def beam_point(xe, ref, xi, cls=Beam):
    l0, beta0 = ref
    e_p = np.array([np.cos(beta0 + xe[2]), np.sin(beta0 + xe[2])])
    e_q = np.array([np.cos(beta0 + xe[5]), np.sin(beta0 + xe[5])])
    h1, h2 = 1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3
    h3, h4 = 3 * xi**2 - 2 * xi**3, -(xi**2) + xi**3
    return h1 * xe[0:2] + h2 * l0 * e_p + h3 * xe[3:5] + h4 * l0 * e_q


CASES = [(Truss, rod_point), (RigidBeam, rod_point), (Beam, beam_point)]


def random_element(cls, rng):
    nc = cls.n_coordinates()
    xe0 = rng.uniform(-1, 1, nc)
    translations = [*cls.ends[0], *cls.ends[1]]
    rot = [i for i in range(nc) if i not in translations]
    xe0[rot] = 0.0
    ref = cls.reference(xe0[None])
    xe = xe0 + rng.normal(scale=0.2, size=nc)
    return ref, xe, rng.normal(size=nc), rng.normal(size=nc)


def point_jacobian(point, xe, ref, xi, cls, h=1e-6):
    cols = []
    for j in range(len(xe)):
        step = np.zeros_like(xe)
        step[j] = h
        cols.append((point(xe + step, ref, xi, cls) - point(xe - step, ref, xi, cls)) / (2 * h))
    return np.stack(cols, axis=1)  # (2, nc)


@pytest.mark.parametrize(("cls", "point"), CASES, ids=lambda c: getattr(c, "name", ""))
@pytest.mark.parametrize("seed", [0, 1])
def test_consistent_mass_inertia_force_and_gravity_by_quadrature(cls, point, seed):
    rng = np.random.default_rng(seed)
    ref, xe, xde, xdde = random_element(cls, rng)
    mass, lumped = np.array([2.7]), np.array([False])
    scalar_ref = (ref.length[0], ref.angle[0])
    rf = scalar_ref if cls is Beam else ref
    g = np.array([0.3, -9.81])
    m_num = np.zeros((len(xe), len(xe)))
    force_num = np.zeros(len(xe))
    gravity_num = np.zeros(len(xe))
    dt = 1e-4
    for xi, w in zip(GAUSS_XI, GAUSS_W, strict=True):
        N = point_jacobian(point, xe, rf, xi, cls)
        m_num += mass[0] * w * N.T @ N
        path = [point(xe + xde * s + 0.5 * xdde * s * s, rf, xi, cls) for s in (-dt, 0, dt)]
        accel = (path[2] - 2 * path[1] + path[0]) / dt**2
        force_num += mass[0] * w * N.T @ accel
        gravity_num += mass[0] * w * N.T @ g
    M = cls.mass_matrix(xe[None], ref, mass, lumped)[0]
    h = cls.inertia_velocity(xe[None], xde[None], ref, mass, lumped)[0]
    np.testing.assert_allclose(M, m_num, atol=1e-8)
    np.testing.assert_allclose(M @ xdde + h, force_num, atol=1e-5)
    np.testing.assert_allclose(cls.gravity_load(xe[None], ref, mass, lumped, g)[0], gravity_num,
                               atol=1e-8)


@pytest.mark.parametrize("cls", [Truss, RigidBeam, Beam], ids=lambda c: c.name)
def test_lumped_mass_is_half_at_each_end(cls):
    rng = np.random.default_rng(4)
    ref, xe, xde, _ = random_element(cls, rng)
    mass, lumped = np.array([3.0]), np.array([True])
    M = cls.mass_matrix(xe[None], ref, mass, lumped)[0]
    ends = list(cls.ends[0]) + list(cls.ends[1])
    np.testing.assert_allclose(np.diag(M)[ends], 1.5)
    assert np.count_nonzero(cls.inertia_velocity(xe[None], xde[None], ref, mass, lumped)) == 0
    if cls is RigidBeam:
        assert M[2, 2] == pytest.approx(-3.0 * ref.length[0] ** 2 / 6)


@pytest.mark.parametrize("cls", [Truss, RigidBeam, Beam], ids=lambda c: c.name)
@pytest.mark.parametrize("lumped", [False, True])
def test_inertia_force_is_mass_matrix_times_acceleration_plus_h(cls, lumped):
    """The closed-form ``inertia_force`` against the assembled ``M xddot + h``, batched."""
    rng = np.random.default_rng(6)
    elements = [random_element(cls, rng) for _ in range(4)]
    ref = type(elements[0][0])(*(np.concatenate([getattr(e[0], f) for e in elements])
                                 for f in ("length", "angle")))
    # two states of the four elements: shapes (2, 4, nc)
    xe, xde, xdde = (np.stack([e[k] for e in elements]) + rng.normal(scale=0.1, size=(2, 4, 1))
                     for k in (1, 2, 3))
    mass, lumps = rng.uniform(0.5, 2.0, 4), np.array([lumped, False, lumped, True])
    expected = (np.einsum("bnij,bnj->bni", cls.mass_matrix(xe, ref, mass, lumps), xdde)
                + cls.inertia_velocity(xe, xde, ref, mass, lumps))
    np.testing.assert_allclose(cls.inertia_force(xe, xde, xdde, ref, mass, lumps), expected,
                               rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("cls", [Truss, RigidBeam, Beam], ids=lambda c: c.name)
@pytest.mark.parametrize("lumped", [False, True])
def test_mass_terms_rebuild_the_mass_matrix(cls, lumped):
    """``M0 + sum_k phi_k M_k`` (the assembly's form) equals ``mass_matrix`` (the product
    ``A^T (P x I) A`` for the beam) at random configurations, alone and batched."""
    rng = np.random.default_rng(21)
    xe0 = rng.uniform(-1.0, 1.0, size=(4, cls.n_coordinates()))
    ref = cls.reference(xe0)
    xe = xe0 + rng.normal(scale=0.4, size=(2, *xe0.shape))
    mass, lumps = rng.uniform(0.5, 3.0, size=4), np.full(4, lumped)
    M0, terms = cls.mass_terms(ref, mass, lumps)
    phi = cls.mass_features(xe, ref)
    rebuilt = M0 + np.einsum("bnk,nkij->bnij", phi, terms)
    np.testing.assert_allclose(rebuilt, cls.mass_matrix(xe, ref, mass, lumps), atol=1e-14)
    assert phi.shape[-1] == (5 if cls is Beam else 0)
