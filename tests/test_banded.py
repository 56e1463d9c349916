"""The static engine in all coordinates on the banded saddle-point system
(:mod:`flexmbd.analysis.banded`) against the reduced one on the degrees of freedom: the
same equilibria, frequencies and compliance from a different formulation (coordinates
and constraint stresses with ``[[K, D_c^T], [D_c, 0]]`` against the dense tangent ``K0 +
G0`` over ``q``), and the compliance against finite differences of the equilibrium."""

import math

import numpy as np
import pytest

import flexmbd as fm

STEEL = fm.Material.from_poisson(210e9, 0.3, 7800.0)
LEAF = fm.Rectangle(0.03, 0.5e-3)
L = 0.1
EI = STEEL.E * 0.03 * 0.5e-3**3 / 12


def _pivot(beams: int = 4, gravity: bool = True) -> fm.Model:
    """The cross-spring pivot of issue 37's benchmark (:func:`pivot_builder`), its
    over-constraints released."""
    b = pivot_builder(beams, gravity)
    b.release_overconstraints()
    return b.build()


def pivot_builder(beams: int = 4, gravity: bool = True) -> fm.ModelBuilder:
    """The cross-spring pivot of issue 37's benchmark, described: two leaves of ``beams``
    beams (at most 200) side by side along y, crossing at 90 degrees, a rigid stage with
    mass and rotary inertia across their tops (six over-constraints, not yet released);
    under gravity along -z."""
    h = L / math.sqrt(2)
    b = fm.ModelBuilder("cross-spring pivot")
    b.add_node(1, -h / 2, 0, 0).add_node(3, h / 2, 0, h)
    b.add_node(5, h / 2, 0.04, 0).add_node(7, -h / 2, 0.04, h)
    b.add_spatial_beams(1, 1, 2, 3, 4, beams, (0, 1, 0), new_nodes=1000, section=LEAF,
                        material=STEEL)
    b.add_spatial_beams(201, 5, 6, 7, 8, beams, (0, 1, 0), new_nodes=2000, section=LEAF,
                        material=STEEL)
    b.add_node(9, 0, 0.02, h)
    b.add_spatial_beam(401, 3, 4, 9, 10, (0, 0, 1)).add_spatial_beam(402, 9, 10, 7, 8,
                                                                     (0, 0, 1))
    b.fix(1).fix(2).fix(5).fix(6)
    b.add_point_mass(9, 0.25).add_rotary_inertia(10, 1e-4, 0, 0, 1e-4, 0, 1e-4)
    if gravity:
        b.set_gravity(0, 0, -9.81)
    return b


TURN = {"x10.3": 0.3 * 2 * EI / L}   #: the moment about the pivot axis for about 0.3 rad


def _planar_arm() -> fm.Model:
    """A planar arm of ten flexible beams (1 m) under gravity, one of them pre-stressed,
    clamped at node 1; a hinge between its halves (rotational nodes 12 and 100) is driven
    (an input deformation)."""
    b = fm.ModelBuilder("planar arm")
    for k in range(11):
        b.add_node(2 * k + 1, 0.1 * k, 0.0)
    for k in range(10):
        phi_p = 100 if k == 5 else 2 * k + 2
        b.add_beam(k + 1, 2 * k + 1, phi_p, 2 * k + 3, 2 * k + 4)
        b.dynamic_deformation(k + 1, 1, 2, 3)
        b.set_stiffness(k + 1, axial=2e5, bending=40.0).set_mass(k + 1, 0.8)
    b.add_hinge(50, 12, 100).input_deformation(50, 1)
    b.set_prestress(3, 1, 50.0).set_gravity(0.0, -9.81)
    return b.fix(1).fix(2).build()


def _compare_rows(a: fm.StaticResult, b: fm.StaticResult, size: float) -> None:
    assert len(a.load) == len(b.load)
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-9 * size)
    scale = np.abs(a.sigma).max()
    np.testing.assert_allclose(a.sigma, b.sigma, rtol=0, atol=1e-7 * scale)


def test_the_pivot_s_equilibria_are_the_reduced_solver_s():
    """Moment, gravity, point mass and releases: every load step's coordinates to 1e-9 of
    the leaf length and stresses to 1e-7 of the largest, the two formulations apart."""
    model = _pivot()
    reduced = fm.static_equilibrium(model, load_increment=TURN, steps=5, method="reduced")
    banded = fm.static_equilibrium(model, load_increment=TURN, steps=5, method="banded")
    _compare_rows(reduced, banded, L)
    assert 2 * math.asin(banded["x10.3"][-1]) == pytest.approx(0.3, rel=0.02)


def test_a_planar_arm_s_equilibria_are_the_reduced_solver_s():
    """Planar, with gravity, pre-stress, a tip load and a driven hinge (its angle an
    input increment, a target of the constraint equations in all coordinates)."""
    model = _planar_arm()
    given = dict(load_increment={"x21.2": -20.0}, input_increment={"e50.1": 0.6}, steps=4)
    reduced = fm.static_equilibrium(model, method="reduced", **given)
    banded = fm.static_equilibrium(model, method="banded", **given)
    _compare_rows(reduced, banded, 1.0)
    assert banded["e50.1"][-1] == pytest.approx(0.6, abs=1e-12)


