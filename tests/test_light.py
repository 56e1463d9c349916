"""The SPACAR Light front door (flexmbd.light): FLEXURES 7's parallel guide (stiffness,
parasitic motion, buckling with its sign), a leaf's root stress, the body-frame compliance
of a turned leaf, the state-space model, SPACAR Light's numbering and its refusals; and,
where SPACAR's own output is beside the checkout, its numbers for a SPACAR Light model."""

import math
from pathlib import Path

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import light
from flexmbd.errors import ArgumentError

#: SPACAR's own numbers for a public model, reduced (data/spacar/SOURCE.md says whence)
SPACAR = Path(__file__).parent / "data" / "spacar"
ALL = [1, 2, 3, 4, 5, 6]
#: FLEXURES 7's leaves: steel (nu 0.3), 20 x 0.5 mm, 50 mm long, 40 mm apart
LEAF = {"emod": 210e9, "smod": 210e9 / 2.6, "dens": 7800, "cshape": "rect",
        "dim": [0.02, 0.0005], "orien": [0, 1, 0], "nbeams": 4, "flex": ALL}
GUIDE_NODES = [[0, 0, 0], [0, 0, 0.05], [0.04, 0, 0], [0.04, 0, 0.05], [0.02, 0, 0.05]]
GUIDE_ELEMENTS = [[1, 2], [3, 4], [2, 5], [5, 4]]   # two leaves, the stage in two halves


def _guide(stage: dict | None = None, opt: dict | None = None):
    nprops = {1: {"fix": True}, 3: {"fix": True}, 5: stage or {}}
    return light.run(GUIDE_NODES, GUIDE_ELEMENTS, nprops, [dict(LEAF, elems=[1, 2])],
                     dict({"silent": True}, **(opt or {})))


def test_the_parallel_guide_is_released_automatically_and_has_its_stiffness():
    """No rls: six over-constraints released on the leaves' last beams; the stage's
    stiffness along the stroke is FLEXURES 7's 8396.1190 N/m (24EI/L^3 = 8400 with shear
    and the stage's tilt)."""
    res = _guide()
    assert len(res.releases) == 6
    last_beams = {res.element[1].spa_nrs[-1], res.element[2].spa_nrs[-1]}
    assert {beam for beam, _ in res.releases} <= last_beams
    assert 1 / res.node[5].CMglob[0, 0, 0] == pytest.approx(8396.1190, rel=1e-7)
    assert res.node[5].CMglob.shape == (6, 6, 1) and res.freq.shape == (res.ndof, 1)


def test_numbering_follows_spacar_light():
    """User node j is node 3j-2 with rotational node 3j-1; the nodes between sub-beams are
    numbered on from 3n+1, three apart; the beams on from 1 over the elements."""
    res = _guide()
    assert res.node[2].spa_nrs == (4, 5)
    assert res.element[1].spa_nrs == (1, 2, 3, 4) and res.element[3].spa_nrs == (9,)
    assert {16, 17, 19, 20, 22, 23} <= set(res.model.nodes)    # element 1's inner nodes
    assert res.model.nodes[16].kind == "spatial translational"
    np.testing.assert_allclose(res.model.x0[list(res.model.nodes[16].coordinates)],
                               [0, 0, 0.0125])
    np.testing.assert_allclose(res.element[1].L0, [0.0125] * 4)


def test_a_stroke_gives_the_parasitic_motion():
    """The stage driven 1 mm along the stroke (displ_x, 5 load steps) sinks by 0.6 u^2/L
    (FLEXURES 7: -11.9978 um at n = 4), its drive holding it at every step."""
    res = _guide({"displ_x": 1e-3}, {"loadsteps": 5})
    assert res.node[5].p.shape == (3, 5)
    np.testing.assert_allclose(res.node[5].p[0], 0.02 + np.linspace(0, 1e-3, 5), atol=1e-15)
    sink = res.node[5].p[2, -1] - 0.05
    assert sink == pytest.approx(-0.6 * 1e-3**2 / 0.05, rel=1e-3)
    assert sink == pytest.approx(-11.9978e-6, rel=1e-4)
    assert res.step[1].node[5].Freac[0] == pytest.approx(0.0, abs=1e-9)
    stiffness = 8396.1190   # the drive's force is about the stroke times the stiffness
    assert res.node[5].Freac[0, 1] == pytest.approx(stiffness * 0.25e-3, rel=2e-3)


