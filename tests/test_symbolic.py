"""The symbolic path agrees with the numeric one (same element definitions)."""

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

import flexmbd as fm  # noqa: E402
from flexmbd import symbolic  # noqa: E402

from .models import slider_crank  # noqa: E402
from .test_kinematics import four_bar_with_spring  # noqa: E402


def substitute(model, expr, x, xd=None):
    values = dict(zip(symbolic.coordinate_symbols(model), x, strict=True))
    if xd is not None:
        values.update(zip(symbolic.coordinate_symbols(model, "xd"), xd, strict=True))
    return np.array(expr.subs(values).evalf(), dtype=float)


@pytest.mark.parametrize("build", [slider_crank, four_bar_with_spring])
def test_symbolic_matches_numeric(build):
    model = build()
    x = fm.solve_position(model, np.array([0.6]))
    xd = fm.velocities(model, x, np.array([1.4]))
    np.testing.assert_allclose(substitute(model, symbolic.deformations(model), x).ravel(),
                               fm.deformations(model, x), atol=1e-13)
    np.testing.assert_allclose(substitute(model, symbolic.jacobian(model), x),
                               fm.jacobian(model, x), atol=1e-13)
    np.testing.assert_allclose(substitute(model, symbolic.quadratic_velocity(model), x, xd)
                               .ravel(), fm.quadratic_velocity(model, x, xd), atol=1e-12)
    np.testing.assert_allclose(
        substitute(model, symbolic.first_order_transfer(model, simplify=False), x),
        fm.first_order_transfer(model, x), atol=1e-12)


def test_slider_crank_symbolic_e_q_is_zero_and_lengths_are_exact():
    model = slider_crank()
    assert symbolic.deformation_transfer(model) == sp.zeros(4, 1)
    assert symbolic.deformations(model)[2].has(sp.sqrt(3))
