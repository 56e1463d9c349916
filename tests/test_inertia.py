"""Element inertia against numerical integration over the interpolated body.

The position of the material point ``xi`` is interpolated here independently of
the element definitions (linear for rods, cubic Hermite for beams, THEORY
section 5); its Jacobian and accelerations come from finite differences and the
integrals from Gauss-Legendre quadrature. The kernels under test are generated
from each type's own ``material_point``.
"""

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.elements import Beam, RigidBeam, Truss
from flexmbd.engine import Workspace

from .test_elements import kernel, random_element

GAUSS_XI, GAUSS_W = np.polynomial.legendre.leggauss(8)
GAUSS_XI, GAUSS_W = 0.5 * (GAUSS_XI + 1.0), 0.5 * GAUSS_W


def rod_point(c, p, xi, cls):
    q = 2 if cls is Truss else 3
    return (1 - xi) * c[0:2] + xi * c[q:q + 2]


def beam_point(c, p, xi, cls=Beam):
    l0, beta0 = p
    e_p = np.array([np.cos(beta0 + c[2]), np.sin(beta0 + c[2])])
    e_q = np.array([np.cos(beta0 + c[5]), np.sin(beta0 + c[5])])
    h1, h2 = 1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3
    h3, h4 = 3 * xi**2 - 2 * xi**3, -(xi**2) + xi**3
    return h1 * c[0:2] + h2 * l0 * e_p + h3 * c[3:5] + h4 * l0 * e_q


CASES = [(Truss, rod_point), (RigidBeam, rod_point), (Beam, beam_point)]


def point_jacobian(point, c, p, xi, cls, h=1e-6):
    cols = []
    for j in range(len(c)):
        step = np.zeros_like(c)
        step[j] = h
        cols.append((point(c + step, p, xi, cls) - point(c - step, p, xi, cls)) / (2 * h))
    return np.stack(cols, axis=1)  # (2, nc)


@pytest.mark.parametrize(("cls", "point"), CASES, ids=lambda c: getattr(c, "name", ""))
@pytest.mark.parametrize("seed", [0, 1])
def test_mass_inertia_and_gravity_by_quadrature(cls, point, seed):
    rng = np.random.default_rng(seed)
    _, p, c, cd = random_element(cls, rng)
    cdd = rng.normal(size=len(c))
    g = np.array([0.3, -9.81])
    nc = len(c)
    m_num, force_num, gravity_num = np.zeros((nc, nc)), np.zeros(nc), np.zeros(nc)
    dt = 1e-4
    for xi, w in zip(GAUSS_XI, GAUSS_W, strict=True):
        N = point_jacobian(point, c, p, xi, cls)
        m_num += w * N.T @ N
        path = [point(c + cd * s + 0.5 * cdd * s * s, p, xi, cls) for s in (-dt, 0, dt)]
        force_num += w * N.T @ ((path[2] - 2 * path[1] + path[0]) / dt**2)
        gravity_num += w * N.T @ g
    # per unit mass: M, h with M cdd + h the inertia force, and the gravity load
    M = kernel(cls, "mass", c, p).reshape(nc, nc)
    np.testing.assert_allclose(M, m_num, atol=1e-8)
    np.testing.assert_allclose(M @ cdd + kernel(cls, "inertia", c, p, cd), force_num, atol=1e-5)
    np.testing.assert_allclose(kernel(cls, "gravity", c, p, g=g), gravity_num, atol=1e-8)


@pytest.mark.parametrize("cls", [Truss, RigidBeam, Beam], ids=lambda c: c.name)
def test_lumped_mass_is_half_at_each_end(cls):
    rng = np.random.default_rng(4)
    _, p, _, _ = random_element(cls, rng)
    diag = cls.lumped_masses(p[None], np.array([3.0]))[0]
    ends = cls.ends()
    np.testing.assert_allclose(diag[[ends[0], ends[0] + 1, ends[1], ends[1] + 1]], 1.5)
    rotational = [i for i in range(len(diag)) if i not in
                  (ends[0], ends[0] + 1, ends[1], ends[1] + 1)]
    if cls is RigidBeam:  # J = m l0^2/12 - m l0^2/4 (THEORY 5)
        assert diag[rotational] == pytest.approx(-3.0 * p[0] ** 2 / 6)
    else:
        np.testing.assert_array_equal(diag[rotational], 0.0)


def test_system_mass_matrix_assembles_the_element_matrices():
    """The core's mass matrix (constant blocks, varying beams, lumped elements, point
    masses) against the element kernels scattered by hand."""
    from .test_dat import everything

    model = everything()
    rng = np.random.default_rng(3)
    x = np.asarray(model.x0) + rng.normal(scale=0.03, size=model.n_coordinates)
    expected = np.zeros((model.n_coordinates,) * 2)
    for number, element in model.elements.items():
        props = model.element_properties.get(number)
        if not (props and props.mass_per_length):
            continue
        coords, p = list(element.coordinates), np.array(element.reference)
        mass = props.mass_per_length * p[0]
        if props.lumped:
            block = np.diag(element.type.lumped_masses(p[None], np.array([mass]))[0])
        else:
            nc = len(coords)
            block = mass * kernel(element.type, "mass", x[coords], p).reshape(nc, nc)
        expected[np.ix_(coords, coords)] += block
    for number, mass in model.nodal_masses.items():
        coords = list(model.nodes[number].coordinates)
        expected[coords, coords] += mass
    np.testing.assert_allclose(fm.mass_matrix(model, x), expected, rtol=0, atol=1e-15)
    M, _, _ = Workspace(model).mass(x)
    np.testing.assert_array_equal(M, fm.mass_matrix(model, x))