def test_buckling_keeps_its_sign():
    """A vertical load on the stage's middle: FLEXURES 7's 345.50 N (2 pi^2 EI/L^2 =
    345.436) as the load factor of 1 N pressing down, the same negative for 1 N pulling."""
    down = _guide({"force": [0, 0, -1.0]}, {"calcbuck": True, "loadsteps": 2})
    assert down.buck[0, -1] == pytest.approx(345.50, rel=1e-4)
    assert np.isnan(down.buck[0, 0])       # step 1 carries no load
    up = _guide({"force": [0, 0, 1.0]}, {"calcbuck": True, "loadsteps": 2})
    assert up.buck[0, -1] == pytest.approx(-345.50, rel=1e-3)
    assert down.step[2].buck[0] == down.buck[0, 1]


def test_buckling_under_a_prescribed_stroke_says_what_its_factors_multiply():
    """With a displacement input the factors multiply the drive's loads too (SPACAR Light
    warns so); they exist, and the note no longer says there are none."""
    res = _guide({"displ_x": 1e-3}, {"calcbuck": True, "loadsteps": 2})
    assert not np.all(np.isnan(res.buck[:, -1]))
    assert any("a displacement is prescribed, so the buckling load factors also multiply"
               in note for note in res.notes)
    assert not any("no buckling load factors" in note for note in res.notes)


def test_a_leaf_s_root_stress_and_its_largest_stress_per_element():
    """A cantilever leaf (100 x 20 x 1 mm) with 0.1 N across its thickness at the tip:
    6 F L / (w t^2) = 3 MPa at the root's surface (FLEXURES 4), zero before the load."""
    F, L, w, t = 0.1, 0.1, 0.02, 0.001
    leaf = dict(LEAF, elems=1, dim=[w, t], nbeams=4)
    res = light.run([[0, 0, 0], [L, 0, 0]], [[1, 2]], {1: {"fix": True},
                    2: {"force": [0, 0, F]}}, [leaf],
                    {"loadsteps": 2, "stressperelement": True, "silent": True})
    assert res.stressmax[0] == pytest.approx(0.0, abs=1e-3)
    assert res.stressmax[1] == pytest.approx(6 * F * L / (w * t**2), rel=1e-4)
    np.testing.assert_array_equal(res.element[1].stressmax, res.stressmax)
    assert res.step[2].stressmax == res.stressmax[1]


def test_the_body_frame_compliance_is_the_global_one_turned():
    """A leaf whose clamp is turned 0.4 rad about z (rot): in the body frame its tip
    compliance is that of the unturned leaf; in global axes it is that turned."""
    leaf = dict(LEAF, elems=1, nbeams=3)
    res = light.run([[0, 0, 0], [0.05, 0, 0]], [[1, 2]],
                    {1: {"fix_pos": True, "rot": [0.4, 0, 0, 1]}}, [leaf],
                    {"loadsteps": 3, "silent": True})
    C0, C_loc, C_glob = (res.node[2].CMglob[:, :, 0], res.node[2].CMloc[:, :, -1],
                         res.node[2].CMglob[:, :, -1])
    np.testing.assert_allclose(C_loc, C0, rtol=1e-8, atol=1e-8 * np.abs(C0).max())
    c, s = math.cos(0.4), math.sin(0.4)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    T = np.kron(np.eye(2), R)
    np.testing.assert_allclose(C_glob, T @ C0 @ T.T, rtol=1e-8, atol=1e-8 * np.abs(C0).max())
    assert res.node[2].r_axang[:, -1] == pytest.approx([0.4, 0, 0, 1], abs=1e-12)
    assert res.node[2].r_eulzyx[:, -1] == pytest.approx([0.4, 0, 0], abs=1e-12)


def test_the_state_space_model_keeps_spacar_light_s_order():
    """transfer_in and transfer_out (velocity listed first): the outputs in that order;
    the static gain of the displacement is the stage's compliance."""
    res = _guide({"transfer_in": ["force_x"], "transfer_out": ["veloc_x", "displ_x"]},
                 {"transfer": [True, 0.01]})
    ss = res.statespace
    assert ss.inputs == ("x13.1",) and ss.outputs == ("xd13.1", "x13.1")
    gain = -ss.C @ np.linalg.solve(ss.A, ss.B) + ss.D
    assert gain[1, 0] == pytest.approx(res.node[5].CMglob[0, 0, 0], rel=1e-8)
    assert gain[0, 0] == pytest.approx(0.0, abs=1e-12)


