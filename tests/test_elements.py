"""The compiled element kernels against the one definition of each element type.

Every kernel is generated from :meth:`ElementType.deformations` (flexmbd.engine.codegen);
here it is evaluated through the core and compared with the definition evaluated
with numpy and differentiated by central differences at random configurations,
and with SymPy's differentiation of the same definition. The generated file must
be the one the current definitions make.
"""

import numpy as np
import pytest
import sympy as sp

from flexmbd.elements import ELEMENT_TYPES, Beam, RigidBeam
from flexmbd.elements.base import (
    COORDINATES_PER_NODE,
    ROTATIONAL,
    SPATIAL_ROTATIONAL,
    WARPING,
)
from flexmbd.engine import _core, codegen

TYPES = list(ELEMENT_TYPES.values())
NUMBER = {cls: k for k, cls in enumerate(TYPES)}


def kernel(cls, name, c, p, v=None, g=None):
    """One generated kernel of ``cls`` at one element."""
    nc, nd = cls.n_coordinates(), cls.n_deformations()
    size = {"deform": nd, "deform_jac": nd * (1 + nc), "quadratic": nd,
            "hessian": nd * nc * nc, "mass": nc * nc, "inertia": nc, "gravity": nc,
            "gravity_jac": nc * nc}[name]
    out = np.empty(size)
    _core.kernel(NUMBER[cls], name, np.asarray(c, float), np.asarray(p, float),
                 None if v is None else np.asarray(v, float),
                 None if g is None else np.asarray(g, float), out)
    return out


def random_element(cls, rng):
    """Reference parameters from a random initial configuration (with random element
    data: orientation vectors, axes, inertia), and a state near it."""
    nc = cls.n_coordinates()
    c0 = rng.uniform(-2.0, 2.0, nc)
    at = 0
    for role in cls.roles:  # rotational and warping nodes start at 0, Euler parameters at
        if role.kind in (ROTATIONAL, WARPING):  # (1, 0, 0, 0)
            c0[at] = 0.0
        elif role.kind == SPATIAL_ROTATIONAL:
            c0[at:at + 4] = (1.0, 0.0, 0.0, 0.0)
        at += COORDINATES_PER_NODE[role.kind]
    data = {name: rng.uniform(-1.0, 1.0, (1, len(default or (0.0,) * 3)))
            for name, default in cls.element_data.items()}
    if "bending_linked" in data:
        data["bending_linked"] = np.ones((1, 1))
    p = cls.reference_parameters(c0[None], data)[0]
    return c0, p, c0 + rng.normal(scale=0.3, size=nc), rng.normal(size=nc)


def definition(cls, c, p):
    """The deformations as the type defines them, evaluated with numpy."""
    return np.array(cls.deformations(list(c), list(p), np), dtype=float)


def central(f, c, h=1e-6):
    """``df/dc`` by central differences, columns over ``c``."""
    cols = []
    for j in range(len(c)):
        step = np.zeros(len(c))
        step[j] = h
        cols.append((f(c + step) - f(c - step)) / (2 * h))
    return np.stack(cols, axis=-1)


def test_the_generated_kernels_are_those_of_the_current_definitions():
    """The hash of the element definitions the kernels were generated from, compiled into
    the core, equals the hash of the definitions now: edit an element and this fails
    until `python -m flexmbd.engine.codegen` is run and the core rebuilt."""
    assert codegen.definitions_hash() == _core.DEFINITIONS_HASH
    assert codegen.KERNELS.read_text().count(codegen.definitions_hash()) == 2
    assert tuple(ELEMENT_TYPES) == _core.KEYWORDS


