"""Models and results travel: they pickle (to a Dask worker, to a file) and come back
whole, and a pickled model runs exactly as the model it was made from."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from flexmbd.examples import EXAMPLES_DIR, cross_spring_pivot, parallel_guide
from flexmbd.examples import slider_crank_flex as flex

import flexmbd as fm
from flexmbd import light
from flexmbd.engine import workspace_of


def _again(value):
    return pickle.loads(pickle.dumps(value))


def _same_arrays(a, b, names) -> None:
    for name in names:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


@pytest.mark.parametrize("make", [
    lambda: flex.build_model(3, eps1flex=True),
    lambda: parallel_guide.build_model(),
    lambda: cross_spring_pivot.build_model(),
    lambda: fm.read_dat(EXAMPLES_DIR / "slider_crank_flex.dat")[0],
], ids=["flexible slider-crank", "parallel guide", "cross-spring pivot", "from a .dat file"])
def test_a_pickled_model_is_the_model(make):
    model = make()
    workspace_of(model).assembly.deformations(np.asarray(model.x0))   # used before
    copy = _again(model)
    assert copy.coordinate_labels == model.coordinate_labels
    assert dict(copy.element_properties) == dict(model.element_properties)
    assert np.array_equal(copy.x0, model.x0) and not copy.x0.flags.writeable
    x = np.asarray(model.x0) + 1e-3
    assert np.array_equal(fm.jacobian(copy, x), fm.jacobian(model, x))


def test_a_pickled_model_simulates_bit_identically():
    model = flex.build_model(4, eps1flex=True)
    times = flex.output_times(0.05)
    options = {"method": "GeneralizedAlpha", "step": flex.turn_time(1.0) / 800,
               "with_reactions": True}
    direct, copied = fm.simulate(model, times, **options), fm.simulate(
        _again(model), times, **options)
    _same_arrays(direct, copied, ("t", "x", "xd", "xdd", "e", "sigma", "reactions"))


def test_results_pickle_and_keep_their_numbers():
    model = flex.build_model(2)
    run = fm.simulate(model, np.linspace(0.0, 0.004, 5), method="GeneralizedAlpha",
                      step=1e-4)
    kinematics = fm.kinematic_analysis(model, np.linspace(0.0, 0.001, 3))
    guide = parallel_guide.build_model()
    statics = fm.static_equilibrium(guide, load_increment={"x5.1": 1.0}, steps=2)
    lin = statics.linearization(1)
    for value, names in ((run, ("t", "x", "xd", "e", "sigma")), (kinematics, ("t", "x", "e")),
                         (statics, ("load", "x", "e", "sigma"))):
        _same_arrays(value, _again(value), names)
    for value in (lin, fm.vibration_modes(lin, 3), fm.buckling(lin, 1),
                  fm.state_space(lin, ["x5.1"], ["x5.1"]),
                  fm.load_step_table(statics, modes=2)):
        copy = _again(value)
        assert type(copy) is type(value)
    assert np.array_equal(_again(fm.vibration_modes(lin, 3)).frequencies,
                          fm.vibration_modes(lin, 3).frequencies)


def test_a_spacar_light_result_pickles():
    nodes = [[0, 0, 0], [0.05, 0, 0]]
    leaf = {"elems": [1], "emod": 210e9, "smod": 81e9, "dens": 7800, "cshape": "rect",
            "dim": [0.02, 0.5e-3], "orien": [0, 0, 1], "nbeams": 2, "flex": [1, 2, 3, 4, 5, 6]}
    res = light.run(nodes, [[1, 2]], {1: {"fix": True}, 2: {"force": [0, 0, -1.0]}}, [leaf],
                    {"silent": True})
    copy = _again(res)
    assert np.array_equal(copy.node[2].p, res.node[2].p)
    assert np.array_equal(copy.freq, res.freq)