def test_mode_3_frees_the_prescribed_directions():
    """opt.mode = 3 makes displ_x a free direction: the frequencies are the free guide's."""
    free = _guide()
    driven = _guide({"displ_x": 1e-3}, {"mode": 3})
    np.testing.assert_allclose(driven.freq[:, 0], free.freq[:, 0], rtol=1e-9)


@pytest.mark.parametrize("call, match", [
    (lambda: _guide({"forse": [1, 0, 0]}), r"unknown field 'forse'; did you mean 'force'"),
    (lambda: _guide(opt={"loadstep": 3}), r"did you mean 'loadsteps'"),
    (lambda: _guide(opt={"customvis": ["X 1 0 0 0"]}), r"customvis: is not supported"),
    (lambda: _guide({"fix": True, "fix_pos": True}), r"fix is combined"),
    (lambda: _guide({"force": [1, 0, 0], "displ_x": 1e-3}), r"fix_x, force\(1\) and displ"),
    (lambda: _guide({"rot_x": 0.1, "rot_y": 0.1}), r"more than one input rotation"),
    (lambda: _guide(opt={"mode": 4}), r"must be 10 \(static\) or 3"),
    (lambda: _guide(opt={"rls": [{"def": [7]}]}), r"deformation modes are 1 to 6"),
    (lambda: light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix_pos": True}}, []),
     r"too few constraints \(3 < 6"),
    (lambda: light.run(GUIDE_NODES, [[1, 9]], {1: {"fix": True}}), r"node numbers 1 to 5"),
    (lambda: light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix": True}},
                       [{"elems": 1, "flex": ALL}]), r"flexible elements \(flex\) need cshape"),
    (lambda: light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix": True}},
                       [{"elems": 1}, {"elems": [1, 2]}]), r"element 1 is already in eprops"),
    (lambda: _guide({"fix_warp": True, "fix": True}), r"fix is combined"),
    # a student's and a designer's first-week mistakes, each named where it is
    (lambda: light.run([*GUIDE_NODES, [0.5, 0.5, 0.5]], GUIDE_ELEMENTS,
                       {1: {"fix": True}, 3: {"fix": True}, 6: {"force": [0, 0, 1]}},
                       [dict(LEAF, elems=[1, 2])], {"silent": True}),
     r"nprops\(6\): gives force, but node 6 is not attached to an element"),
    (lambda: light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix": True}, 3: {"fix": True}},
                       [dict(LEAF, elems=[1, 2]), {"elems": [3, 4]}],
                       {"silent": True, "rls": {3: [2, 3]}}),
     r"opt\.rls\(3\): element 3 belongs to a set without flex \(eprops\(2\)\): its "
     r"deformations are rigid"),
    (lambda: light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix": True}, 3: {"fix": True}},
                       [{k: v for k, v in LEAF.items()}], {"silent": True}),
     r"eprops\(1\)\.elems: is missing: the set gives emod, .* but names no element"),
    (lambda: light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix": True}, 3: {"fix": True}},
                       [{k: v for k, v in LEAF.items() if k != "flex"} | {"elems": [1, 2]}],
                       {"silent": True}),
     r"eprops: no element set has flex, so every element is rigid"),
])
def test_what_spacar_light_refuses_is_refused_by_name(call, match):
    with pytest.raises(ArgumentError, match=match):
        call()


def test_numbers_are_one_based():
    res = _guide()
    with pytest.raises(IndexError, match="numbered 1 to 5"):
        res.node[0]
    assert res.step[1].node[5].p.shape == (3,)
    assert res.step[1].node[5].x is res.step[1].node[5].p   # the names before 2019
    assert res.node[5].rx_quat is res.node[5].r_quat
    assert "5 nodes" in repr(res) and len(repr(res)) < 300


def test_notes_are_printed_unless_silent(capsys):
    light.run(GUIDE_NODES, GUIDE_ELEMENTS, [{"fix": True}, None, {"fix": True}],
              [dict(LEAF, elems=[1, 2])])
    printed = capsys.readouterr().out
    assert "over-constraints released" in printed and "elements 3, 4 have no properties" \
        in printed


