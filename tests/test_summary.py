"""What a user sees by typing a variable's name: every model and result prints a few
lines with its sizes and how to see more, under 2,000 characters whatever its size (a
201-point run used to print 64 kB, the whole model included)."""

from pathlib import Path

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import light

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
LONGEST = 2000


@pytest.fixture(scope="module")
def crank():
    return fm.read_dat(EXAMPLES / "slider_crank_flex.dat")


def _results(crank, tmp_path):
    model = crank.model
    run = fm.simulate(model, np.linspace(0.0, 0.08, 201))
    statics = fm.static_equilibrium(model, load_increment={"x5.1": -1.0}, steps=20)
    lin = statics.linearization()
    path = tmp_path / "run.sbd"
    fm.write_sbd(path, run)
    leaf = {"emod": 210e9, "smod": 80e9, "dens": 7800, "cshape": "rect", "dim": [0.02, 5e-4],
            "orien": [0, 1, 0], "nbeams": 4, "flex": [1, 2, 3, 4, 5, 6], "elems": [1, 2]}
    guide = light.run([[0, 0, 0], [0, 0, 0.05], [0.04, 0, 0], [0.04, 0, 0.05],
                       [0.02, 0, 0.05]], [[1, 2], [3, 4], [2, 5], [5, 4]],
                      {1: {"fix": True}, 3: {"fix": True}, 5: {"force": [1.0, 0, 0]}},
                      [leaf], {"silent": True, "loadsteps": 3})
    return {
        "model": model, "simulation": run, "columns": run.columns(), "statics": statics,
        "kinematics": fm.kinematic_analysis(model, np.linspace(0.0, 0.05, 201)),
        "linearization": lin, "modes": fm.vibration_modes(lin),
        "buckling": fm.buckling(guide.statics.linearization()),
        "modes along": fm.modes_along(run, 2),
        "state space": fm.state_space(fm.linearize(model), inputs=["x5.1"],
                                      outputs=["x5.1"]),
        "load steps": fm.load_step_table(statics, modes=2, compliance=[(5, None)]),
        "result file": fm.read_sbd(path), "light": guide, "light step": guide.step[1],
        "light node": guide.node[2],
    }


def test_every_result_prints_in_a_few_lines(crank, tmp_path):
    for name, value in _results(crank, tmp_path).items():
        text = repr(value)
        assert len(text) < LONGEST, (name, len(text))
        assert str(value) == text or len(str(value)) < LONGEST, name


def test_a_run_says_its_span_status_columns_and_how_to_see_more(crank):
    run = fm.simulate(crank.model, np.linspace(0.0, 0.08, 201))
    text = repr(run)
    assert "201 points, t = 0 to 0.08 s; completed" in text
    assert "x (9), xd (9), xdd (9), e (5)" in text and "res.columns()" in text
    assert "slider_crank_flex" in repr(crank.model) and "model.nodes" in repr(crank.model)
