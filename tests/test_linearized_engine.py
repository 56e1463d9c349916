"""One linearized engine behind every door: the per-step public analyses, the load-step
table and ``light.run`` run the same path (the banded tangent and ARPACK for a large
model at an equilibrium, the reduced matrices and LAPACK otherwise), take what a user
holds, record their path, and turn only physical failures into NaN, with the reason."""

import numpy as np
import pytest
from flexmbd.examples import flexures

import flexmbd as fm
from flexmbd import light
from flexmbd.analysis import eigen, linearization
from tests.test_banded import TURN, _pivot


@pytest.fixture(scope="module")
def loaded():
    """The pivot of twelve beams per leaf (138 degrees of freedom: the banded tangent and
    ARPACK by size) turned in three load steps."""
    model = _pivot(12)
    return fm.static_equilibrium(model, load_increment=TURN, steps=3)


def _dense(monkeypatch) -> None:
    """Make every size take the reduced matrices and LAPACK."""
    monkeypatch.setattr(linearization, "BANDED_FROM", 10**9)
    monkeypatch.setattr(eigen, "FEW_MODES_FROM", 10**9)


def test_the_per_step_path_is_the_table_s(loaded):
    """A loop over the steps with the public analyses gives the table's numbers exactly:
    one path, recorded as ARPACK on the banded tangent."""
    table = fm.load_step_table(loaded, modes=6, compliance=[(9, 10)])
    assert table.paths["modes"] == [str(fm.vibration_modes(loaded, 6).path)]
    assert "arpack on the banded tangent" in table.paths["modes"][0]
    assert table.paths["compliance"] == ["the engine's banded tangent"] and not table.notes
    for row in range(len(loaded.load)):
        lin = loaded.linearization(row)
        f = fm.vibration_modes(lin, 6).frequencies
        C = fm.node_compliance(lin, 9, 10)
        np.testing.assert_array_equal(f, [table[f"f{k}"][row] for k in range(1, 7)])
        np.testing.assert_array_equal(C[2, 4], table["C9.35"][row])


def test_banded_modes_and_shapes_are_the_reduced_ones(loaded, monkeypatch):
    """At the loaded last step (its moment's load stiffness makes the tangent
    unsymmetric): ARPACK on the banded tangent with Rayleigh-Ritz on exact element
    products against LAPACK on the dense reduced matrices, a different formulation: the
    frequencies to 1e-9, the shapes (as coordinate motions) to 1e-6 of their largest."""
    banded = fm.vibration_modes(loaded, 6)
    assert banded.linearization.tangent is not None
    _dense(monkeypatch)
    dense = fm.vibration_modes(loaded.linearization(), 6)
    assert dense.path.method == "dense" and dense.linearization.tangent is None
    np.testing.assert_allclose(banded.frequencies, dense.frequencies, rtol=1e-9)
    for k in range(6):
        a, b = banded.motion[:, k], dense.motion[:, k]
        sign = np.sign(a @ b)
        np.testing.assert_allclose(a, sign * b, atol=1e-6 * np.abs(b).max())
    mass = dense.linearization.block("M0")
    np.testing.assert_allclose(np.einsum("ik,ij,jk->k", banded.shapes, mass, banded.shapes),
                               1.0, rtol=1e-8)


def test_the_analyses_take_what_users_hold(loaded):
    """A Model means its reference configuration, a static result its last row (or
    ``row``), a motion's result its row with the rates; anything else is refused by
    name, saying what to pass."""
    model = loaded.model
    at_rest = fm.linearize(model)
    np.testing.assert_array_equal(fm.vibration_modes(model, 3).frequencies,
                                  fm.vibration_modes(at_rest, 3).frequencies)
    last, first = loaded.linearization(), loaded.linearization(0)
    np.testing.assert_array_equal(fm.node_compliance(loaded, 9, 10),
                                  fm.node_compliance(last, 9, 10))
    np.testing.assert_array_equal(fm.compliance(loaded, ["x9.1"], row=0),
                                  fm.compliance(first, ["x9.1"]))
    np.testing.assert_array_equal(fm.buckling(loaded, 1).factors, fm.buckling(last, 1).factors)
    np.testing.assert_array_equal(fm.state_space(loaded, ["x9.1"], ["x9.1"]).A,
                                  fm.state_space(last, ["x9.1"], ["x9.1"]).A)
    for wrong in (3, "model", None, np.zeros(4)):
        with pytest.raises(fm.ArgumentError, match=r"linearization: must be a linearized "
                                                   r"state .* a Model"):
            fm.vibration_modes(wrong)
    with pytest.raises(fm.ArgumentError, match=r"row: must lie in -4 \.\. 3"):
        fm.node_compliance(loaded, 9, 10, row=4)
    with pytest.raises(fm.ArgumentError, match="row: is for a result's rows"):
        fm.vibration_modes(model, row=0)


