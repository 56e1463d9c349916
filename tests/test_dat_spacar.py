"""SPACAR's own syntax as SPACAR reads it: lines written by SPACAR, SPACAR Light and
oopspa mean in flexmbd what they mean in SPACAR."""

import re

import numpy as np
import pytest

from flexmbd.cli import main as cli
from flexmbd.errors import InputFileError
from flexmbd.io.dat import dat_from_text, dat_text

#: a cantilever of two spatial beams, as SPACAR Light lays out a file (tabs, comments)
CANTILEVER = """\
#NODES\t Nn\t\t\tX\t\t\tY\t\t\tZ
X\t\t  1\t\t\t0.000000\t0.000000\t0.000000\t\t#node 1
X\t\t  3\t\t\t0.100000\t0.000000\t0.000000\t\t#node 2
X\t\t  5\t\t\t0.200000\t0.000000\t0.000000\t\t#node 3
BEAM\t\t  1\t\t  1\t  2\t  3\t  4\t\t0.000000\t1.000000\t0.000000\t\t#beam
BEAM\t\t  2\t\t  3\t  4\t  5\t  6\t\t0.000000\t1.000000\t0.000000\t\t#beam
DYNE\t\t  1\t\t  1\t  2\t  3\t  4\t  5\t  6
DYNE\t\t  2\t\t  1\t  2\t  3\t  4\t  5\t  6
FIX\t\t  1
FIX\t\t  2
END
HALT
ESTIFF\t\t  1\t210000.0\t10.0\t20.0\t30.0
ESTIFF\t\t  2\t210000.0\t10.0\t20.0\t30.0
{block2}
END
END
"""


def read(block2: str = "", **replace: str):
    text = CANTILEVER.format(block2=block2)
    for old, new in replace.items():
        text = text.replace(old, new)
    return dat_from_text(text, "cantilever.dat")


