"""Leaf springs drawn with their sections: the ribbon's geometry against a straight and a
rigidly turned leaf, its stress colours, and the front door's pictures and movies."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import light, plot
from flexmbd.ribbons import quads, ribbon, ribbon_beams

STEEL = fm.Material.from_poisson(210e9, 0.3, 7800.0)
L, W, T = 0.05, 0.02, 0.0005
LEAF = {"elems": 1, "emod": STEEL.E, "smod": STEEL.G, "dens": STEEL.rho, "cshape": "rect",
        "dim": [W, T], "orien": [0, 1, 0], "nbeams": 4, "flex": [1, 2, 3, 4, 5, 6]}


def _leaf(clamp: dict, tip: dict | None = None, **opt):
    return light.run([[0, 0, 0], [L, 0, 0]], [[1, 2]], {1: clamp, 2: tip or {}}, [LEAF],
                     {"silent": True, **opt})


def test_a_straight_leaf_is_a_flat_band_of_its_width():
    res = _leaf({"fix": True})
    model, x, e = res.model, res.statics.x[0], res.statics.e[0]
    assert ribbon_beams(model) == [1, 2, 3, 4]
    edges = np.concatenate([ribbon(model, k, x, e) for k in (1, 2, 3, 4)], axis=1)
    np.testing.assert_allclose(edges[:, :, 1], np.array([[-W / 2], [W / 2]]) * np.ones(
        edges.shape[1]), atol=1e-15)
    np.testing.assert_allclose(edges[:, :, 2], 0.0, atol=1e-15)
    assert edges[0, 0, 0] == 0.0 and edges[0, -1, 0] == pytest.approx(L)
    assert quads(ribbon(model, 1, x, e)).shape == (20, 4, 3)


def test_a_turned_leaf_turns_its_band():
    """The clamp turned 0.3 rad about the leaf's axis (rot_x), the tip free: the whole
    band lies across (0, cos 0.3, sin 0.3)."""
    res = _leaf({"fix_pos": True, "rot": [0.3, 1, 0, 0]}, loadsteps=2)
    model, x, e = res.model, res.statics.x[-1], res.statics.e[-1]
    for k in (1, 4):
        low, high = ribbon(model, k, x, e)
        across = (high - low) / W
        np.testing.assert_allclose(across, np.tile([0, math.cos(0.3), math.sin(0.3)],
                                                   (len(across), 1)), atol=1e-9)


def test_pictures_colour_the_bands_by_stress(tmp_path):
    """A cantilever leaf with a tip force: the band is coloured on one scale over the
    steps, its root (the largest stress) at the top of the scale; a colour bar; the
    movie and a mode shape with bands."""
    res = _leaf({"fix": True}, {"force": [0, 0, 0.05]}, loadsteps=3)
    history = fm.stress_history(res.statics)
    assert history.ends.shape == (3, 4, 2)
    assert history.ends[-1, 0, 0] == pytest.approx(res.stressmax[-1])   # the root
    fig = plot.plot_sections(res.statics, stresses=history, filename=tmp_path / "leaf.png")
    assert len(fig.axes) == 2 and (tmp_path / "leaf.png").stat().st_size > 10_000
    ax = fig.axes[0]
    sections = plot.Sections(ax, res.model, history)
    sections.draw(res.statics.x[-1], res.statics.e[-1], 2)
    colours = sections.collection.get_facecolor()
    assert len(colours) == 4 * 20
    top = sections.cmap(sections.norm(history.ends[-1, 0, 0] / 1e6 * (1 - 1 / 40)
                                      + history.ends[-1, 0, 1] / 1e6 / 40))
    np.testing.assert_allclose(colours[0], top, atol=1e-12)
    res.animate(tmp_path / "leaf.gif")
    assert (tmp_path / "leaf.gif").stat().st_size > 10_000
    lin = res.statics.linearization()
    modes = fm.vibration_modes(lin, 2)
    plot.plot_shapes(res.model, lin.x, modes.motion, ["1", "2"], sections=True,
                     filename=tmp_path / "modes.png")
    assert (tmp_path / "modes.png").stat().st_size > 10_000


def test_the_front_door_draws_in_the_sets_colours():
    res = light.run([[0, 0, 0], [L, 0, 0], [L, W, 0]], [[1, 2], [2, 3]], {1: {"fix": True}},
                    [dict(LEAF, color=[255, 0, 0], opacity=0.5),
                     {"elems": 2, "dens": 1000, "cshape": "rect", "dim": [0.01, 0.01],
                      "orien": [0, 0, 1], "hide": True}], {"silent": True})
    assert res.styles[1] == {"hide": False, "alpha": 0.5, "color": (1.0, 0.0, 0.0)}
    fig = res.plot(1, stress=False)
    sections = plot.Sections(fig.axes[0], res.model, styles=res.styles)
    assert 5 not in sections.beams and sections.beams == [1, 2, 3, 4]
    with pytest.raises(IndexError, match="numbered 1 to 1"):
        res.plot(2)