def test_a_spring_hinge_turns_through_two_turns_in_all_coordinates():
    """A spatial hinge's spring under a growing moment about its axis, 2.2 turns in 24
    steps: the banded engine keeps the hinge's rotation continuous beyond half a turn
    (the coordinates alone give it within half a turn), so its stress is right."""
    k, turns, steps = 2.0, 2.2, 24
    b = fm.ModelBuilder("spring hinge")
    b.add_spatial_hinge(1, 1, 2).fix(1).dynamic_deformation(1, 1).set_stiffness(1, hinge=k)
    model = b.build()
    moment = k * turns * 2 * np.pi
    statics = fm.static_equilibrium(model, load_increment={"x2.4": moment}, steps=steps,
                                    method="banded")
    np.testing.assert_allclose(statics["e1.1"], statics["load"] * moment / k, atol=1e-9)
    np.testing.assert_allclose(statics["sig1.1"], statics["load"] * moment, atol=1e-8)


def _table(model, statics, monkeypatch, banded: bool, **given):
    """The table by the banded tangent and ARPACK (``banded``), or by the reduced
    matrices and LAPACK, whatever the model's size."""
    from flexmbd.analysis import eigen, linearization

    monkeypatch.setattr(linearization, "BANDED_FROM", 0 if banded else 10**9)
    monkeypatch.setattr(eigen, "FEW_MODES_FROM", 0 if banded else 10**9)
    table = fm.load_step_table(statics, **given)
    ways = " ".join(way for ways in table.paths.values() for way in ways)
    assert ("banded" in ways) == banded and ("arpack" in ways) == banded, ways
    return table


def test_frequencies_and_compliance_along_the_steps_are_the_dense_ones(monkeypatch):
    """Every step of the loaded pivot: the six lowest frequencies by ARPACK on the banded
    tangent equal the dense reduced eigenproblem's to 1e-8, and the stage's
    6x6 compliance (global and body axes) the dense solve's to 1e-8 of its largest."""
    model = _pivot()
    statics = fm.static_equilibrium(model, load_increment=TURN, steps=4)
    given = dict(modes=6, compliance=[(9, 10)])
    for frame in ("global", "body"):
        banded = _table(model, statics, monkeypatch, True, frame=frame, **given)
        dense = _table(model, statics, monkeypatch, False, frame=frame, **given)
        frequencies = [f"f{k}" for k in range(1, 7)]
        for name in frequencies:
            np.testing.assert_allclose(banded[name], dense[name], rtol=1e-8)
        entries = [name for name in dense if name.startswith("C9.")]
        largest = max(np.abs(dense[name]).max() for name in entries)
        for name in entries:
            np.testing.assert_allclose(banded[name], dense[name], rtol=0, atol=1e-8 * largest)


def test_the_compliance_under_a_moment_is_the_equilibrium_s_own_slope():
    """The stage's compliance at the last step against central differences of the static
    equilibrium itself under small extra forces and moments on the stage (moving it by
    1e-5 of the leaf length or 1e-5 rad; the differences' error is 2e-6): the response
    to a load, unsymmetric as the moment's load stiffness is (the moment keeps its axis
    while the stage turns; by 3e-3 here), each entry to 1e-5 of the geometric mean of its
    row's and column's diagonal entries. The leaves' weight turns with their rotations:
    without its load stiffness three columns are off by 3e-5."""
    model = _pivot()
    steps = 3
    statics = fm.static_equilibrium(model, load_increment=TURN, steps=steps)
    table = fm.load_step_table(statics, compliance=[(9, 10)])
    C = np.array([[table[f"C9.{i}{j}"][-1] for j in range(1, 7)] for i in range(1, 7)])
    labels = ["x9.1", "x9.2", "x9.3", "x10.2", "x10.3", "x10.4"]
    at = [model.coordinate_index(f"x10.{k}") for k in range(1, 5)]
    centre = [model.coordinate_index(f"x9.{k}") for k in (1, 2, 3)]
    x0 = statics.x[-1]
    slopes = np.empty((6, 6))
    for j, label in enumerate(labels):
        size = 1e-5 * (L if j < 3 else 1.0) / C[j, j]
        moved = []
        for sign in (1.0, -1.0):
            x = fm.static_equilibrium(model, loads={label: sign * size}, load_increment=TURN,
                                      steps=steps).x[-1]
            moved.append(np.concatenate([x[centre],
                                         fm.angular_velocity(x0[at], x[at] - x0[at])]))
        slopes[:, j] = (moved[0] - moved[1]) / (2 * size)
    scale = np.sqrt(np.outer(np.diag(C), np.diag(C)))
    np.testing.assert_array_less(np.abs(slopes - C), 1e-5 * scale)
    assert np.abs((C - C.T) / scale).max() > 1e-3   # unsymmetric, far beyond rounding


def test_where_newton_in_all_coordinates_fails_the_reduced_newton_takes_the_step(
        monkeypatch):
    """A step the all-coordinate Newton cannot take (here forced) is taken, after two
    halvings, by the reduced solver's Newton, which solves the constraints at every
    iteration: the same equilibria, and the result says so (method="banded" warns)."""
    from flexmbd.analysis import banded

    model = _pivot()
    reduced = fm.static_equilibrium(model, load_increment=TURN, steps=2, method="reduced")

    def fails(*args, **kwargs):
        raise fm.ConvergenceError("forced")

    monkeypatch.setattr(banded.BandedStatics, "equilibrium", fails)
    with pytest.warns(fm.AnalysisWarning, match="by the reduced Newton"):
        rescued = fm.static_equilibrium(model, load_increment=TURN, steps=2, method="banded")
    _compare_rows(reduced, rescued, L)
    # row 0 and two steps, each after two halvings in a quarter, a half and a quarter
    assert "9 stretches by the reduced Newton" in rescued.message
    quiet = fm.static_equilibrium(model, load_increment=TURN, steps=2)   # auto: no warning
    assert "by the reduced Newton" in quiet.message
