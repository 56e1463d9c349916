"""The factorisations behind a model's build: ``D_c``'s rank, its left null space (the
over-constraints SPACAR Light releases) and the condition estimate, sparse for large
models, against the dense SVD."""

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.builder import constraints, validation
from flexmbd.engine import deformations_and_jacobian
from flexmbd.engine.diagnosis import SPARSE_FROM, clearly_regular, condition, factorised
from tests.test_banded import pivot_builder


def constraint_jacobian(b: fm.ModelBuilder) -> np.ndarray:
    model = validation.assemble_checked(b._records)
    D_x = deformations_and_jacobian(model, np.asarray(model.x0))[1]
    return D_x[np.ix_(list(model.constrained), model.dependent)]


@pytest.mark.parametrize("nbeams", [4, 70])  # 75 and 867 rows: dense and sparse
def test_the_left_null_space_is_the_svds(nbeams):
    D_c = constraint_jacobian(pivot_builder(nbeams))
    assert (len(D_c) >= SPARSE_FROM) == (nbeams == 70)
    over, under, null = constraints._over_constraints(D_c)
    U, values, _ = np.linalg.svd(D_c)
    assert (over, under) == (6, 0) == (len(D_c) - D_c.shape[1], 0)
    assert values[-1] > 1e-8 * values[0]  # full column rank, as the counts say
    np.testing.assert_allclose(null.T @ null, np.eye(6), atol=1e-10)
    assert np.abs(D_c.T @ null).max() < 1e-10 * np.abs(D_c).max()
    # the same space as the SVD's last left singular vectors: projections agree
    svd_null = U[:, -6:]
    np.testing.assert_allclose(null @ null.T, svd_null @ svd_null.T, atol=1e-8)


def test_released_models_build_and_keep_their_stiffness():
    """The releases the sparse path chooses at 70 beams per leaf make a model that builds
    (its count closes, D_c regular), and a released deformation keeps its stiffness: the
    stage's rotational stiffness is that of the mesh at 4 beams per leaf within 1e-3."""
    stiffness = []
    for nbeams in (4, 70):
        b = pivot_builder(nbeams)
        assert len(b.release_overconstraints()) == 6
        model = b.build()
        stiffness.append(1.0 / fm.node_compliance(model, 9, 10)[5, 5])
    assert stiffness[1] == pytest.approx(stiffness[0], rel=1e-3)


@pytest.mark.parametrize("n", [50, SPARSE_FROM + 50])
def test_condition_is_the_svds(n):
    """A chain's matrix (a second difference, condition growing with n^2) and a
    singular one (a repeated row), dense and sparse."""
    A = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    A[0, 0] = 1.0  # one end free: condition ~ n^2
    solve = factorised(A)
    assert condition(A, solve) == pytest.approx(np.linalg.cond(A), rel=0.05)
    assert clearly_regular(A, 1e-10)
    singular = A.copy()
    singular[-1] = singular[-2]
    assert not clearly_regular(singular, 1e-10)
