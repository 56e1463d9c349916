"""Spatial SPACAR files: every spatial keyword read, written and read back, the values
flexmbd reads but does not model reported once, and spatial files that are malformed or
mix planar and spatial elements refused at their line."""

from pathlib import Path

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.cli import main as cli
from flexmbd.io.dat import dat_from_text, dat_text
from tests.test_dat import state

#: a spatial file that uses every spatial keyword: a driven hinge turning a flexible arm,
#: a spring truss to a free point mass, a rigid pendulum on a spring hinge at the arm's tip
SPATIAL_EVERYTHING = """\
% every spatial keyword
OUTLEVEL 0 1
HINGE  1  2 3   0 0 1          % driven hinge about Z
BEAM   2  1 3 4 5   0 0 1      % flexible arm along X
TRUSS  3  4 6                  % spring to the free mass
HINGE  4  5 7   0 1 0          % spring hinge about Y at the tip
beam   5  4 7 8 9   1 0 0      % rigid pendulum, down
TRUSS  6  6 10                 % spring to a slider
X 1 0 0 0
X 4 0.5 0 0
X 6 0.7 0.0 0.0
X 8 0.5 0 -0.2
X 10 1.0D0 0 0
FIX 1
FIX 2
FIX 10 2 3
INPUTX 10 1
INPUTE 1 1
DYNE 2 3 4 5 6
DYNE 4 1
RLSE 3
RLSE 6 1
DYNX 6
END
HALT
OUTLEVEL 1
EM 2 0.8 1e-4 5e-5 6e-5 1e-6 2e-9
EM 3 0.01
EMLUMP 5 0.3
ESTIFF 2 2e7 30 50 80 2e-5 3e-5 1e-3
ESTIFF 3 1000
ESTIFF 4 5 0 0
ESTIFF 6 200
EDAMP 2 0 0.01 0.02 0.03
EDAMP 4 0.1
ESIG 3 5.0
XM 6 0.1
XM 7 1e-3 0 1e-5 2e-3 0 3e-3
XF 8 0 0 -1.5
XF 7 0 0.2 0
GRAVITY 0 0 -9.81
INPUTX 10 1 1.0 0.0 0.0
INPUTE 1 1 0.0 2.0
STARTDE 4 1 0.1 0.0
STARTDX 6 3 0.0 0.1
TIMESTEP 0.2 20
ITERSTEP 30 4 1e-11 1 3 4
ERROR 1e-10 1e-7
DELXF 6 1 0 0
DELXF 9 0 0.1 0
DELINPX 10 1 0.01
DELINPE 1 1 0.5
INPUTF 6 3
OUTX 6 3
OUTXP 6 1
END
END
VISUALIZATION
BEAMPROPS 2 1 1
"""


def test_every_spatial_keyword_is_read():
    model, s = dat_from_text(SPATIAL_EVERYTHING, "everything.dat")
    assert model.is_spatial
    assert [model.elements[n].type for n in range(1, 7)] == [
        fm.SpatialHinge, fm.SpatialBeam, fm.SpatialTruss, fm.SpatialHinge, fm.SpatialBeam,
        fm.SpatialTruss]
    # the automatic Euler elements follow the user's, one per rotational node
    assert [model.elements[n].type for n in range(7, 12)] == [fm.EulerNormalization] * 5
    assert dict(model.elements[2].data) == {"orientation": (0.0, 0.0, 1.0),
                                            "bending_linked": (1.0,)}
    assert dict(model.elements[4].data) == {"axis": (0.0, 1.0, 0.0)}
    assert model.nodes[10].position == (1.0, 0.0, 0.0)
    # FIX 2 on a rotational node fixes lam1..lam3; DYNX 6 frees x, y and z
    fixed = [model.coordinate_labels[i] for i in model.fixed]
    assert fixed == ["x1.1", "x1.2", "x1.3", "x2.2", "x2.3", "x2.4", "x10.2", "x10.3"]
    assert model.q_labels == ("x6.1", "x6.2", "x6.3", "x10.1", "e1.1", "e2.3", "e2.4",
                              "e2.5", "e2.6", "e4.1")
    p = model.element_properties
    assert (p[2].mass_per_length, p[2].section_inertia) == (0.8, (1e-4, 5e-5, 6e-5, 1e-6))
    assert p[5].lumped and p[3].mass_per_length == 0.01
    assert dict(p[2].stiffness) == {"axial": 2e7, "torsion": 30.0, "bending_y": 50.0,
                                    "bending_z": 80.0, "shear_y": 2e-5, "shear_z": 3e-5}
    assert dict(p[2].damping) == {"axial": 0.0, "torsion": 0.01, "bending_y": 0.02,
                                  "bending_z": 0.03}
    assert dict(p[4].stiffness) == {"hinge": 5.0, "tilt_y": 0.0, "tilt_z": 0.0}
    assert p[3].prestress == (5.0,)
    assert model.nodal_masses == {6: 0.1}
    assert model.nodal_inertias == {7: (1e-3, 0.0, 1e-5, 2e-3, 0.0, 3e-3)}
    assert model.nodal_forces == {8: (0.0, 0.0, -1.5), 7: (0.0, 0.2, 0.0)}
    assert model.gravity == (0.0, 0.0, -9.81)
    assert model.input_laws["e1.1"] == fm.Polynomial(0.0, 2.0, 0.0)
    assert dict(s.initial) == {"e4.1": (0.1, 0.0), "x6.3": (0.0, 0.1)}
    # a moment increment on a rotational node sits on lam1..lam3, as loads do
    assert dict(s.load_increment) == {"x6.1": 1.0, "x6.2": 0.0, "x6.3": 0.0, "x9.2": 0.0,
                                      "x9.3": 0.1, "x9.4": 0.0}
    assert dict(s.input_increment) == {"x10.1": 0.01, "e1.1": 0.5}
    assert (s.force_inputs, s.outputs, s.rate_outputs) == (("x6.3",), ("x6.3",), ("x6.1",))
    # what is read but not modelled is reported once per kind, with its lines
    assert s.notes == ("OUTLEVEL (SPACAR's output level) on lines 2, 26: read and ignored",
                       "the warping inertia Jw (EM's 6th value) on line 27: read and ignored",
                       "the warping stiffness ECw (ESTIFF's 7th value) on line 30: read and "
                       "ignored")


