"""Design sensitivities (:mod:`flexmbd.design`): every output's exact gradient against
converged central differences of the public analyses (Richardson-extrapolated, with a
tight Newton tolerance), closed forms of a cantilever, and the engine's own residual."""

import dataclasses
import math

import numpy as np
import pytest
import sympy as sp
from flexmbd.examples import crossing_pivots

import flexmbd as fm
from flexmbd import design
from flexmbd.builder.recording import kept_releases
from flexmbd.design.evaluate import Design
from flexmbd.design.hyperdual import MATH, seed
from flexmbd.design.state import Equilibrium

GAP, WIDTH = 0.04, 0.03


def cantilever(EI=2.0, L=1.0, P=1e-6, axial=0.0, tip=0.0):
    """A planar cantilever of four beams along x (SPACAR's first exercise), tip loads ``P``
    down and ``axial`` along it; ``tip`` a moment [N, N m]."""
    b = fm.ModelBuilder("cantilever")
    for k in range(5):
        b.add_node(2 * k + 1, 0.25 * L * k, 0.0)
    for k in range(4):
        (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
         .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
         .set_stiffness(k + 1, axial=1e4, bending=EI))
    loads = {"x9.2": -P, "x9.1": -axial, "x10.1": tip}
    return b.fix(1).fix(2).build(), fm.RunSettings(load_increment=loads, load_steps=2)