def test_esig_gives_the_pre_stresses_in_order():
    """SPACAR's own output stores ``ESIG 1 1.0`` as element 1's first stress; more
    values are the next deformations' (not a deformation number and a value)."""
    model = read("ESIG\t\t  1\t1.0\nESIG 2 2 100").model
    assert model.element_properties[1].prestress == (1.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert model.element_properties[2].prestress == (2.0, 100.0, 0.0, 0.0, 0.0, 0.0)


def test_esig_writes_as_spacar_reads():
    model = read("ESIG 2 0 -3.5 7.25").model
    text = dat_text(model)
    assert "ESIG     2 0.0 -3.5 7.25\n" in text
    again = dat_from_text(text).model
    assert again.element_properties[2].prestress == model.element_properties[2].prestress


def test_esig_with_more_stresses_than_deformations_is_refused():
    with pytest.raises(InputFileError, match=r"cantilever.dat:15: ESIG: a BEAM has 6 "
                                             r"deformation\(s\), one pre-stress each in order; "
                                             r"got 7 values"):
        read("ESIG 1 1 2 3 4 5 6 7")


#: SPACAR Light's transfer-function file (mode 9): END HALT after block 2, then the
#: numbered inputs and outputs, each line starting with its number
TRANSFER = """\
EM\t\t\t  1\t\t   0.078\t   1e-5\t   1e-5\t   1e-5\t   0.0
EM\t\t\t  2\t\t   0.078\t   1e-5\t   1e-5\t   1e-5\t   0.0
END
HALT



INPUTF\t\t\t  1\t\t    5 \t    3
OUTXP\t\t\t  1\t\t    5 \t    3
OUTX\t\t\t  2\t\t    5 \t    3"""


def test_a_transfer_function_file_numbers_its_inputs_and_outputs():
    settings = read(TRANSFER, **{"10.0\t20.0\t30.0": "10.0\t20.0\t20.0"}).settings
    assert settings.force_inputs == ("x5.3",)
    assert settings.output_order == ("xd5.3", "x5.3")  # by number, not by keyword
    assert settings.outputs == ("x5.3",) and settings.rate_outputs == ("x5.3",)


def test_a_transfer_function_file_runs_as_statespace(tmp_path, capsys):
    """``flexmbd statespace`` on SPACAR's mode-9 layout: the outputs in the file's
    numbering, and the tip's static compliance that of a cantilever, L^3 / (3 EI)."""
    path = tmp_path / "cantilever_9.dat"
    path.write_text(CANTILEVER.format(block2=TRANSFER).replace("10.0\t20.0\t30.0",
                                                                "10.0\t20.0\t20.0"))
    assert cli(["statespace", str(path), "--out", str(tmp_path / "ss.npz")]) == 0
    with np.load(tmp_path / "ss.npz") as stored:
        system = dict(stored)
    assert list(system["outputs"]) == ["xd5.3", "x5.3"]
    gain = -system["C"] @ np.linalg.solve(system["A"], system["B"])
    np.testing.assert_allclose(gain[:, 0], [0.0, 0.2**3 / (3 * 20.0)], rtol=1e-9, atol=1e-15)


def test_a_transfer_function_file_is_written_as_spacar_lays_it_out():
    model, settings = read(TRANSFER)
    text = dat_text(model, settings)
    block3 = text.split("HALT")[2]
    assert "INPUTF   1 5 3\nOUTXP    1 5 3\nOUTX     2 5 3\nEND\nEND" in block3
    assert dat_from_text(text).settings == settings


@pytest.mark.parametrize("line, message", [
    ("OUTX 1 5 3", "output 1 is already defined on line"),
    ("OUTX 0 5 3", "outputs are numbered from 1, got 0"),
    ("OUTX 3 5 7", "node 5 is spatial translational: directions are 1 to 3, got 7"),
    ("OUTX 3 5", "OUTX takes OUTX number node direction; got 2 value"),
    ("STARTDX 5 1 0.0", "STARTDX is not supported by flexmbd in the block of inputs"),
    ("TUBE 3 1 2", "SPACAR's element or keyword TUBE is not supported by flexmbd"),
    ("OUTQ 3 5 1", "unknown keyword OUTQ in the transfer block; did you mean OUTX or OUTXP"),
])
def test_a_wrong_line_in_the_third_block_is_named(line, message):
    block2 = TRANSFER + "\n" + line
    with pytest.raises(InputFileError, match=re.escape(message)) as raised:
        read(block2)
    assert raised.value.line == CANTILEVER.format(block2=block2).splitlines().index(line) + 1


def test_em_values_left_off_are_zero():
    """``EM e rhoA Jxx`` on a BEAM: SPACAR takes the section inertias not given as 0."""
    model = read("EM 1 0.078 1.5e-5\nEM 2 0.078 1e-5 2e-5").model
    assert model.element_properties[1].section_inertia == (1.5e-5, 0.0, 0.0, 0.0)
    assert model.element_properties[2].section_inertia == (1e-5, 2e-5, 0.0, 0.0)
    with pytest.raises(InputFileError, match="a BEAM takes rhoA and then Jxx Jyy Jzz Jyz"):
        read("EM 1 0.078 1 2 3 4 5 6")


def test_fix_of_a_node_no_element_uses_is_a_note():
    """SPACAR Light writes ``FIX n #warping`` for every warping node (since 2021), warping
    elements or not."""
    dat = read(**{"FIX\t\t  2\n": "FIX\t\t  2\nFIX\t\t 13  #warping\n"})
    assert any("FIX on line 11: node 13 is used by no element" in n for n in dat.settings.notes)
    assert 13 not in dat.model.nodes


def test_classification_may_come_before_the_element_line():
    """Block 1 has no order in SPACAR: a FIX may name a node its element defines later."""
    text = CANTILEVER.format(block2="")
    lines = text.splitlines()
    fixes = [line for line in lines if line.startswith("FIX")]
    reordered = "\n".join(fixes + [line for line in lines if not line.startswith("FIX")])
    model = dat_from_text(reordered, "cantilever.dat").model
    assert dat_text(model) == dat_text(dat_from_text(text, "cantilever.dat").model)


def test_a_translational_node_without_x_starts_at_the_origin():
    dat = read(**{"X\t\t  1\t\t\t0.000000\t0.000000\t0.000000\t\t#node 1\n": ""})
    assert dat.model.nodes[1].position == (0.0, 0.0, 0.0)
    assert any("node 1 (BEAM 1, line 4) has no X line: it starts at the origin" in n
               for n in dat.settings.notes)


def test_euler_parameter_forces_of_before_2017_are_a_moment():
    """SPACAR before 2017 loaded a rotational node by forces on its Euler parameters,
    ``0 2Mx 2My 2Mz`` (``2 E(lam)^T M`` at the reference orientation)."""
    old = read("XF 6 0 0.4 -1.0 3.0\nDELXF 6 0 0 0 2")
    new = read("XF 6 0.2 -0.5 1.5\nDELXF 6 0 0 1")
    assert dat_text(old.model) == dat_text(new.model)
    assert dict(old.settings.load_increment) == dict(new.settings.load_increment)
    assert any("line 16: the four values on rotational node 6" in n for n in old.settings.notes)
    with pytest.raises(InputFileError, match="whose first must be 0 \\(got 1\\)"):
        read("XF 6 1 0 0 0")


def test_an_empty_estiff_line_is_as_no_line():
    """oopspa writes ``ESTIFF e`` with no values; SPACAR then keeps the element's defaults,
    as if the line were not there."""
    empty = read("ESTIFF 2", **{"ESTIFF\t\t  2\t210000.0\t10.0\t20.0\t30.0\n": ""})
    absent = read(**{"ESTIFF\t\t  2\t210000.0\t10.0\t20.0\t30.0\n": ""})
    assert dat_text(empty.model) == dat_text(absent.model)


def test_inverse_dynamics_keywords_are_refused_with_what_to_use():
    text = CANTILEVER.format(block2="NOMS 1 1 0.5")
    with pytest.raises(InputFileError, match=r":\d+: SPACAR's keyword NOMS is not supported "
                                             r"by flexmbd: prescribe the motion with INPUTX"):
        dat_from_text(text, "nominal.dat")


def test_the_guide_lists_every_keyword_the_reader_knows():
    """The guide's support table names exactly the keywords flexmbd reads or refuses."""
    import re
    from pathlib import Path

    from flexmbd.io.dat.syntax import DYNAMICS, INSTEAD, KINEMATICS, TRANSFER, UNSUPPORTED

    page = (Path(__file__).parent.parent / "docs" / "guide" / "spacar-files.md").read_text()
    table = page.split("## SPACAR's keywords and elements in flexmbd")[1].split("\n## ")[0]
    listed = {word for row in table.splitlines() if row.startswith("| `")
              for word in re.findall(r"`([A-Z0-9]+)`", row.split("|")[1])}
    assert listed == {*KINEMATICS, *DYNAMICS, *TRANSFER, *UNSUPPORTED, *INSTEAD}


def test_a_beam_without_orientation_takes_spacars_choice_and_says_so():
    """SPACAR takes the global axis in which the beam is smallest, the last of equal ones,
    made perpendicular to the beam: a beam along x gets ey0 = z (y and z tie); SPACAR 2019
    stored ey0 = y for a beam along z (x and y tie)."""
    text = CANTILEVER.format(block2="").replace("\t\t0.000000\t1.000000\t0.000000\t\t#beam",
                                                "", 1)
    dat = dat_from_text(text, "beam.dat")
    frame = np.array(dat.model.elements[1].reference[1:10]).reshape(3, 3)   # rows ex, ey, ez
    assert frame == pytest.approx(np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]]), abs=1e-15)
    assert [n for n in dat.settings.notes if "orientation" in n] == [
        "line 5: no orientation vector; the local y axis is SPACAR's choice, the global axis "
        "in which the element's direction is smallest (the last of equal ones) made "
        "perpendicular to it"]
    upright = text.replace("X\t\t  3\t\t\t0.100000\t0.000000\t0.000000",
                           "X\t\t  3\t\t\t0.000000\t0.000000\t0.100000")
    frame = np.array(dat_from_text(upright, "beam.dat").model.elements[1].reference[1:10])
    assert frame[3:6] == pytest.approx([0, 1, 0], abs=1e-15)