def test_spacar_s_own_numbers_for_a_spacar_light_model():
    """The sample cross hinge as SPACAR Light described it (its .dat header and lines):
    SPACAR 2018's positions, reactions and frequencies at all ten steps."""
    import scipy.linalg

    nodes = [[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.1, 0, 0]]
    leaf = {"elems": [1, 3], "emod": 210e9, "smod": 70e9, "dens": 7800, "cshape": "rect",
            "dim": [50e-3, 0.2e-3], "orien": [0, 0, 1], "flex": ALL}
    body = {"elems": 2, "dens": 3000, "cshape": "rect", "dim": [50e-3, 10e-3],
            "orien": [0, 0, 1]}
    nprops = {1: {"fix": True}, 4: {"fix": True},   # the file's DELINPX is sin(angle/2)
              3: {"rot_z": 2 * math.asin(0.247404), "mass": 0.1}}
    res = light.run(nodes, [[1, 3], [2, 3], [2, 4]], nprops, [leaf, body],
                    {"gravity": [0, 0, -9.81], "rls": [{"def": ALL}, None, {"def": [4]}],
                     "silent": True})
    with np.load(SPACAR / "crosshinge.npz") as stored:
        sbd = {key.split(".")[2]: value for key, value in stored.items()
               if key.startswith("crosshinge.sbd.")}
        sbm = {key.split(".")[2]: value for key, value in stored.items()
               if key.startswith("crosshinge.sbm.")}
    places = sbd["LNP"].astype(int) - 1
    for j in (2, 3):
        np.testing.assert_allclose(res.node[j].p.T, sbd["X"][:, places[3 * j - 3, :3], 0],
                                   atol=1e-12)
    reactions = sbd["FXT"][:, :, 0]
    np.testing.assert_allclose(res.node[1].Freac.T, reactions[:, places[0, :3]], atol=1e-9)
    np.testing.assert_allclose(res.node[1].Mreac.T, reactions[:, places[1, 1:4]] / 2,
                               atol=1e-9)
    for step in range(10):
        K = sbm["K0"][step] + sbm["N0"][step] + sbm["G0"][step]
        omega2 = np.sort(scipy.linalg.eigvals(K, sbm["M0"][step]).real)
        np.testing.assert_allclose(res.freq[:, step], np.sqrt(omega2) / (2 * np.pi),
                                   rtol=1e-10)


def test_each_step_keeps_its_mode_shapes():
    """res.step[i].freqmodes: mass-normalized shapes over the degrees of freedom, one per
    frequency (SPACAR Light's field), and the buckled shapes with calcbuck."""
    res = _guide({"force": [0, 0, -1.0]}, {"calcbuck": True, "loadsteps": 2})
    step = res.step[2]
    lin = res.statics.linearization(1)
    M = lin.block("M0")
    assert step.freqmodes.shape == (res.ndof, res.ndof)
    np.testing.assert_allclose(step.freqmodes.T @ M @ step.freqmodes, np.eye(res.ndof),
                               atol=1e-8)
    assert step.buckmodes.shape[0] == res.ndof and res.step[1].buckmodes is None


def test_an_older_script_with_its_releases_fifth_runs(tmp_path):
    """SPACAR Light's wire-flexure example (a 1 mm wire, 40 mm, clamped, 1 N along it)
    in its pre-2019 call spacarlight(nodes, elements, nprops, eprops, rls, opt) with
    rls = []: the buckling factor is the clamped-free column's pi^2 EI/(4 L^2) with shear,
    to 1e-3."""
    nodes = [[0, 0, 0], [6e-3, 0, 0], [34e-3, 0, 0], [40e-3, 0, 0]]
    wire = {"emod": 210e9, "smod": 79e9, "dens": 7800, "cshape": "circ", "dim": [1e-3],
            "orien": [0, 0, 1], "flex": ALL, "nbeams": 2}
    res = light.run(nodes, [[1, 2], [2, 3], [3, 4]],
                    {1: {"fix": True}, 4: {"force_initial": [-1, 1e-6, 0]}},
                    [dict(wire, elems=[1, 3]), dict(wire, elems=[2])], [],
                    {"calcbuck": True, "filename": str(tmp_path / "wireflexure"),
                     "silent": True})
    E, G, d, L = 210e9, 79e9, 1e-3, 0.04
    euler = math.pi**2 * E * math.pi * d**4 / 64 / (4 * L**2)
    kga = 6 * (1 + E / (2 * G) - 1) / (7 + 6 * (E / (2 * G) - 1)) * G * math.pi * d**2 / 4
    assert res.buck[0, 0] == pytest.approx(euler / (1 + euler / kga), rel=1e-3)
    with pytest.raises(ArgumentError, match="given twice"):
        light.run(nodes, [[1, 2], [2, 3], [3, 4]], {1: {"fix": True}}, [],
                  [{"def": [1]}], {"rls": [{"def": [1]}]})


