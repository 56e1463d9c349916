"""The assembly's scatter maps against the plain per-group assembly of other modules.

Small models build ``D_x``, the scaled ``D_c`` and the mass matrix from a few
features per element (``flexmbd.assembly``); ``flexmbd.kinematics.jacobian`` and
``flexmbd.inertia.mass_matrix`` assemble the element matrices of each type
directly. Both must give the same matrices at any configuration.
"""

import numpy as np

from flexmbd.assembly import SystemJacobian
from flexmbd.dat.reader import model_from_text
from flexmbd.inertia import mass_matrix
from flexmbd.kinematics import jacobian
from tests.test_dat import EVERYTHING


def everything_at_random_configurations(count=3):
    """The model with every element type, masses lumped and consistent, point masses,
    and ``count`` configurations near its reference one ``(count, nx)``."""
    model = model_from_text(EVERYTHING, "everything.dat")
    rng = np.random.default_rng(5)
    x = np.asarray(model.x0, dtype=float) + rng.normal(scale=0.05,
                                                       size=(count, model.n_coordinates))
    return model, x


def features_of(asm, x):
    return [g.type.deformations_and_features(xe, g.reference)[1]
            for g, xe in zip(asm.groups, asm.element_values(x), strict=True)]


def test_jacobian_and_scaled_constraint_matrix_from_features():
    model, x = everything_at_random_configurations()
    asm = model.assembly
    assert not asm.sparse and {g.type.name for g in asm.groups} == {
        "truss", "beam", "rigid beam", "hinge"}
    system = SystemJacobian(asm, features_of(asm, x))
    for k in range(len(x)):
        D_x = jacobian(model, x[k])
        np.testing.assert_allclose(system.dense[k], D_x, rtol=0, atol=1e-15)
        D_c = D_x[np.ix_(asm.rows, asm.dependent)]
        expected = asm.constraint_row_scale[:, None] * D_c * asm.row_scale_columns
        np.testing.assert_allclose(system.scaled_constraint_matrix()[k], expected,
                                   rtol=0, atol=1e-15)
        np.testing.assert_array_equal(system.member(k).dense[0], system.dense[k])


def test_mass_matrix_from_features():
    model, x = everything_at_random_configurations()
    asm = model.assembly
    assert asm.varying_mass_groups and len(asm.nodal_mass_coordinates)
    features = [g.type.mass_features(xe, g.reference)
                for g, xe in zip(asm.groups, asm.element_values(x), strict=True)
                if g in asm.varying_mass_groups]
    M = asm.mass_matrix(features, len(x))
    for k in range(len(x)):
        np.testing.assert_allclose(M[k], mass_matrix(model, x[k]), rtol=0, atol=1e-15)


def test_selectors_index_as_the_index_sets():
    """``Assembly.take`` holds slices for contiguous index sets: the same entries."""
    from flexmbd.assembly import as_selector

    assert as_selector(np.array([3, 4, 5])) == slice(3, 6)
    assert as_selector(np.array([], dtype=int)) == slice(0, 0)
    np.testing.assert_array_equal(as_selector(np.array([3, 5, 6])), [3, 5, 6])
    asm = everything_at_random_configurations()[0].assembly
    for name, selector in asm.take._asdict().items():
        index = getattr(asm, name)
        table = np.arange(40.0)[None].repeat(2, axis=0)
        np.testing.assert_array_equal(table[:, selector], table[:, index], err_msg=name)