@pytest.mark.parametrize("axis, ey0", [((0, 0, 1), (-1, 0, 0)), ((1, 0, 0), (0, -1, 0)),
                                       ((0, 1, 0), (1, 0, 0)),
                                       ((1, 1, 0), (0.5**0.5, -(0.5**0.5), 0))])
def test_hinge_frames_are_spacars(axis, ey0):
    """``ey0 = unit(ex0 x e_k)``, ``e_k`` the global axis of the axis's smallest component
    (the last of equal ones): about z, ``ey0 = -x`` as SPACAR stores it."""
    from flexmbd.elements.spatial_hinge import hinge_frame

    frame = hinge_frame(np.array([axis], dtype=float))[0]      # columns ex0, ey0, ez0
    assert frame[:, 1] == pytest.approx(ey0, abs=1e-15)
    assert frame[:, 2] == pytest.approx(np.cross(frame[:, 0], frame[:, 1]), abs=1e-15)


def test_a_planar_beams_rotary_inertia_turns_with_it():
    """``EM e rhoA rhoI`` on a planar beam: a rigid beam on a hinge spring ``k`` about its
    end has ``omega^2 = k / (rhoA L^3 / 3 + rhoI L)``; the builder takes ``(rhoI,)``, and a
    spatial beam's four values are refused on a planar one."""
    import flexmbd as fm

    L, rho_a, rho_i, k = 0.5, 2.0, 0.03, 7.0
    text = (f"PLBEAM 1 1 2 3 4\nPLHINGE 2 5 2\nX 3 {L} 0\nFIX 1\nFIX 5\nDYNE 2 1\nEND\nHALT\n"
            f"EM 1 {rho_a} {rho_i}\nESTIFF 2 {k}\nEND\nEND\n")
    model, _ = dat_from_text(text, "rotary.dat")
    frequency = fm.vibration_modes(fm.static_equilibrium(model).linearization(), 1)
    expected = np.sqrt(k / (rho_a * L**3 / 3 + rho_i * L)) / (2 * np.pi)
    assert frequency.frequencies[0] == pytest.approx(expected, rel=1e-10)
    assert model.section_masses[2] == pytest.approx(0.5 * L * rho_i)
    b = fm.ModelBuilder("rotary").add_node(1, 0, 0).add_node(3, L, 0)
    b.add_beam(1, 1, 2, 3, 4).set_mass(1, rho_a, section_inertia=(1e-3, 0, 0, 0))
    with pytest.raises(fm.ModelError, match=r"a beam takes one section inertia, its rotary "
                                            r"inertia per length \(rhoI,\)"):
        b.fix(1).fix(2).build()