def test_spacar_light_s_parallel_guide_transfer_example(capsys, tmp_path):
    """SPACAR Light's own transfer-function example (a guide of 0.2 mm leaves with a
    sensor arm, cw = true, 1 % damping): the static gain is 1 / (24 EI / L^3) to 1e-4, and
    the deprecated cw is noted, not used (as SPACAR Light does now)."""
    nodes = [[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.1, 0, 0], [0.1, 0.2, 0]]
    nprops = {1: {"fix": True}, 4: {"fix": True},
              3: {"transfer_in": ["force_x"], "transfer_out": ["displ_x"]}}
    leaves = {"elems": [1, 3], "emod": 210e9, "smod": 70e9, "dens": 7800, "cshape": "rect",
              "dim": [50e-3, 0.2e-3], "orien": [0, 0, 1], "nbeams": 2, "flex": ALL,
              "color": "grey", "opacity": 0.7, "cw": True}
    rigid = {"elems": [2, 4], "dens": 7800, "cshape": "rect", "dim": [50e-3, 25e-3],
             "orien": [0, 0, 1], "nbeams": 1, "color": "darkblue"}
    res = light.run(nodes, [[1, 2], [2, 3], [3, 4], [3, 5]], nprops, [leaves, rigid],
                    {"transfer": [True, 0.01], "filename": str(tmp_path / "test1")})
    ss = res.statespace
    gain = (ss.D - ss.C @ np.linalg.solve(ss.A, ss.B))[0, 0]
    EI = 210e9 * 50e-3 * 0.2e-3**3 / 12
    assert 1 / gain == pytest.approx(24 * EI / 0.1**3, rel=1e-4)
    assert "cw is ignored, as SPACAR Light 1.38 ignores it: before 2019 cw = true multiplied" \
        in capsys.readouterr().out


def test_one_load_step_applies_no_increment_and_says_so():
    """SPACAR Light's loadsteps: step 1 is the state before the increments, so one step
    applies none of them; the note says so and what to give."""
    res = _guide({"force": [0, 0, -1.0]}, {"loadsteps": 1})
    assert res.node[5].p.shape == (3, 1)
    assert res.node[5].p[2, 0] == pytest.approx(0.05, abs=1e-15)   # never loaded
    assert any(note.startswith("opt.loadsteps is 1: the one step is the state before the "
                               "increments") for note in res.notes)


def test_a_step_past_buckling_is_named_not_a_silent_negative_frequency():
    """400 N pressing on the guide (buckling at 345.5 N): the last step's lowest mode
    grows; the note names the step and says the negative frequency means that."""
    res = _guide({"force": [0, 0, -400.0]}, {"loadsteps": 3})
    assert res.freq[0, -1] < 0 < res.freq[0, 1]
    assert any(note.startswith("step 3 lies past a buckling point: the equilibrium is "
                               "unstable there") for note in res.notes)


@pytest.mark.parametrize("change, words", [
    ({"eprops": {"emod": 210}}, r"eprops\(1\)\.emod = 210 Pa is softer than any rubber: "
                                r"moduli are in Pa \(210 GPa is 2\.1e\+11\)"),
    ({"eprops": {"dens": 7.8}}, r"eprops\(1\)\.dens = 7\.8 kg/m\^3 is lighter than any foam"),
    ({"eprops": {"dim": [20, 0.5]}}, r"eprops\(1\)\.dim = \[20\.0, 0\.5\] m is larger than "
                                     r"element 1, 0\.05 m long: dimensions are in m"),
    ({"stage": {"rot_z": 30}}, r"nprops\(5\)\.rot_z = 30 rad is more than a turn: rotations "
                               r"are in rad \(30 degrees is 0\.523599\)"),
])
def test_a_number_in_another_unit_is_named_with_the_si_value(change, words):
    """SPACAR Light takes SI units; a value whose size points at mm, GPa, g/cm^3 or
    degrees is named once, also in a silent run."""
    eprops = [dict(LEAF, elems=[1, 2], **change.get("eprops", {}))]
    with pytest.warns(fm.ModelWarning, match=words):
        light.run(GUIDE_NODES, GUIDE_ELEMENTS,
                  {1: {"fix": True}, 3: {"fix": True}, 5: change.get("stage", {})}, eprops,
                  {"silent": True, "loadsteps": 2})


