"""flexmbd.light's ``opt.customkin`` and ``opt.customdyn``: SPACAR lines added to the
model's file mean what SPACAR Light's own fields mean for the same thing (a mass, a load,
a support), and a line that cannot work is named by its option and index."""

import numpy as np
import pytest

from flexmbd import light
from flexmbd.errors import ArgumentError

ALL = [1, 2, 3, 4, 5, 6]
LEAF = {"emod": 210e9, "smod": 210e9 / 2.6, "dens": 7800, "cshape": "rect",
        "dim": [0.02, 0.0005], "orien": [0, 1, 0], "nbeams": 2, "flex": ALL}
NODES = [[0, 0, 0], [0, 0, 0.05], [0.04, 0, 0], [0.04, 0, 0.05], [0.02, 0, 0.05]]
ELEMENTS = [[1, 2], [3, 4], [2, 5], [5, 4]]   # two leaves, the stage in two halves
STAGE = 13                                     # user node 5's translational node


def _guide(stage: dict | None = None, opt: dict | None = None):
    nprops = {1: {"fix": True}, 3: {"fix": True}, 5: stage or {}}
    return light.run(NODES, ELEMENTS, nprops, [dict(LEAF, elems=[1, 2])],
                     dict({"silent": True, "loadsteps": 3}, **(opt or {})))


def test_a_mass_line_is_the_mass_field():
    """``XM 13 0.2`` in customdyn is nprops(5).mass 0.2: the same frequencies, lower
    than the bare guide's."""
    custom = _guide(opt={"customdyn": [f"XM {STAGE} 0.2"]})
    field = _guide({"mass": 0.2})
    np.testing.assert_allclose(custom.freq[:6, 0], field.freq[:6, 0], rtol=1e-9)
    assert custom.freq[0, 0] < 0.5 * _guide().freq[0, 0]


def test_a_load_line_is_the_force_field():
    """``DELXF 13 1 0 0`` in customdyn is nprops(5).force [1, 0, 0] over the load steps:
    the same stroke at every step (1/8396 m per N, FLEXURES 7)."""
    custom = _guide(opt={"customdyn": f"DELXF {STAGE} 1.0 0.0 0.0"})   # one str is a line
    field = _guide({"force": [1.0, 0, 0]})
    np.testing.assert_allclose(custom.node[5].p, field.node[5].p, rtol=1e-9, atol=1e-15)
    assert custom.node[5].p[0, -1] - NODES[4][0] == pytest.approx(1 / 8396.1190, rel=1e-4)
    np.testing.assert_allclose(custom.stressmax, field.stressmax, rtol=1e-9)


def test_a_support_line_is_the_fix_field_with_its_releases():
    """``FIX 13 1`` in customkin is nprops(5).fix_x: the over-constraint it makes is
    released automatically, as for the field, and the frequencies agree."""
    custom = _guide(opt={"customkin": [f"FIX {STAGE} 1"]})
    field = _guide({"fix_x": True})
    assert len(custom.releases) == len(field.releases)
    np.testing.assert_allclose(custom.freq[:6, 0], field.freq[:6, 0], rtol=1e-9)


def test_a_changed_stiffness_keeps_no_section_and_says_so():
    """ESTIFF of beam 1 with its axial stiffness halved: the stroke barely changes, but the
    section no longer gives that beam's stiffness, so it has no stresses (a note says)."""
    made = _guide().model.element_properties[1].stiffness
    values = [made[name] for name in ("axial", "torsion", "bending_y", "bending_z",
                                      "shear_y", "shear_z")]
    line = "ESTIFF 1 " + " ".join(repr(v) for v in [values[0] / 2, *values[1:]])
    custom = _guide({"force": [1.0, 0, 0]}, {"customdyn": [line], "stressperelement": True})
    assert any("beam 1" in note and "no stresses" in note for note in custom.notes)
    field = _guide({"force": [1.0, 0, 0]})
    assert custom.node[5].p[0, -1] == pytest.approx(field.node[5].p[0, -1], rel=1e-3)


def test_run_control_lines_are_noted_as_unused():
    custom = _guide(opt={"customdyn": ["ITERSTEP 10 5 1e-7"]})
    assert any("run control" in note and "tolerance" in note for note in custom.notes)