def pivot(t=0.5e-3, L=0.1, mass=0.25, g=0.0, w=WIDTH, rotation=0.3, beams=2,
          tolerance=None):
    """The cross-spring pivot of the flexure benchmark: two steel leaves ``w`` x ``t`` of
    length ``L`` crossing at their middles, a stage of ``mass`` turned by the moment that
    takes ``rotation`` [rad] at ``2 EI/L``, gravity ``g`` along -z; releases as SPACAR
    Light makes them."""
    steel = fm.Material.from_poisson(210e9, 0.3, 7800.0)
    b = fm.ModelBuilder("cross-spring pivot")
    h = L / math.sqrt(2)
    b.add_node(1, -h / 2, 0, 0).add_node(3, h / 2, 0, h)
    b.add_node(5, h / 2, GAP, 0).add_node(7, -h / 2, GAP, h)
    for first, ends in ((1, (1, 2, 3, 4)), (201, (5, 6, 7, 8))):
        b.add_spatial_beams(first, *ends, beams, (0, 1, 0), new_nodes=1000 * (first // 200 + 1),
                            section=fm.Rectangle(w, t), material=steel)
    b.add_node(9, 0, GAP / 2, h)
    b.add_spatial_beam(401, 3, 4, 9, 10, (0, 0, 1)).add_spatial_beam(402, 9, 10, 7, 8,
                                                                     (0, 0, 1))
    b.fix(1).fix(2).fix(5).fix(6)
    b.add_point_mass(9, mass).add_rotary_inertia(10, 1e-4, 0, 0, 1e-4, 0, 1e-4)
    if g:
        b.set_gravity(0, 0, -g)
    b.release_overconstraints()
    moment = rotation * 2 * steel.E * w * t**3 / 12 / L
    return b.build(), fm.RunSettings(load_increment={"x10.3": moment}, load_steps=3,
                                     tolerance=tolerance)


def tight(build):
    """``build`` with a Newton tolerance at the coordinates' rounding: the references."""
    def tightened(**params):
        model, settings = build(**params)
        return model, dataclasses.replace(settings, tolerance=5e-14)
    return tightened


def central(build, params, outputs, name, rel):
    """Richardson's extrapolation of two central differences (steps ``rel`` and ``rel/2``
    of the parameter), each design analysed from scratch."""
    estimates = []
    for step in (rel, rel / 2):
        h = step * abs(params[name])
        sides = [design.evaluate(tight(build), {**params, name: params[name] + s * h},
                                 outputs, gradient=False).values for s in (-1.0, 1.0)]
        estimates.append({k: (sides[1][k] - sides[0][k]) / (2 * h) for k in outputs})
    return {k: (4 * estimates[1][k] - estimates[0][k]) / 3 for k in outputs}


def assert_gradients(build, params, outputs, rel=1e-3, rtol=1e-6, stress_rtol=1e-5):
    exact = design.evaluate(build, params, outputs)
    for name in params:
        reference = central(build, params, outputs, name, rel)
        for out in outputs:
            # a derivative that vanishes is judged against the output's own scale
            floor = 1e-7 * abs(exact.values[out]) / abs(params[name])
            # stresses and reactions sum large internal forces: the differences of the
            # analyses (not the exact derivatives) carry their rounding, 1e-6 of a step
            tol = stress_rtol if out.startswith("stress") or ("." in out and \
                out.startswith("f")) else rtol
            assert exact.gradient[out][name] == pytest.approx(
                reference[out], rel=tol, abs=floor), (out, name)
    return exact


# --- the pieces ----------------------------------------------------------------------------
def test_hyperdual_numbers_give_the_third_derivatives_sympy_gives():
    x0, y0 = 0.7, -1.3
    a, b, c = (1.0, 0.5), (-0.3, 2.0), (0.8, 0.1)
    X = seed(np.array(x0), [np.array(a[0]), np.array(b[0]), np.array(c[0])])
    Y = seed(np.array(y0), [np.array(a[1]), np.array(b[1]), np.array(c[1])])
    f = MATH.sqrt(X * X + Y**2) * MATH.atan2(Y, X) / (2.0 - MATH.sin(X)) + MATH.cos(Y * X)**3
    xs, ys, t1, t2, t3 = sp.symbols("x y t1 t2 t3")
    F = (sp.sqrt(xs**2 + ys**2) * sp.atan2(ys, xs) / (2 - sp.sin(xs))
         + sp.cos(ys * xs)**3).subs({xs: x0 + t1 * a[0] + t2 * b[0] + t3 * c[0],
                                     ys: y0 + t1 * a[1] + t2 * b[1] + t3 * c[1]})
    at = {t1: 0, t2: 0, t3: 0}
    for mask in range(8):
        wrt = [t for bit, t in enumerate((t1, t2, t3)) if mask >> bit & 1]
        expected = float((sp.diff(F, *wrt) if wrt else F).subs(at))
        assert f.parts[mask] == pytest.approx(expected, rel=1e-13, abs=1e-13)


@pytest.mark.parametrize("g", [0.0, 9.81])
def test_the_element_residual_is_the_engines(g):
    """The static residual from the element definitions (hyper-dual) against the core's at
    a state away from equilibrium: the same equations."""
    model, settings = pivot(g=g)
    statics = fm.static_equilibrium(model, load_increment=dict(settings.load_increment),
                                    steps=2, progress=False)
    state = Equilibrium(model, statics.x[-1], statics.q[-1], statics.sigma[-1],
                        statics.applied[-1])
    rng = np.random.default_rng(1)
    x = state.x.copy()
    x[state.free] += 1e-4 * rng.standard_normal(len(state.free))
    mu = state.mu * (1 + 0.1 * rng.standard_normal(len(state.mu)))
    core = state.banded.factor(x, state.q, mu, state.loads)
    assert np.abs(core).max() > 1.0
    np.testing.assert_allclose(state.residual(x, mu), core, rtol=0, atol=1e-12 *
                               np.abs(core).max())


# --- gradients against the closed forms ---------------------------------------------------
def test_cantilever_gradients_are_the_closed_forms():
    """Tip deflection ``P L^3/(3 EI)`` and compliance ``L^3/(3 EI)``, ``L^2/(2 EI)`` under a
    small load: their derivatives to ``EI``, ``L`` and ``P``."""
    EI, L, P = 2.0, 1.0, 1e-6
    r = design.evaluate(cantilever, {"EI": EI, "L": L, "P": P},
                        ["x9.2", "C[9,10][1,1]", "C[9,10][1,2]"])
    assert r.gradient["x9.2"]["EI"] == pytest.approx(P * L**3 / (3 * EI**2), rel=1e-6)
    assert r.gradient["x9.2"]["L"] == pytest.approx(-P * L**2 / EI, rel=1e-6)
    assert r.gradient["x9.2"]["P"] == pytest.approx(-L**3 / (3 * EI), rel=1e-6)
    assert r.gradient["C[9,10][1,1]"]["EI"] == pytest.approx(-L**3 / (3 * EI**2), rel=1e-6)
    assert r.gradient["C[9,10][1,1]"]["L"] == pytest.approx(L**2 / EI, rel=1e-6)
    assert r.gradient["C[9,10][1,2]"]["L"] == pytest.approx(L / EI, rel=1e-6)


# --- gradients against central differences of the analyses -------------------------------
def test_planar_large_deflection_and_buckling_gradients():
    """A cantilever bent far (tip moment) and pressed: positions, deformations, stresses,
    reactions, frequencies, buckling factors and compliance."""
    outputs = ["x9.1", "x10.1", "e4.3", "sig2.1", "f1.2", "f1", "f2", "buckling1",
               "C[9,10][0,1]"]
    assert_gradients(cantilever, {"EI": 2.0, "L": 1.0, "P": 0.5, "axial": 0.2, "tip": 1.5},
                     outputs)


@pytest.mark.parametrize("g", [0.0, 9.81])
def test_pivot_gradients_match_central_differences(g):
    """The spatial cross pivot turned 0.3 rad by a global moment (an unsymmetric tangent),
    with and without gravity on its leaves: thickness, length, stage mass."""
    outputs = ["x10.3", "e2.3", "f1", "f2", "C[9,10][4,4]", "C[9,10][0,4]", "stress_max",
               "stress_ks", "f1.3"]
    params = {"t": 0.5e-3, "L": 0.1, "mass": 0.25}
    if g:
        params["g"] = g
    assert_gradients(pivot, params, outputs, rel=2e-3)


def test_symmetric_cross_pivot_stiffness_scales_as_2EI_over_L():
    """Leaves crossing at their middles turn with ``2 EI/L``: at a small rotation the
    stage's rotational compliance has log-derivatives -3 in thickness, -1 in width and
    +1 in length: the exact derivatives give them to 1e-9 (the leaves' shear and stretch
    at this size stay below that)."""
    params = {"t": 0.5e-3, "w": WIDTH, "L": 0.1}
    r = design.evaluate(lambda **p: pivot(**p, rotation=1e-4, beams=4), params,
                        "C[9,10][4,4]")
    C = r.values["C[9,10][4,4]"]
    steel_E = 210e9
    assert pytest.approx(0.1 / (2 * steel_E * WIDTH * 0.5e-3**3 / 12), rel=1e-6) == C
    slopes = {name: r.gradient["C[9,10][4,4]"][name] * value / C
              for name, value in params.items()}
    assert slopes["t"] == pytest.approx(-3.0, abs=1e-7)
    assert slopes["w"] == pytest.approx(-1.0, abs=1e-7)
    assert slopes["L"] == pytest.approx(1.0, abs=1e-7)


def test_a_design_keeps_its_releases():
    """A change of a leaf's length would let the automatic releases choose another set;
    the design keeps the first one, so both sides of a difference share a structure."""
    with kept_releases() as kept:
        first = pivot()[0]
        again = pivot(L=0.1 * (1 + 1e-6))[0]
    assert kept["releases"]
    assert list(first.deformation_class) == list(again.deformation_class)


# --- refusals ------------------------------------------------------------------------------
def test_unknown_outputs_and_bad_parameters_are_refused_by_name():
    with pytest.raises(fm.ArgumentError, match="'f0': modes count from 1"):
        design.evaluate(cantilever, {"EI": 2.0}, "f0")
    with pytest.raises(fm.ArgumentError, match="'omega1' is not an output"):
        design.evaluate(cantilever, {"EI": 2.0}, ["x9.2", "omega1"])
    with pytest.raises(fm.ArgumentError, match="'EI' must be a finite number"):
        design.evaluate(cantilever, {"EI": "2"}, "x9.2")
    with pytest.raises(fm.ArgumentError, match="named twice"):
        design.evaluate(cantilever, {"EI": 2.0}, ["x9.2", "x9.2"])
    with pytest.raises(fm.ArgumentError, match=r"build.*failed at \{'EJ': 2.0\}"):
        design.evaluate(cantilever, {"EJ": 2.0}, "x9.2")


def test_a_parameter_that_changes_the_structure_is_refused():
    with pytest.raises(fm.ArgumentError, match="'beams' changes the model's structure"):
        design.evaluate(lambda beams: pivot(beams=round(beams)), {"beams": 2.4999999}, "f1")


def test_a_repeated_frequency_has_no_derivative():
    """A spatial cantilever of square section bends alike in y and z."""
    def square(t):
        steel = fm.Material.from_poisson(210e9, 0.3, 7800.0)
        b = fm.ModelBuilder("square rod")
        b.add_node(1, 0, 0, 0).add_node(3, 0.1, 0, 0)
        b.add_spatial_beams(1, 1, 2, 3, 4, 3, (0, 1, 0), new_nodes=100,
                            section=fm.Rectangle(t, t), material=steel)
        return b.fix(1).fix(2).build()

    values = design.evaluate(square, {"t": 0.01}, ["f1", "f2"], gradient=False).values
    assert values["f1"] == pytest.approx(values["f2"], rel=1e-9)
    with pytest.raises(fm.ArgumentError, match="f1 is a repeated frequency"):
        design.evaluate(square, {"t": 0.01}, "f1")


def test_the_state_sensitivity_is_one_factorisation():
    """The direct method: every parameter's state change from the one factorised tangent;
    its linear prediction of the neighbouring design's equilibrium is good to second
    order in the step."""
    params = {"t": 0.5e-3, "L": 0.1}
    with kept_releases():
        nominal = Design(tight(pivot), params)
        nominal.sensitivities()
        misses = []
        for rel in (1e-4, 1e-5):
            h = rel * params["t"]
            moved = Design(tight(pivot), {**params, "t": params["t"] + h})
            predicted = nominal.x + h * nominal.dx[0]
            misses.append(np.abs(moved.x - predicted).max())
    change = np.abs(nominal.dx[0]).max() * 1e-4 * params["t"]
    assert misses[0] < 1e-4 * change      # second order: 1e-4 of the change itself
    assert misses[1] < misses[0] / 20     # and a tenth of the step gives a hundredth


# --- optimisation ---------------------------------------------------------------------------
STROKE, LIMIT = 2e-3, 60e6


def leaf(t=0.5e-3, L=0.1):
    """A steel leaf spring (20 mm wide) clamped at one end, its other end driven ``STROKE``
    across (an input coordinate), its rotation free."""
    steel = fm.Material.from_poisson(210e9, 0.3, 7800.0)
    b = fm.ModelBuilder("leaf")
    b.add_node(1, 0, 0, 0).add_node(3, L, 0, 0)
    b.add_spatial_beams(1, 1, 2, 3, 4, 4, (0, 1, 0), new_nodes=100,
                        section=fm.Rectangle(0.02, t), material=steel)
    b.fix(1).fix(2).input_coordinate(3, 3)
    b.release_overconstraints()
    return b.build(), fm.RunSettings(input_increment={"x3.3": STROKE}, load_steps=2)


def test_the_stiffest_leaf_under_a_stress_limit():
    """The force the stroke takes grows with the thickness cubed, the root stress linearly:
    the optimum lies where the stress meets its limit, which a root search on the
    analyses alone finds independently (near the closed form ``2 L^2 sigma / (3 E d)``,
    off it by the leaf's shear and the large deflection)."""
    from scipy.optimize import brentq

    found = design.optimize(leaf, {"t": 0.5e-3, "L": 0.1}, "f1.3",
                            constraints={"stress_max": (None, LIMIT)},
                            bounds={"t": (1e-4, 2e-3), "L": (0.05, 0.1)})
    assert found.success, found.message
    root = brentq(lambda t: design.evaluate(leaf, {"t": t}, "stress_max", gradient=False)
                  .values["stress_max"] - LIMIT, 1e-4, 2e-3, xtol=1e-16, rtol=1e-15)
    assert found.x["L"] == pytest.approx(0.1, rel=1e-9)
    assert found.x["t"] == pytest.approx(root, rel=1e-6)
    assert root == pytest.approx(2 * 0.1**2 * LIMIT / (3 * 210e9 * STROKE), rel=1e-3)
    assert found.nfev <= 30
    assert found.outputs["stress_max"] == pytest.approx(LIMIT, rel=1e-6)


def test_check_gradient_reports_agreement_and_second_order():
    check = design.check_gradient(cantilever, {"EI": 2.0, "tip": 1.5}, ["x9.1", "f1"])
    assert check.worst < 1e-5
    for rates in check.taylor.values():
        assert all(r == pytest.approx(2.0, abs=0.1) for r in rates if r == r)
    assert "Taylor rates" in repr(check)


def test_optimize_refuses_bad_limits_by_name():
    with pytest.raises(fm.ArgumentError, match=r"\['T'\] are not parameters"):
        design.optimize(leaf, {"t": 0.5e-3}, "f1.3", bounds={"T": (0, 1)})
    with pytest.raises(fm.ArgumentError, match=r"low limit 2\.0 is above the high 1\.0"):
        design.optimize(leaf, {"t": 0.5e-3}, "f1.3", bounds={"t": (2.0, 1.0)})
    with pytest.raises(fm.ArgumentError, match="'stress_max': give a"):
        design.optimize(leaf, {"t": 0.5e-3}, "f1.3", constraints={"stress_max": 3.0})
    with pytest.raises(fm.ArgumentError, match="'omega' is not an output"):
        design.optimize(leaf, {"t": 0.5e-3}, "omega")


def driven_arm(L1=0.3, L2=0.5, angle=0.4, EI=5.0, P=2.0):
    """A planar arm: a rigid link turned by a driven hinge (an input deformation), then a
    flexible link of four beams under a tip load."""
    b = fm.ModelBuilder("driven arm")
    b.add_node(1, 0, 0).add_node(3, L1, 0)
    b.add_rigid_beam(1, 1, 2, 3).add_hinge(2, 4, 2)
    b.fix(1).fix(4).input_deformation(2, 1)
    previous = (3, 2)
    for k in range(1, 5):
        node = 10 + 2 * k
        b.add_node(node, L1 + L2 * k / 4, 0)
        (b.add_beam(10 + k, *previous, node, node + 1).dynamic_deformation(10 + k)
         .set_mass(10 + k, 0.2).set_stiffness(10 + k, axial=1e6, bending=EI))
        previous = (node, node + 1)
    return b.build(), fm.RunSettings(load_increment={"x18.2": -P},
                                     input_increment={"e2.1": angle}, load_steps=3)


def test_a_driven_input_and_its_stroke_are_design_parameters():
    """The drive's stroke (an input deformation's increment) and the links' lengths."""
    assert_gradients(driven_arm, {"L1": 0.3, "L2": 0.5, "angle": 0.4, "EI": 5.0},
                     ["x18.1", "x18.2", "C[18,19][1,1]", "f2"])


def test_a_weighted_sum_is_an_objective():
    """``{output: weight}`` minimises the weighted sum: twice an output has the same
    optimum as the output."""
    limits = {"stress_max": (None, LIMIT)}
    one = design.optimize(leaf, {"t": 0.5e-3}, "f1.3", constraints=limits,
                          bounds={"t": (1e-4, 2e-3)})
    two = design.optimize(leaf, {"t": 0.5e-3}, {"f1.3": 2.0}, constraints=limits,
                          bounds={"t": (1e-4, 2e-3)})
    assert two.x["t"] == pytest.approx(one.x["t"], rel=1e-9)
    assert two.fun == pytest.approx(2 * one.fun, rel=1e-9)
    with pytest.raises(fm.ArgumentError, match="weighted sum maps output names"):
        design.optimize(leaf, {"t": 0.5e-3}, {"f1.3": "2"})


def cross_pivots(crossing=0.2):
    """The three pivots of :mod:`flexmbd.examples.crossing_pivots` on a coarse mesh."""
    return crossing_pivots.pivots(crossing, beams=4)


def test_an_equality_on_a_difference_of_outputs():
    """Wittrick's crossing point on a coarse mesh: where the pulled and the pushed pivot
    turn alike. The optimiser's equality on the difference of their compliance lands on
    the root a search on the analyses alone finds."""
    from scipy.optimize import brentq

    names = [crossing_pivots.stage_compliance(k, beams=4) for k in range(3)]
    found = design.optimize(cross_pivots, {"crossing": 0.2}, names[0],
                            constraints={f"{names[1]} - {names[2]}": (0.0, 0.0)},
                            bounds={"crossing": (0.05, 0.3)})
    assert found.success, found.message

    def difference(crossing):
        v = design.evaluate(cross_pivots, {"crossing": crossing}, names[1:],
                            gradient=False).values
        return v[names[1]] - v[names[2]]

    root = brentq(difference, 0.05, 0.3, xtol=1e-14)
    assert found.x["crossing"] == pytest.approx(root, rel=1e-6)
    assert found.x["crossing"] == pytest.approx(crossing_pivots.WITTRICK, abs=0.02)


def test_a_failed_analysis_keeps_the_optimisation_so_far():
    """A design the analysis cannot converge ends the search with its error, the designs
    analysed so far attached."""
    def fragile(t):
        if t > 0.8e-3:
            raise fm.ConvergenceError("pretend: no equilibrium for so thick a leaf")
        return leaf(t)

    with pytest.raises(fm.ArgumentError, match=r"build.*pretend") as caught:
        design.optimize(fragile, {"t": 0.5e-3}, "f3.3", maximize=True,
                        bounds={"t": (1e-4, 2e-3)})
    partial = caught.value.partial_result
    assert partial.nfev >= 1 and not partial.success
    assert partial.x["t"] <= 0.8e-3


# --- several starts ---------------------------------------------------------------------------
def wavy(theta):
    """A node at height ``sin(3 theta) + theta / 5`` (a fixed end of a spring): the height
    has local minima at ``3 theta = 2 pi k - acos(-1/15)`` and at ``theta = 0``."""
    b = fm.ModelBuilder("wavy")
    b.add_node(1, 0, 0).add_node(2, 1, 0).add_truss(1, 1, 2).dynamic_deformation(1)
    b.set_stiffness(1, axial=100.0).fix(1).fix(2, "y")
    height = math.sin(3 * theta) + 0.2 * theta
    b.add_node(3, theta, height).add_node(4, theta + 1.0, height)
    b.add_truss(2, 3, 4).dynamic_deformation(2).set_stiffness(2, axial=100.0)
    b.fix(3).fix(4, "y")
    return b.build(), fm.RunSettings(load_increment={"x2.1": 1.0}, load_steps=1)


WAVY_LOCAL = (4 * math.pi - math.acos(-1 / 15)) / 3    # 3.643
WAVY_BEST = (2 * math.pi - math.acos(-1 / 15)) / 3     # 1.549, the lowest on [0, 4]


def test_starts_spread_over_the_bounds_find_the_lowest_optimum():
    one = design.optimize(wavy, {"theta": 3.5}, "x3.2", bounds={"theta": (0, 4)})
    assert one.x["theta"] == pytest.approx(WAVY_LOCAL, abs=1e-6)
    several = design.optimize(wavy, {"theta": 3.5}, "x3.2", bounds={"theta": (0, 4)},
                              starts=4, progress=False)
    assert several.x["theta"] == pytest.approx(WAVY_BEST, abs=1e-7)
    assert several.fun == pytest.approx(math.sin(3 * WAVY_BEST) + 0.2 * WAVY_BEST, abs=1e-12)
    assert several.starts[0]["theta"] == 3.5 and len(several.starts) == 4
    assert all(0 <= row["theta"] <= 4 and row["status"] == "ok" for row in several.starts)
    assert several.nfev > sum(row["nfev"] for row in several.starts)   # and the polish
    listed = design.optimize(wavy, {"theta": 3.5}, "x3.2", bounds={"theta": (0, 4)},
                             starts=[{"theta": 1.2}], progress=False)
    assert listed.x["theta"] == pytest.approx(WAVY_BEST, abs=1e-7)


def test_starts_run_on_dask_as_in_this_process():
    distributed = pytest.importorskip("distributed")
    serial = design.optimize(wavy, {"theta": 3.5}, "x3.2", bounds={"theta": (0, 4)},
                             starts=3, progress=False)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=":0") as client:
        on_dask = design.optimize(wavy, {"theta": 3.5}, "x3.2", bounds={"theta": (0, 4)},
                                  starts=3, client=client, progress=False)
    assert [r["x"]["theta"] for r in on_dask.starts] == \
        pytest.approx([r["x"]["theta"] for r in serial.starts])
    assert on_dask.x["theta"] == pytest.approx(serial.x["theta"], abs=1e-9)


@pytest.mark.parametrize("starts, words", [
    (3, r"starts.*\['theta'\].*bounds"),
    (0, r"starts.*1 or more"),
    ([{"phi": 1.0}], r"starts.*start 0.*\['phi'\] are not parameters"),
    ([{"theta": "1"}], r"starts.*'theta' must be a finite number"),
    ("many", r"starts.*a number of starts or a list"),
])
def test_bad_starts_are_refused_by_name(starts, words):
    with pytest.raises(fm.ArgumentError, match=words):
        design.optimize(wavy, {"theta": 3.5}, "x3.2", starts=starts)


def test_every_start_failing_is_an_error_with_the_starts():
    def broken(theta):
        raise fm.ConvergenceError(f"pretend: no equilibrium at {theta}")

    with pytest.raises(fm.SimulationError, match=r"every one of the 2 starts.*pretend") \
            as caught:
        design.optimize(broken, {"theta": 1.0}, "x3.2", starts=[{"theta": 2.0}],
                        progress=False)
    assert [row["status"] for row in caught.value.partial_result] == ["failed", "failed"]
