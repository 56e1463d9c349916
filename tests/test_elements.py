"""Element kernels against finite differences and against SymPy.

Every derivative is hand-written in the kernels; here it is compared with
central differences of the deformation functions at random configurations and
with symbolic differentiation of the single definition ``formula``.
"""

import numpy as np
import pytest
import sympy as sp

from flexmbd.elements import Beam, Hinge, RigidBeam, Truss

ELEMENTS = [Truss, Beam, RigidBeam, Hinge]
N = 7  # elements evaluated at once, to exercise vectorisation


def random_state(cls, rng):
    """Random reference geometry, configuration and velocities for ``N`` elements."""
    nc = cls.n_coordinates()
    xe0 = rng.uniform(-2.0, 2.0, size=(N, nc))
    for col, kind in enumerate(_column_kinds(cls)):
        if kind == "r":
            xe0[:, col] = 0.0  # rotational nodes start at 0 by definition
    ref = cls.reference(xe0)
    xe = xe0 + rng.normal(scale=0.3, size=(N, nc))
    xde = rng.normal(size=(N, nc))
    return ref, xe, xde


def _column_kinds(cls):
    kinds = []
    for kind in cls.node_kinds:
        kinds += ["t", "t"] if kind == "translational" else ["r"]
    return kinds


def numeric_jacobian(f, xe, h=1e-6):
    """Central differences of ``f(xe) -> (n, m)`` into ``(n, m, nc)``."""
    cols = []
    for j in range(xe.shape[1]):
        step = np.zeros_like(xe)
        step[:, j] = h
        cols.append((f(xe + step) - f(xe - step)) / (2 * h))
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
def test_reference_configuration_is_undeformed(cls):
    rng = np.random.default_rng(1)
    _ref, _, _ = random_state(cls, rng)
    xe0 = rng.uniform(-2, 2, size=(N, cls.n_coordinates()))
    for col, kind in enumerate(_column_kinds(cls)):
        if kind == "r":
            xe0[:, col] = 0.0
    np.testing.assert_allclose(cls.deformations(xe0, cls.reference(xe0)), 0.0, atol=1e-14)


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_jacobian_matches_finite_differences(cls, seed):
    ref, xe, _ = random_state(cls, np.random.default_rng(seed))
    expected = numeric_jacobian(lambda z: cls.deformations(z, ref), xe)
    np.testing.assert_allclose(cls.jacobian(xe, ref), expected, rtol=1e-7, atol=1e-8)


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_hessian_matches_finite_differences_of_jacobian(cls, seed):
    ref, xe, _ = random_state(cls, np.random.default_rng(seed))
    n, nd, nc = N, cls.n_deformations(), cls.n_coordinates()
    flat = lambda z: cls.jacobian(z, ref).reshape(n, nd * nc)  # noqa: E731
    expected = numeric_jacobian(flat, xe).reshape(n, nd, nc, nc)
    hess = cls.hessian(xe, ref)
    np.testing.assert_allclose(hess, expected, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(hess, np.swapaxes(hess, -1, -2), atol=0)


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_quadratic_velocity_is_second_derivative_along_a_path(cls, seed):
    """``(D_xx xd) xd = d2/ds2 D(x + s xd)`` at ``s = 0``, by central differences."""
    ref, xe, xde = random_state(cls, np.random.default_rng(seed))
    h = 1e-4
    f = lambda s: cls.deformations(xe + s * xde, ref)  # noqa: E731
    expected = (f(h) - 2 * f(0.0) + f(-h)) / h**2
    np.testing.assert_allclose(cls.quadratic_velocity(xe, xde, ref), expected, rtol=1e-5, atol=1e-6)
    contracted = np.einsum("edij,ei,ej->ed", cls.hessian(xe, ref), xde, xde)
    np.testing.assert_allclose(cls.quadratic_velocity(xe, xde, ref), contracted,
                               rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
def test_kernels_match_symbolic_derivatives_of_the_formula(cls):
    ref, xe, _ = random_state(cls, np.random.default_rng(5))
    symbols = sp.symbols(f"c0:{cls.n_coordinates()}")
    length, angle = sp.symbols("l0 beta0")
    exprs = sp.Matrix(cls.formula(list(symbols), length, angle, sp))
    jac = exprs.jacobian(symbols)
    hess = [sp.hessian(e, symbols) for e in exprs]
    f_jac = sp.lambdify((symbols, length, angle), jac, "numpy")
    f_hess = sp.lambdify((symbols, length, angle), hess, "numpy")
    num_jac, num_hess = cls.jacobian(xe, ref), cls.hessian(xe, ref)
    for k in range(N):
        args = (xe[k], ref.length[k], ref.angle[k])
        np.testing.assert_allclose(num_jac[k], np.array(f_jac(*args), float), atol=1e-13)
        np.testing.assert_allclose(num_hess[k], np.array(f_hess(*args), float), atol=1e-13)


def test_beam_bending_signs_follow_theory():
    """A constant-curvature bend gives ``e2 = e3 ~ l theta`` (THEORY section 2)."""
    xe0 = np.array([[0.0, 0.0, 0.0, 1.0, 0.0, 0.0]])
    ref = Beam.reference(xe0)
    theta = 1e-4
    xe = np.array([[0.0, 0.0, theta, 1.0, 0.0, -theta]])  # tangent up at p, down at q
    e = Beam.deformations(xe, ref)[0]
    np.testing.assert_allclose(e[1], theta, rtol=1e-6)
    np.testing.assert_allclose(e[2], theta, rtol=1e-6)


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
def test_kernels_take_leading_batch_axes(cls):
    """A batch of states ``(nb, n, nc)`` gives the same as one call per state."""
    rng = np.random.default_rng(8)
    ref, xe, xde = random_state(cls, rng)
    batch = xe + rng.normal(scale=0.1, size=(3, *xe.shape))
    rates = xde + rng.normal(size=(3, *xde.shape))
    for kernel in ("deformations", "jacobian", "hessian"):
        together = getattr(cls, kernel)(batch, ref)
        for k in range(3):
            np.testing.assert_array_equal(together[k], getattr(cls, kernel)(batch[k], ref))
    together = cls.quadratic_velocity(batch, rates, ref)
    for k in range(3):
        np.testing.assert_array_equal(together[k], cls.quadratic_velocity(batch[k], rates[k], ref))


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
def test_fast_kernels_evaluate_the_formula(cls):
    """The numeric kernels' ``e`` are second expressions of ``formula``: they must agree."""
    ref, xe, _ = random_state(cls, np.random.default_rng(11))
    columns = [xe[:, k] for k in range(xe.shape[1])]
    expected = np.stack(cls.formula(columns, ref.length, ref.angle, np), axis=-1)
    e, jac = cls.deformations_and_jacobian(xe, ref)
    np.testing.assert_allclose(e, expected, rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(cls.deformations(xe, ref), expected, rtol=1e-14, atol=1e-14)
    np.testing.assert_array_equal(jac, cls.jacobian(xe, ref))


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.name)
def test_kernels_give_the_same_with_the_shared_geometry(cls):
    """The geometry computed once per configuration (``ElementType.geometry``) and passed
    to the kernels changes nothing: it is the same chord and cosines they compute alone."""
    rng = np.random.default_rng(12)
    ref, xe, xde = random_state(cls, rng)
    xdde = rng.normal(size=xe.shape)
    mass, lumped = np.full(len(xe), 2.0), np.zeros(len(xe), dtype=bool)
    shared = cls.geometry(xe, ref)
    for alone, given in zip(cls.deformations_and_jacobian(xe, ref),
                            cls.deformations_and_jacobian(xe, ref, shared), strict=True):
        np.testing.assert_array_equal(given, alone)
    np.testing.assert_array_equal(cls.quadratic_velocity(xe, xde, ref, shared),
                                  cls.quadratic_velocity(xe, xde, ref))
    np.testing.assert_array_equal(cls.inertia_force(xe, xde, xdde, ref, mass, lumped, shared),
                                  cls.inertia_force(xe, xde, xdde, ref, mass, lumped))