def test_the_spatial_file_runs():
    """The file is a working model: a short simulation and the static load steps."""
    model, s = dat_from_text(SPATIAL_EVERYTHING, "everything.dat")
    run = fm.simulate(model, s.output_times()[:5], initial=s.initial,
                      method="GeneralizedAlpha", step=1e-3)
    assert run.success and np.all(np.isfinite(run.x))
    static = fm.static_equilibrium(model, load_increment=dict(s.load_increment),
                                   input_increment=dict(s.input_increment), steps=2)
    assert static.success and len(static.load) == 3


def test_spatial_files_round_trip(tmp_path):
    model, settings = dat_from_text(SPATIAL_EVERYTHING, "m.dat")
    path = fm.write_dat(model, tmp_path / "m.dat", settings)
    again, settings_again = fm.read_dat(path)
    assert state(again, settings_again) == state(model, dataclass_replace(settings))
    assert dat_text(again, settings_again) == dat_text(model, settings)


def dataclass_replace(settings):
    """The settings a written file reads back with: the notes are about the original."""
    import dataclasses
    return dataclasses.replace(settings, notes=())


def test_a_spatial_python_model_round_trips(tmp_path):
    b = fm.ModelBuilder("arm")
    b.add_node(1, 0, 0, 0).add_node(3, 0.4, 0.1, -0.2)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0.1, 1, 0.3))
    b.fix(1).fix(2).dynamic_deformation(1, 3, 4, 5, 6)
    b.set_mass(1, 1.5, section_inertia=(1e-3, 4e-4, 6e-4, 1e-5))
    b.set_stiffness(1, axial=1e7, torsion=20, bending_y=40, bending_z=60)
    b.add_force(4, 0.1, -0.2, 0.3).add_rotary_inertia(4, 1, 0, 0, 2, 0, 3)
    model = b.build()
    again, settings = fm.read_dat(fm.write_dat(model, tmp_path / "m.dat"))
    assert state(again) == state(model) and settings == fm.RunSettings()


def test_a_beam_without_the_bending_linked_terms_cannot_be_written(tmp_path):
    b = fm.ModelBuilder("arm")
    b.add_node(1, 0, 0, 0).add_node(3, 1, 0, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 1, 0), bending_linked=False)
    b.fix(1).fix(2).dynamic_deformation(1).set_section(1, fm.Circle(0.01), fm.Material(
        210e9, 80e9, 7800.0))
    with pytest.raises(fm.FlexmbdError, match="bending-linked terms"):
        fm.write_dat(b.build(), tmp_path / "m.dat")


def test_notes_are_printed_by_the_command_line(tmp_path, capsys):
    path = tmp_path / "everything.dat"
    path.write_text(SPATIAL_EVERYTHING)
    cli(["static", str(path), "--steps", "1"])
    err = capsys.readouterr().err
    assert err.count("note: ") == 3 and "ECw" in err


