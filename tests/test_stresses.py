"""Stresses of a leaf spring against beam theory (FLEXURES 4's checks): a cantilever of
four beams, 20 x 0.5 mm, 50 mm long, under a tip moment, a tip force and a tip torque."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.errors import ArgumentError

W, T, L = 0.02, 0.0005, 0.05


def _leaf() -> fm.Model:
    b = fm.ModelBuilder("leaf")
    b.add_node(1, 0.0, 0.0, 0.0).add_node(3, L, 0.0, 0.0)
    b.add_spatial_beams(1, 1, 2, 3, 4, 4, orientation=(0, 1, 0), new_nodes=10,
                        section=fm.Rectangle(W, T),
                        material=fm.Material.from_poisson(210e9, 0.3, 7800.0))
    b.fix(1).fix(2)
    return b.build()


def _loaded(loads):
    model = _leaf()
    statics = fm.static_equilibrium(model, loads=loads, tolerance=1e-14)
    return model, statics, fm.beam_stresses(model, statics.x[-1], statics.sigma[-1])


def test_a_tip_moment_bends_every_beam_alike():
    """M = 0.01 N m about the width: every beam carries sigma3 = sigma4 = M / l0 and
    6 M / (w t^2) = 12 MPa at its outer fibres."""
    model, statics, stresses = _loaded({"x4.3": 0.01})   # My on the tip's rotational node
    for k in range(1, 5):
        sig = statics.sigma[-1][[model.deformation_index(f"e{k}.{j}") for j in (3, 4)]]
        assert np.abs(sig) == pytest.approx([0.01 / (L / 4)] * 2, rel=1e-5)
        assert stresses[k].von_mises == pytest.approx(6 * 0.01 / (W * T**2), rel=1e-6)
        assert abs(stresses[k].resultants[0, 4]) == pytest.approx(0.01, rel=1e-6)


def test_a_tip_force_gives_the_root_moment():
    """F = 0.05 N across the leaf: the root's My = F L and 6 F L / (w t^2) = 3 MPa."""
    model, _, stresses = _loaded({"x3.3": 0.05})
    root = stresses[1]
    assert abs(root.resultants[0, 4]) == pytest.approx(0.05 * L, rel=1e-5)
    assert abs(root.resultants[0, 2]) == pytest.approx(0.05, rel=1e-5)   # the shear Qz
    assert root.von_mises == pytest.approx(6 * 0.05 * L / (W * T**2), rel=1e-5)
    assert root.where.startswith("p")
    history = fm.stress_history(fm.static_equilibrium(model, load_increment={"x3.3": 0.05},
                                                      steps=2))
    assert history.maximum == pytest.approx([0.0, 1.5e6, 3.0e6], rel=1e-5, abs=1e-3)


def test_a_tip_torque_gives_st_venant_s_shear():
    """T = 0.002 N m: tau = T / (alpha w t^2) with alpha = 0.32808 at w/t = 40 (Timoshenko
    and Goodier), von Mises sqrt(3) tau."""
    _, _, stresses = _loaded({"x4.2": 0.002})
    tau = 0.002 / (0.32808 * W * T**2)
    for beam in stresses.values():
        assert beam.resultants[:, 3] == pytest.approx([0.002, 0.002], rel=1e-6)
        assert beam.von_mises == pytest.approx(math.sqrt(3) * tau, rel=1e-4)
        assert "long side" in beam.where


def test_stresses_need_a_section():
    model, _ = fm.read_dat(__import__("pathlib").Path(__file__).parent.parent
                                  / "examples" / "slider_crank_flex.dat")
    with pytest.raises(ArgumentError, match="no spatial beam has a cross-section"):
        fm.beam_stresses(model, model.x0, np.zeros(model.n_deformations))