@pytest.mark.parametrize("opt, match", [
    ({"customdyn": ["XM 13 0.2", "XM 99 0.5"]},
     r"opt\.customdyn\{2\}: 'XM 99 0\.5': XM: node 99 is not used"),
    ({"customdyn": ["FOO 1 2"]}, r"opt\.customdyn\{1\}: 'FOO 1 2': unknown keyword FOO"),
    ({"customkin": ["XM 13 1"]}, r"opt\.customkin\{1\}: 'XM 13 1': XM belongs in the dynamics"),
    # with the releases given (none automatic), a fixed stage over-constrains the leaves
    ({"customkin": ["FIX 13"], "customdyn": ["XM 13 1"], "rls": {1: [2, 3, 4, 5], 2: [2, 4]}},
     r"opt\.customkin/opt\.customdyn: with these lines \(opt\.customkin\{1\} 'FIX 13'; "
     r"opt\.customdyn\{1\} 'XM 13 1'\) the model cannot be built: the degree-of-freedom "
     r"count does not close"),
    ({"customkin": [3]}, r"opt\.customkin: must be a list of SPACAR input lines"),
    ({"customvis": ["COLOR 1 0 0"]}, r"opt\.customvis: is not supported"),
])
def test_a_custom_line_that_cannot_work_is_named(opt, match):
    with pytest.raises(ArgumentError, match=match):
        _guide(opt=opt)


# --- the numbered input (opt.showinputonly) and the result's picture (opt.spavisual) -------
def _texts(fig) -> list[str]:
    return [t.get_text() for t in fig.axes[0].texts]


def test_showinputonly_draws_the_numbered_input_instead_of_running():
    """Every node and element number is written, one arrow per load (force and moment on
    the stage), and nothing runs: a description that cannot be built is drawn too."""
    from matplotlib.figure import Figure
    nprops = {1: {"fix_pos": True}, 5: {"force": [1.0, 0, 0], "moment": [0, 0.1, 0]}}
    fig = light.run(NODES, ELEMENTS, nprops, [dict(LEAF, elems=[1, 2])],
                    {"showinputonly": True})   # three constraints: it would move freely
    assert isinstance(fig, Figure)
    texts = _texts(fig)
    assert sorted(texts[:4], key=int) == ["1", "2", "3", "4"]           # elements
    assert sorted(texts[4:], key=int) == ["1", "2", "3", "4", "5"]      # nodes
    assert len(fig.axes[0].collections) == 5 + 2                        # nodes, arrows
    with pytest.raises(ArgumentError, match="too few constraints"):
        light.run(NODES, ELEMENTS, nprops, [dict(LEAF, elems=[1, 2])], {"silent": True})


def test_show_input_checks_the_fields_and_saves(tmp_path):
    with pytest.raises(ArgumentError, match=r"unknown field 'forse'"):
        light.show_input(NODES, ELEMENTS, {5: {"forse": [1, 0, 0]}})
    with pytest.raises(ArgumentError, match=r"opt\.showinputonly: must be true or false"):
        light.run(NODES, ELEMENTS, {1: {"fix": True}}, [], {"showinputonly": "yes"})
    light.show_input(NODES, ELEMENTS, filename=tmp_path / "input.png")
    assert (tmp_path / "input.png").stat().st_size > 1000


def test_spavisual_draws_the_last_step():
    res = _guide({"force": [1.0, 0, 0]}, {"spavisual": True})
    assert res.fighandle is not None and res.fighandle.axes
    assert _guide().fighandle is None


# --- a warping flexure's state space ---------------------------------------------------------
def test_a_warping_guide_s_state_space_is_exact_and_quiet():
    """Thin warping leaves (50 x 0.1 mm, 8 beams each): the warping coordinates carry some
    1e-17 of a translation's mass, so the mass matrix's condition is 1e18 in its units
    alone. The state space is formed without LAPACK's ill-conditioning warning (the test
    suite makes warnings errors), its static gain is the compliance computed from the
    stiffness alone, and its poles are the vibration frequencies of the eigen path."""
    leaf = dict(LEAF, dim=[0.05, 0.0001], nbeams=8, warping=True)
    stage = {"elems": [3, 4], "dens": 7800, "cshape": "rect", "dim": [0.02, 0.01],
             "orien": [0, 1, 0]}
    nprops = {1: {"fix": True}, 3: {"fix": True},
              5: {"transfer_in": ["force_x"], "transfer_out": ["displ_x"]}}
    res = light.run(NODES, ELEMENTS, nprops, [dict(leaf, elems=[1, 2]), stage],
                    {"silent": True, "transfer": [True, 0.0]})
    ss = res.statespace
    assert ss.static_gain()[0, 0] == pytest.approx(res.node[5].CMglob[0, 0, 0], rel=1e-7)
    assert ss.truncated(3).static_gain()[0, 0] == pytest.approx(ss.static_gain()[0, 0],
                                                                rel=1e-9)
    poles = np.linalg.eigvals(ss.A)
    lowest = np.sort(np.abs(poles.imag[poles.imag > 0]))[:4] / (2 * np.pi)
    np.testing.assert_allclose(lowest, res.freq[:4, 0], rtol=1e-6)