def test_the_kernels_are_as_generated():
    """kernels.c holds the hash of its own body: a hand edit of a kernel fails here (the
    generator's output itself is checked by .ci/run, which regenerates it)."""
    text = codegen.KERNELS.read_text()
    recorded, actual = codegen.recorded_body_hash(text)
    assert recorded == actual
    at = text.index(" = ", text.index("_deform("))   # the first formula of the first kernel
    edited = text[:at] + " = -" + text[at + 3:]
    assert codegen.recorded_body_hash(edited)[1] != recorded


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.name)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_deformations_and_jacobian_match_the_definition(cls, seed):
    c0, p, c, _ = random_element(cls, np.random.default_rng(seed))
    nd, nc = cls.n_deformations(), cls.n_coordinates()
    np.testing.assert_allclose(kernel(cls, "deform", c0, p), 0.0, atol=1e-14)  # undeformed
    out = kernel(cls, "deform_jac", c, p)
    np.testing.assert_allclose(out[:nd], definition(cls, c, p), rtol=1e-14, atol=1e-14)
    # the two kernels eliminate common subexpressions apart: equal to rounding
    np.testing.assert_allclose(kernel(cls, "deform", c, p), out[:nd], rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(out[nd:].reshape(nd, nc),
                               central(lambda z: definition(cls, z, p), c),
                               rtol=1e-7, atol=1e-8)


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.name)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_hessian_and_quadratic_velocity_match_the_definition(cls, seed):
    _, p, c, v = random_element(cls, np.random.default_rng(seed))
    nd, nc = cls.n_deformations(), cls.n_coordinates()
    hess = kernel(cls, "hessian", c, p).reshape(nd, nc, nc)
    jac = lambda z: kernel(cls, "deform_jac", z, p)[nd:].reshape(nd * nc)  # noqa: E731
    np.testing.assert_allclose(hess, central(jac, c).reshape(nd, nc, nc), rtol=1e-6, atol=1e-7)
    np.testing.assert_array_equal(hess, np.swapaxes(hess, -1, -2))
    # (D_xx xd) xd = d2/ds2 D(c + s v) at s = 0
    h = 1e-4
    path = [definition(cls, c + s * v, p) for s in (-h, 0.0, h)]
    quadratic = kernel(cls, "quadratic", c, p, v)
    np.testing.assert_allclose(quadratic, (path[2] - 2 * path[1] + path[0]) / h**2,
                               rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(quadratic, np.einsum("dij,i,j->d", hess, v, v),
                               rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.name)
def test_kernels_match_symbolic_derivatives_of_the_definition(cls):
    """SymPy differentiates the definition along random directions ``v``, ``w`` through
    the state: ``d/ds D(c + s v + t w)`` is ``D_x v`` and ``d2/ds dt`` is ``v^T D_xx w``
    (a full symbolic Hessian of the spatial beam would take a minute)."""
    rng = np.random.default_rng(5)
    _, p, c, _ = random_element(cls, rng)
    nd, nc = cls.n_deformations(), cls.n_coordinates()
    v, w = rng.normal(size=(2, nc))
    s, t = sp.symbols("s t", real=True)
    path = [sp.Float(ck) + s * sp.Float(vk) + t * sp.Float(wk)
            for ck, vk, wk in zip(c, v, w, strict=True)]
    exprs = sp.Matrix(cls.deformations(path, [sp.Float(pk) for pk in p], sp))
    at_zero = {s: 0, t: 0}
    slope = np.array(exprs.diff(s).subs(at_zero).evalf(), dtype=float).ravel()
    cross = np.array(exprs.diff(s).diff(t).subs(at_zero).evalf(), dtype=float).ravel()
    jac = kernel(cls, "deform_jac", c, p)[nd:].reshape(nd, nc)
    hess = kernel(cls, "hessian", c, p).reshape(nd, nc, nc)
    np.testing.assert_allclose(jac @ v, slope, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(np.einsum("dij,i,j->d", hess, v, w), cross, rtol=1e-11,
                               atol=1e-11)


WEIGHTED = [cls for cls in TYPES if cls.has_mass and cls.body_angular_velocity(
    list(sp.symbols(f"c0:{cls.n_coordinates()}")), sp) is None]


@pytest.mark.parametrize("cls", WEIGHTED, ids=lambda c: c.name)
def test_the_gravity_slope_is_the_derivative_of_the_gravity_load(cls):
    """``d(int N^T g)/dc``, the load stiffness of an element's weight, against central
    differences of its gravity kernel at a random state."""
    _, p, c, _ = random_element(cls, np.random.default_rng(3))
    nc = cls.n_coordinates()
    g = np.random.default_rng(4).normal(size=cls.dimension())
    slope = kernel(cls, "gravity_jac", c, p, g=g).reshape(nc, nc)
    np.testing.assert_allclose(slope, central(lambda z: kernel(cls, "gravity", z, p, g=g), c),
                               rtol=1e-7, atol=1e-8)


def test_beam_bending_signs_follow_theory():
    """A constant-curvature bend gives ``e2 = e3 ~ l theta`` (THEORY section 2)."""
    c0 = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    p = Beam.reference_parameters(c0[None])[0]
    theta = 1e-4
    e = kernel(Beam, "deform", [0.0, 0.0, theta, 1.0, 0.0, -theta], p)
    np.testing.assert_allclose(e[1:], [theta, theta], rtol=1e-6)
    rigid = kernel(RigidBeam, "deform", [0.0, 0.0, theta, 1.0, 0.0], p)
    np.testing.assert_allclose(rigid[1], -theta, rtol=1e-6)  # n_p . d: the opposite sign


def test_a_kernel_the_type_does_not_have_is_refused():
    hinge = ELEMENT_TYPES["PLHINGE"]
    with pytest.raises(ValueError, match="mass: not defined for PLHINGE"):
        kernel(hinge, "mass", [0.0, 0.1], [])