def test_a_stress_beyond_any_material_is_named():
    """A leaf 0.5 m thick (a thickness in mm) driven 1 mm: stresses far beyond any
    material; the note says to check the units."""
    eprops = [dict(LEAF, elems=[1, 2], dim=[0.02, 0.5 * 0.05])]
    with pytest.warns(fm.ModelWarning, match=r"the largest stress, .* Pa, is beyond any "
                                             r"material's strength: check the units"):
        light.run(GUIDE_NODES, GUIDE_ELEMENTS, {1: {"fix": True}, 3: {"fix": True},
                                                5: {"displ_x": 0.04}},
                  eprops, {"silent": True, "loadsteps": 3})


def test_what_a_spacar_light_user_reads_off_its_output():
    """``out.version``, ``out.element(i).Ri`` (the first beam's frame: columns ex0 along
    the element, ey0 the set's orien, ez0) and the state space's SPACAR Light names."""
    res = _guide({"transfer_in": ["force_x"], "transfer_out": ["displ_x", "veloc_z"]},
                 {"transfer": [True]})
    assert res.version.startswith("flexmbd ")
    frame = res.element[1].Ri
    np.testing.assert_allclose(frame[:, 0], [0, 0, 1], atol=1e-15)    # leaf 1 along z
    np.testing.assert_allclose(frame[:, 1], [0, 1, 0], atol=1e-15)    # LEAF's orien
    np.testing.assert_allclose(frame.T @ frame, np.eye(3), atol=1e-15)
    assert res.statespace.InputName == ("force-x n5",)
    assert res.statespace.OutputName == ("displ-x n5", "veloc-z n5")


def test_the_mesh_check_reports_what_doubling_nbeams_changes():
    """``opt.meshcheck``: the guide driven 5 mm, rerun with nbeams doubled; the reported
    frequency change is that of the two runs, and it shrinks as the mesh is refined."""
    def stroke(nbeams, check=True):
        nprops = {1: {"fix": True}, 3: {"fix": True}, 5: {"displ_x": 5e-3}}
        return light.run(GUIDE_NODES, GUIDE_ELEMENTS, nprops,
                         [dict(LEAF, elems=[1, 2], nbeams=nbeams)],
                         {"silent": True, "loadsteps": 3, "meshcheck": check})

    coarse, finer = stroke(2), stroke(4)
    direct = stroke(4, check=False)
    expected = np.max(np.abs(direct.freq[:6] - coarse.freq[:6]) / np.abs(direct.freq[:6]))
    assert coarse.meshcheck["freq"] == pytest.approx(expected, rel=1e-12)
    assert finer.meshcheck["freq"] < coarse.meshcheck["freq"] / 3
    assert set(coarse.meshcheck) == {"freq", "stressmax", "displacement"}
    assert coarse.notes[-1].startswith("meshcheck: with every set's nbeams doubled, freq "
                                       "changes by")


def test_a_filename_writes_the_model_and_its_results(tmp_path):
    """``opt.filename``: the .dat SPACAR Light writes and the .sbd and .sbm SPACAR writes;
    the .dat, run again by flexmbd in mode 10, gives the same records."""
    from flexmbd.cli import main as cli
    from flexmbd.io.sbd import read_sbd

    base = tmp_path / "guide"
    res = _guide({"force": [0, 0, -1.0]}, {"loadsteps": 3, "filename": str(base)})
    assert any(note.startswith("opt.filename: wrote ") for note in res.notes)
    written = read_sbd(tmp_path / "guide.sbd")
    stage_z = written["LNP"][3 * 5 - 3, 2]      # user node 5: translational node 13, z
    assert written.step("X", 3)[stage_z - 1, 0] == res.node[5].p[2, -1]
    again = tmp_path / "again"
    again.mkdir()
    (again / "guide.dat").write_text((tmp_path / "guide.dat").read_text())
    assert cli(["spacar", "10", str(again / "guide")]) == 0
    rerun = read_sbd(again / "guide.sbd")
    for record in ("X", "E", "SIG"):
        scale = np.abs(written[record]).max()
        assert np.abs(rerun[record] - written[record]).max() <= 1e-9 * scale, record
