"""More first-week mistakes at flexmbd.light's door, each named by its field: an
orientation along the element, impossible material and section numbers, a displacement
in mm, a model without degrees of freedom, a note repeated for every load step."""

import warnings

import numpy as np
import pytest

from flexmbd import light
from flexmbd.errors import ArgumentError, ModelWarning

ALL = [1, 2, 3, 4, 5, 6]
LEAF = {"emod": 210e9, "smod": 210e9 / 2.6, "dens": 7800, "cshape": "rect",
        "dim": [0.02, 0.0005], "orien": [0, 1, 0], "nbeams": 2, "flex": ALL}
NODES = [[0, 0, 0], [0, 0, 0.05], [0.04, 0, 0], [0.04, 0, 0.05], [0.02, 0, 0.05]]
ELEMENTS = [[1, 2], [3, 4], [2, 5], [5, 4]]


def _guide(stage=None, leaf=None, opt=None):
    nprops = {1: {"fix": True}, 3: {"fix": True}, 5: stage or {"force": [1.0, 0, 0]}}
    return light.run(NODES, ELEMENTS, nprops, [dict(LEAF, elems=[1, 2], **(leaf or {}))],
                     dict({"silent": True, "loadsteps": 3}, **(opt or {})))


@pytest.mark.parametrize("leaf, match", [
    ({"orien": [0, 0, 1]}, r"eprops\(1\)\.orien: orien lies along element 1 \(0, 0, 1\)"),
    ({"emod": -1.0}, r"eprops\(1\)\.emod: must be a positive modulus \[Pa\], got -1"),
    ({"smod": 0.0}, r"eprops\(1\)\.smod: must be a positive modulus"),
    ({"dens": -7800}, r"eprops\(1\)\.dens: must be a density >= 0"),
    ({"dim": [0.02, -0.0005]}, r"eprops\(1\)\.dim: must be positive lengths \[m\] "
                               r"\(\[width thickness\]\)"),
])
def test_impossible_set_fields_are_named(leaf, match):
    with pytest.raises(ArgumentError, match=match):
        _guide(leaf=leaf)


@pytest.mark.parametrize("color", ["purpleish", [0, -1, 300]])
def test_a_colour_no_one_knows_is_drawn_grey_and_noted(color):
    res = _guide(leaf={"color": color})
    assert "color" not in res.styles[1]
    assert any(f"eprops(1).color {color!r} is drawn grey" in note for note in res.notes)


def test_an_unset_element_along_the_default_orientation_takes_spacar_s_choice():
    """A rigid, massless element along y (no set) needs no orientation: SPACAR's choice (z)
    replaces [0 1 0], noted; a rectangular set's orien along it is refused."""
    nodes, elements = [[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0]], [[1, 2], [2, 3]]
    leaf = dict(LEAF, elems=[2], orien=[0, 0, 1])
    res = light.run(nodes, elements, {1: {"fix": True}, 3: {"fix": True}}, [leaf],
                    {"silent": True})
    assert any("SPACAR's choice [0 0 1]" in note for note in res.notes)
    with pytest.raises(ArgumentError, match=r"eprops\(1\)\.orien: orien lies along "
                                            r"element 1 \(0, 1, 0\)"):
        light.run(nodes, elements, {1: {"fix": True}, 3: {"fix": True}},
                  [dict(LEAF, elems=[1, 2])], {"silent": True})


def test_moduli_that_are_no_isotropic_solid_are_warned_about():
    """smod = emod gives a Poisson's ratio of -0.5; a ModelWarning names the set and the
    shear modulus meant."""
    with pytest.warns(ModelWarning, match=r"eprops\(1\): emod / \(2 smod\) - 1 = -0\.5 is no "
                                          r"Poisson's ratio"):
        _guide(leaf={"smod": 210e9})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _guide()                                   # steel, nu = 0.3: nothing said


def test_a_displacement_in_mm_is_warned_about():
    with pytest.warns(ModelWarning, match=r"nprops\(5\)\.displ_x = 1 m is larger than the "
                                          r"whole model \(0\.05 m across\)"):
        light.build(NODES, ELEMENTS, {1: {"fix": True}, 3: {"fix": True}, 5: {"displ_x": 1.0}},
                    [dict(LEAF, elems=[1, 2])], {"silent": True})


def test_a_note_of_every_step_is_said_once():
    """Massless leaves (dens 0): no frequencies at any of the 3 steps, one note naming
    them all."""
    res = _guide(leaf={"dens": 0.0})
    said = [note for note in res.notes if note.startswith("eigenfrequencies")]
    assert len(said) == 1 and said[0].startswith("eigenfrequencies at steps 1 to 3: ")
    assert np.all(np.isnan(res.freq))


def test_a_model_without_degrees_of_freedom_runs_and_says_so():
    """A rigid arm fixed at one end: its tip stays put under a load, no frequencies."""
    res = light.run([[0, 0, 0], [0.1, 0, 0]], [[1, 2]], {1: {"fix": True},
                                                        2: {"force": [0, 0, 1.0]}},
                    [], {"silent": True, "calcbuck": True})
    assert res.ndof == 0 and res.freq.shape == (0, len(res.load))
    np.testing.assert_allclose(res.node[2].p[:, -1], [0.1, 0, 0], atol=1e-15)
    assert any("no degrees of freedom" in note for note in res.notes)


def test_a_flag_given_as_an_array_is_named():
    with pytest.raises(ArgumentError, match=r"nprops\(1\)\.fix: must be true or false, got "
                                            r"array\(\[1, 0\]\)"):
        light.run(NODES, ELEMENTS, {1: {"fix": np.array([1, 0])}, 3: {"fix": True}},
                  [dict(LEAF, elems=[1, 2])], {"silent": True})


def test_releases_that_leave_over_constraints_name_rls():
    """Releasing the bending of element 1 only leaves four over-constraints of the guide:
    refused under opt.rls, with the way out (automatic releases)."""
    with pytest.raises(ArgumentError, match=r"opt\.rls: with the releases given the model "
                                            r"does not close .* leave rls out"):
        _guide(opt={"rls": {1: [1, 2]}})


def test_a_filename_may_be_a_path(tmp_path):
    _guide(opt={"filename": tmp_path / "guide"})
    assert (tmp_path / "guide.dat").exists()