ARM = """BEAM 1 1 2 3 4 0 0 1
X 1 0 0 0
X 3 1 0 0
FIX 1
FIX 2
DYNE 1 3 4 5 6
END
HALT
ESTIFF 1 1e7 10 20 30
{dynamics}
END
END
"""

MALFORMED = {
    "planar position in a spatial file": (ARM.replace("X 3 1 0 0", "X 3 1 0"), 3,
                                          "a spatial file gives x y z, got 2 value(s)"),
    "spatial position in a planar file": ("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0 0\nEND\nEND\n", 3,
                                          "a planar file gives x y, got 3 value(s)"),
    "direction 5 of a rotational node": (ARM.replace("FIX 2", "FIX 2 5"), 5,
                                         "directions are 1 to 4, got 5"),
    "moment with two values": (ARM.format(dynamics="XF 4 1 2"), 10,
                               "node 4 is spatial rotational: give Mx My Mz"),
    "inertia tensor of three values": (ARM.format(dynamics="XM 4 1 2 3"), 10,
                                       "give its inertia tensor Ixx Ixy Ixz Iyy Iyz Izz"),
    "section inertia of six values": (ARM.format(dynamics="EM 1 2.0 1 2 3 4 5 6"), 10,
                                      "a BEAM takes rhoA and then Jxx Jyy Jzz Jyz [Jw]"),
    "eight stiffness values": (ARM.format(dynamics="ESTIFF 1 1 2 3 4 5 6 7 8"), 10,
                               "a BEAM takes 6 value(s)"),
    "orientation along the beam": (ARM.replace("0 0 1", "2 0 0"), 1,
                                   "orientation vector (2.0, 0.0, 0.0) lies along the beam"),
    "huge axis": ("HINGE 1 2 3 1e308 0 1\nFIX 2\nEND\nEND\n", 1,
                  "axis (1e+308, 0.0, 1.0) is not finite numbers of at most 1e+100"),
    "hinge without its axis": ("HINGE 1 2 3\nEND\nEND\n", 1,
                               "takes HINGE element lam_p lam_q ax ay az"),
    "planar gravity in a spatial file": (ARM.format(dynamics="GRAVITY 0 -9.81"), 10,
                                         "a spatial file gives gx gy gz, got 2 value(s)"),
    "spatial then planar element": ("TRUSS 1 1 2\nPLTRUSS 2 2 3\nEND\nEND\n", 2,
                                    "mixes planar and spatial elements: PLTRUSS on line 2, "
                                    "TRUSS on line 1"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_malformed_spatial_files_name_line_and_reason(case, tmp_path):
    text, line, reason = MALFORMED[case]
    path = tmp_path / "bad.dat"
    path.write_text(text if "{dynamics}" not in text else text.format(dynamics=""))
    with pytest.raises(fm.InputFileError) as info:
        fm.read_dat(path)
    assert reason in str(info.value) and info.value.line == line, str(info.value)


def test_flexmbd_static_writes_one_row_per_load_step(tmp_path, capsys):
    path, out = tmp_path / "everything.dat", tmp_path / "steps.csv"
    path.write_text(SPATIAL_EVERYTHING)
    assert cli(["static", str(path), "--steps", "3", "--out", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert len(lines) == 1 + 4   # a header, the model's loads, three load steps
    header = lines[0].split(",")
    assert "x9.4" in header and "f2.4" in header   # lam3 of a rotational node, a moment


def test_the_spatial_example_file_runs():
    """examples/rotating_arm.dat: the driven hinge follows its law (2 rad/s^2 from rest),
    the arm keeps its length (elongation rigid), and its weight, applied at once to the
    undamped arm, swings its tip down to twice the static cantilever sag q L^4/(8 EI) +
    P L^3/(3 EI) (to 3 %: the spin stiffens it a little)."""
    dat = fm.read_dat(Path(__file__).resolve().parents[1] / "examples" / "rotating_arm.dat")
    run = fm.simulate(dat.model, np.linspace(0.0, 1.0, 201), method="GeneralizedAlpha")
    np.testing.assert_allclose(run["e1.1"], run.t**2, atol=1e-12)
    tip = np.stack([run["x10.1"], run["x10.2"], run["x10.3"]], axis=1)
    assert np.all(np.linalg.norm(tip, axis=1) > 0.99)
    EI, q, P = 7.4667, 0.216 * 9.81, 0.05 * 9.81
    sag = q / (8 * EI) + P / (3 * EI)
    assert -tip[:, 2].min() == pytest.approx(2 * sag, rel=0.03)