def test_a_motion_s_row_is_linearized_with_its_rates():
    """A pendulum swinging: its row's modes are those of linearize at that state with its
    rates (the inertia terms N0 included), and a result without rates is refused."""
    pendulum = (fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 1, 0)
                .add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1)
                .dynamic_coordinate(2).set_gravity(0, -9.81).build())
    motion = fm.simulate(pendulum, np.linspace(0, 0.3, 4), outputs="all")
    x, model = motion.x[2], motion.model
    qd = np.array([motion.xd[2, model.independent_coordinates[0]]])
    qdd = np.array([motion.xdd[2, model.independent_coordinates[0]]])
    direct = fm.vibration_modes(fm.linearize(pendulum, x, qd, qdd), 1)
    assert fm.vibration_modes(motion, 1, row=2).omega2 == pytest.approx(direct.omega2,
                                                                        rel=1e-12)
    bare = fm.simulate(pendulum, np.linspace(0, 0.3, 4), outputs="positions")
    with pytest.raises(fm.ArgumentError, match="outputs='all'"):
        fm.vibration_modes(bare, row=1)


def test_a_state_off_equilibrium_takes_the_reduced_tangent(loaded):
    """The pivot's reference configuration under its weight is no equilibrium: its
    balancing stresses are not the elastic ones, so the reduced tangent serves, and
    says why."""
    lin = fm.linearize(loaded.model)
    assert lin.tangent is None and "not an equilibrium" in lin.tangent_reason
    assert fm.vibration_modes(lin, 3).path.system == "reduced"
    assert loaded.linearization().tangent is not None


def test_arpack_that_cannot_tell_the_modes_falls_back_with_a_warning(loaded, monkeypatch):
    """Where ARPACK fails, LAPACK gives the same modes, and an AnalysisWarning and the
    path say so."""
    expected = fm.vibration_modes(loaded, 4).frequencies

    def fails(*args, **kwargs):
        raise eigen.EigenError("ARPACK did not converge to the 8 lowest modes")

    from flexmbd.analysis import modes

    monkeypatch.setattr(modes, "lowest_arpack", fails)
    with pytest.warns(fm.AnalysisWarning, match="ARPACK on the banded tangent failed"):
        found = fm.vibration_modes(loaded, 4)
    assert found.path.method == "dense" and "did not converge" in found.path.reason
    np.testing.assert_allclose(found.frequencies, expected, rtol=1e-9)


def test_only_physical_failures_become_nan_with_their_reason(monkeypatch):
    """A state without stresses has no buckling factor and a stage without stiffness no
    compliance: NaN with the reason in the table's notes. Any other error (here a bug
    planted in the modes) propagates."""
    model = _pivot(2, gravity=False)
    unloaded = fm.static_equilibrium(model)
    table = fm.load_step_table(unloaded, modes=2, buckle=1)
    assert np.isnan(table["buckling1"][0]) and np.all(np.isfinite(table["f1"]))
    assert len(table.notes) == 1 and "no stresses" in table.notes[0]
    assert "buckling1..buckling1 at step 0" in repr(table)
    asked = fm.load_step_table(unloaded, modes=1000)
    assert np.isnan(asked["f1000"][0]) and "f" in asked.notes[0] and "state has" in \
        asked.notes[0]

    from flexmbd.analysis import load_steps

    def planted(*args, **kwargs):
        raise ValueError("a plain bug")

    monkeypatch.setattr(load_steps, "vibration_modes", planted)
    with pytest.raises(ValueError, match="a plain bug"):
        fm.load_step_table(unloaded, modes=2)


def test_a_column_past_buckling_has_no_compliance_and_says_so():
    """A straight cantilever pressed by twice its buckling load stays straight (an
    unstable equilibrium): no compliance (NaN in the table, with the reason), a
    negative lowest omega^2 (an unstable mode, not an error)."""
    b = fm.ModelBuilder("cantilever")   # 1 m, four beams, EI = 2 N m^2: buckles at 4.93 N
    for k in range(5):
        b.add_node(2 * k + 1, 0.25 * k, 0.0)
    for k in range(4):
        (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
         .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
         .set_stiffness(k + 1, axial=1e6, bending=2.0))
    column = b.fix(1).fix(2).build()
    statics = fm.static_equilibrium(column, loads={"x9.1": -10.0})
    table = fm.load_step_table(statics, modes=1, compliance=[(9, 10)])
    assert np.isnan(table["C9.22"][0]) and "not positive definite" in table.notes[0]
    assert table["f1"][0] < 0


def test_light_run_computes_a_large_model_s_lowest_frequencies():
    """SPACAR Light's cross hinge at 10 beams per leaf: the 12 lowest frequencies by
    default (noted), every one with opt.nmodes = 'all', the same lowest ones either way;
    a bad count is refused by name."""
    leaf = dict(flexures.HINGE_LEAF, nbeams=10)
    args = (flexures.HINGE_NODES, flexures.HINGE_ELEMENTS,
            {1: {"fix": True}, 4: {"fix": True}, 3: {"mass": 0.1}}, [leaf, flexures.HINGE_BODY])
    few = light.run(*args, {"silent": True})
    every = light.run(*args, {"silent": True, "nmodes": "all"})
    assert few.freq.shape == (12, 1) and every.freq.shape == (every.ndof, 1)
    assert any("the 12 lowest of" in note for note in few.notes)
    np.testing.assert_allclose(few.freq[:, 0], every.freq[:12, 0], rtol=1e-8)
    assert light.run(*args, {"silent": True, "nmodes": 3}).freq.shape == (3, 1)
    for bad in (0, 2.5, "some", True):
        with pytest.raises(fm.ArgumentError, match=r"opt\.nmodes"):
            light.run(*args, {"silent": True, "nmodes": bad})
