"""SPACAR input files: reading every keyword, round trips, malformed files, flexmbd run."""

import math
from pathlib import Path

import numpy as np
import pytest
from flexmbd.examples import slider_crank_dynamics, slider_crank_flex

import flexmbd as fm
from flexmbd.cli import main as cli
from flexmbd.io.dat import dat_from_text, dat_text

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DAT_FILES = sorted(EXAMPLES.glob("*.dat"))

#: a file that uses every keyword of the planar subset
EVERYTHING = """\
* every keyword: a four-bar with a flexible coupler, a spring hinge and a loaded slider
PLRBEAM 1  1 2 3          % crank, flexmbd's rigid beam
plbeam  2  3 4 5 6        # coupler (keywords are case-insensitive)
PLBEAM  3  5 7 8 9
PLHINGE 4  6 7
PLTRUSS 5  8 10
PLSPRING 6  5 10          % flexmbd's spring-damper (released by default)
X 1 0 0
X 3 0.1 0.0
X 5 0.3 0.0
X 8 0.5 0.0
X 10 0.5D0 -0.2D0         % Fortran exponents
FIX 1
FIX 10
INPUTX 2 1
DYNE 2 2 3.
RLSE 4 1
INPUTE 5 1
DYNX 5 2
END
HALT
EM 2 0.5
EMLUMP 3 0.25
EM 1 0.1 0.0
ESTIFF 2 1e6 10.0 2e5
ESTIFF 3 1e6 10.0
ESTIFF 4 3.5
EDAMP 2 0.0 0.01
EDAMP 4 0.2
ESIG 5 12.5
ESTIFF 6 400.0
EDAMP 6 1.5
ESIG 6 2.0
XM 5 0.02
XM 6 1e-4
XF 5 1.0 -2.0
XF 6 0.3
GRAVITY 0 -9.81
INPUTX 2 1 0.0 10.0 5.0
INPUTE 5 1 0.0 0.01
STARTDE 2 2 1e-4 0.0
STARTDX 5 2 0.0 0.5
TIMESTEP 0.5 50
ITERSTEP 30 4 1e-11 1 3 4
ERROR 1e-10 1e-7
END
END
VISUALIZATION
anything here is ignored 1 2 3
"""


def everything() -> fm.Model:
    """The model of :data:`EVERYTHING`."""
    return dat_from_text(EVERYTHING, "everything.dat").model


def state(model: fm.Model, settings: fm.RunSettings | None = None) -> dict:
    """Everything a model (and its run settings) describes, in comparable form."""
    settings = settings or fm.RunSettings()
    return {
        "nodes": {n: (v.kind, v.position, v.coordinates) for n, v in model.nodes.items()},
        "elements": {n: (e.type, e.nodes, dict(e.data)) for n, e in model.elements.items()},
        "x0": model.x0.tolist(),
        "classes": (model.coordinate_class.tolist(), model.deformation_class.tolist()),
        "laws": dict(model.input_laws),
        "properties": dict(model.element_properties),
        "masses": dict(model.nodal_masses),
        "inertias": dict(model.nodal_inertias),
        "forces": dict(model.nodal_forces),
        "gravity": model.gravity,
        "settings": settings,
    }


def test_every_keyword_is_read():
    model, s = dat_from_text(EVERYTHING, "everything.dat")
    assert model.name == "everything"
    assert [model.elements[n].type for n in range(1, 7)] == [
        fm.RigidBeam, fm.Beam, fm.Beam, fm.Hinge, fm.Truss, fm.SpringDamper]
    assert model.nodes[10].position == (0.5, -0.2)
    assert model.q_labels == ("x2.1", "x5.2", "e2.2", "e2.3", "e5.1")
    assert model.q_is_input.tolist() == [True, False, False, False, True]
    for label in ("e4.1", "e6.1"):  # RLSE, and the spring's default
        assert model.deformation_class[model.deformation_index(label)] == \
            fm.DeformationClass.RELEASED
    p = model.element_properties
    assert (p[2].mass_per_length, p[2].lumped) == (0.5, False)
    assert p[3].lumped and p[1].mass_per_length == 0.1
    assert dict(p[2].stiffness) == {"axial": 1e6, "bending": 10.0, "shear": 2e5}
    assert "shear" not in p[3].stiffness and dict(p[4].stiffness) == {"hinge": 3.5}
    assert dict(p[2].damping) == {"axial": 0.0, "bending": 0.01}
    assert dict(p[4].damping) == {"hinge": 0.2}
    assert p[5].prestress == (12.5,)
    assert (dict(p[6].stiffness), dict(p[6].damping), p[6].prestress) == (
        {"spring": 400.0}, {"spring": 1.5}, (2.0,))
    assert model.nodal_masses == {5: 0.02, 6: 1e-4}
    assert model.nodal_forces == {5: (1.0, -2.0), 6: (0.3,)}
    assert model.gravity == (0.0, -9.81)
    assert model.input_laws["x2.1"] == fm.Polynomial(0.0, 10.0, 5.0)
    assert model.input_laws["e5.1"] == fm.Polynomial(0.0, 0.01, 0.0)
    assert dict(s.initial) == {"e2.2": (1e-4, 0.0), "x5.2": (0.0, 0.5)}
    # ITERSTEP in SPACAR's order: iterations, load steps, tolerance, solver flags
    assert (s.t_end, s.steps, s.max_iterations, s.load_steps, s.tolerance, s.atol, s.rtol) == (
        0.5, 50, 30, 4, 1e-11, 1e-10, 1e-7)
    assert len(s.output_times()) == 51


@pytest.mark.parametrize("text", [EVERYTHING, *(p.read_text() for p in DAT_FILES)],
                         ids=["everything", *(p.name for p in DAT_FILES)])
def test_write_then_read_gives_an_equal_model(text, tmp_path):
    model, settings = dat_from_text(text, "m.dat")
    path = fm.write_dat(model, tmp_path / "m.dat", settings)
    again, settings_again = fm.read_dat(path)
    assert state(again, settings_again) == state(model, settings)
    assert dat_text(again, settings_again) == dat_text(model, settings)


def test_python_models_round_trip(tmp_path):
    for model in (slider_crank_flex.build_model(3, eps1flex=True),
                  slider_crank_dynamics.build_model("lumped", gravity=True)):
        again, settings = fm.read_dat(fm.write_dat(model, tmp_path / "m.dat"))
        assert state(again) == state(model) and settings == fm.RunSettings()


def test_models_the_format_cannot_hold_are_refused(tmp_path):
    b = fm.ModelBuilder()
    b.add_node(1, 0, 0).add_node(3, 1, 0).add_rigid_beam(1, 1, 2, 3).fix(1)
    b.input_coordinate(2, law=fm.Custom(math.sin, math.cos, lambda t: -math.sin(t)))
    with pytest.raises(fm.FlexmbdError, match="Polynomial"):
        fm.write_dat(b.build(), tmp_path / "m.dat")


CRANK = """PLRBEAM 1 1 2 3
PLRBEAM 2 3 4 5
X 1 0 0
X 3 0.15 0
X 5 0.45 0
FIX 1
FIX 5 2
INPUTX 2 1
END
HALT
EM 2 0.2225
XM 5 0.03338
GRAVITY 0 -9.81
TIMESTEP 0.0419 72
ESTIFF 1 1e6
INPUTX 2 1 0 150
END
END
"""

MALFORMED = {
    "truncated": ("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nINPUTX 2", 5, "ends without"),
    "word for a number": ("PLTRUSS 1 1 two\nEND\nEND\n", 1, "must be a number"),
    "unknown node": ("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nINPUTX 7\nEND\nEND\n", 5,
                     "node 7 is not used"),
    "missing END": ("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2\nEND\nHALT\nXM 2 1.0\n",
                    8, "END ending the dynamics block"),
    "duplicate element": ("PLTRUSS 1 1 2\nPLTRUSS 1 2 3\nEND\nEND\n", 2,
                          "already defined on line 1"),
    "negative step count": ("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1 2\nINPUTX 2 1\nFIX 2 2\n"
                            "END\nHALT\nINPUTX 2 1 1 0.1\nTIMESTEP 1.0 -5\nEND\nEND\n", 10,
                            "must be positive"),
    "mixed planar and spatial": ("PLTRUSS 1 1 2\nBEAM 2 1 2 3 4 0 0 1\nEND\nEND\n", 2,
                                 "mixes planar and spatial elements: PLTRUSS on line 1, "
                                 "BEAM on line 2"),
    "unsupported keyword": ("PLTRUSS 1 1 2\nPINBAR 2 1 2\nEND\nEND\n", 2,
                            "SPACAR's element or keyword PINBAR is not supported by flexmbd"),
    "too many values": ("PLTRUSS 1 1 2 3\nEND\nEND\n", 1, "takes PLTRUSS element p q"),
    "fractional node": ("PLTRUSS 1 1 2.5\nEND\nEND\n", 1, "whole number"),
    "huge node number": ("PLTRUSS 1 1 1e308\nEND\nEND\n", 1, "is larger than"),
    "bad direction": ("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1 3\nEND\nEND\n", 4,
                      "directions are 1 and 2"),
    "block-2 keyword in block 1": ("PLTRUSS 1 1 2\nEM 1 2.0\nEND\nEND\n", 2,
                                   "belongs in the dynamics block"),
    "mass on a massless element": ("PLSPRING 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2\nEND\n"
                                   "HALT\nEM 1 2.0\nEND\nEND\n", 8, "which has no mass"),
    "start of a coordinate that is not dynamic": (
        "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2\nRLSE 1\nEND\nHALT\n"
        "STARTDX 2 1 0.1\nEND\nEND\n", 9, "x2.1 is not a dynamic degree of freedom"),
    # errors found when the model is assembled name the line that made what they are about
    "nan in a law": (CRANK.replace("INPUTX 2 1 0 150", "INPUTX 2 1 nan 150"), 16,
                     "x0 must be a finite number"),
    "overflowing number": (CRANK.replace("X 5 0.45 0", "X 5 1e400 0"), 5,
                           "x must be a finite number"),
    "far node": (CRANK.replace("X 5 0.45 0", "X 5 1e300 0"), 5, "beyond 1e+100 m"),
    "coincident nodes": (CRANK.replace("X 5 0.45 0", "X 5 0.15 0"), 2,
                         "PLRBEAM: rigid beam 2 has zero length: its nodes 3 and 5 coincide"),
    "two classes": (CRANK.replace("FIX 5 2", "FIX 5 2\nINPUTX 5 2"), 8,
                    "INPUTX: x5.2 is put in two classes: fixed and an input"),
    "too many equations": (CRANK.replace("FIX 5 2", "FIX 5"), 1,
                           "degree-of-freedom count does not close"),
    "too few equations": (CRANK.replace("FIX 5 2", ""), 2,
                          "degree-of-freedom count does not close"),
    "rotational node with a position": ("X 4 1 1\n" + CRANK, 1, "node 4 is rotational"),
    "start of a rigid deformation": (CRANK.replace("TIMESTEP", "STARTDE 1 1 0.1\nTIMESTEP"), 14,
                                     "STARTDE: e1.1 is not a dynamic degree of freedom"),
    "invisible character": (CRANK.replace("FIX 1", "FIX\u200b 1"), 6,
                            "unknown keyword 'FIX\\u200b'"),
    # run settings that cannot work are refused at their line, before any run
    "iteration limit that cannot help": (CRANK.replace("TIMESTEP", "ITERSTEP 100000000 1 "
                                                       "1e-300\nTIMESTEP"), 14,
                                         "ITERSTEP: max_iterations: must lie in 1 .. 1000"),
    "tolerance below round-off": (CRANK.replace("TIMESTEP", "ITERSTEP 10 1 1e-300\nTIMESTEP"),
                                  14, "ITERSTEP: tolerance: 1e-300 is below the round-off"),
    "loose tolerance": (CRANK.replace("TIMESTEP", "ITERSTEP 10 1 1e10\nTIMESTEP"), 14,
                        "ITERSTEP: tolerance: 1e+10 is not small against the model's size"),
    "integrator tolerance below round-off": (
        CRANK.replace("TIMESTEP", "ERROR 1e-300 1e-300\nTIMESTEP"), 14,
        "ERROR: rtol: 1e-300 must lie in"),
    "integrator tolerance that controls nothing": (
        CRANK.replace("TIMESTEP", "ERROR 1e10 1e10\nTIMESTEP"), 14, "ERROR: rtol: 1e+10 must"),
    "empty file": ("# nothing\n\n", 2, "the file is empty, without END"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_malformed_files_name_line_and_reason(case, tmp_path, capsys):
    text, line, reason = MALFORMED[case]
    path = tmp_path / "bad.dat"
    path.write_text(text)
    with pytest.raises(fm.InputFileError) as info:
        fm.read_dat(path)
    assert info.value.line == line and reason in str(info.value)
    assert str(info.value).startswith(f"{path}:{line}: ")
    assert cli(["run", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and reason in err and "Traceback" not in err


def test_a_byte_order_mark_is_not_a_keyword():
    model, _ = dat_from_text("\ufeff" + CRANK, "bom.dat")
    assert model.n_dof == 1


def test_a_file_that_is_not_text_is_refused_unread(tmp_path):
    with pytest.raises(fm.InputFileError, match="larger than 64 MiB"):
        fm.read_dat("/dev/zero")
    binary = tmp_path / "image.dat"
    binary.write_bytes(b"PLTRUSS 1 1 2\n\x00\x01\x02")
    with pytest.raises(fm.InputFileError, match="not a text file") as info:
        fm.read_dat(binary)
    assert info.value.line == 2


def test_a_model_error_after_reading_names_the_file(tmp_path):
    path = tmp_path / "loose.dat"
    path.write_text("PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nEND\nEND\n")  # q is free
    with pytest.raises(fm.InputFileError, match="degree-of-freedom count"):
        fm.read_dat(path)


def test_flexible_slider_crank_file_matches_the_python_model(tmp_path, capsys):
    out = tmp_path / "flex.csv"
    assert cli(["run", str(EXAMPLES / "slider_crank_flex.dat"), "--out", str(out),
                "--method", "RK45"]) == 0
    assert "801 rows written" in capsys.readouterr().out
    header = out.read_text().splitlines()[0].split(",")
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    model, _ = fm.read_dat(EXAMPLES / "slider_crank_flex.dat")
    x = data[:, [header.index(label) for label in model.coordinate_labels]]
    v_file = slider_crank_flex.midpoint_deflection(model, x)
    python = slider_crank_flex.simulate(1, revolutions=2.0, method="RK45", rtol=1e-6)
    v_python = slider_crank_flex.midpoint_deflection(python.model, python.x)
    assert len(v_file) == 801 and np.ptp(v_file) > 0.02
    assert np.max(np.abs(v_file - v_python)) < 1e-8


def test_rigid_slider_crank_file_gives_the_lagrange_torque(tmp_path):
    out = tmp_path / "torque.npz"
    assert cli(["run", str(EXAMPLES / "slider_crank_rigid.dat"), "--mode", "inverse",
                "--out", str(out), "--plot", str(tmp_path / "t.png")]) == 0
    with np.load(out) as stored:
        data = dict(stored)
    assert "f2.1" in data["columns"] and len(data["t"]) == 73
    expected = slider_crank_dynamics.lagrange_torque(data["x2.1"], 150.0, 0.0, gravity=True)
    np.testing.assert_allclose(data["f2.1"], expected, atol=1e-9 * np.abs(expected).max())


def test_sliding_bar_file_runs_kinematics_by_default(tmp_path):
    out = tmp_path / "bar.h5"
    assert cli(["run", str(EXAMPLES / "sliding_bar.dat"), "--out", str(out), "--steps", "8",
                "--movie", str(tmp_path / "bar.gif"), "--plot", str(tmp_path / "bar.png"),
                "--columns", "x2.2", "--against", "x1.1"]) == 0
    assert (tmp_path / "bar.png").stat().st_size > 5000
    h5py = pytest.importorskip("h5py")
    with h5py.File(out) as f:
        x_p, y_q = f["x1.1"][:], f["x2.2"][:]
    assert len(x_p) == 9
    np.testing.assert_allclose(x_p**2 + y_q**2, 4.0, rtol=1e-12)  # the bar keeps its length


def test_a_missing_hdf5_writer_is_reported_before_the_run(tmp_path, capsys, monkeypatch):
    import flexmbd.io.outputs

    monkeypatch.setattr(flexmbd.io.outputs, "find_spec", lambda name: None)
    assert cli(["run", str(EXAMPLES / "sliding_bar.dat"), "--out", str(tmp_path / "r.h5")]) == 1
    captured = capsys.readouterr()
    assert "needs h5py" in captured.err and "analysis" not in captured.out


def test_run_options_are_checked(tmp_path, capsys):
    dat = str(EXAMPLES / "sliding_bar.dat")
    assert cli(["run", dat, "--out", str(tmp_path / "r.xlsx")]) == 2
    assert "--out: " in capsys.readouterr().err
    assert cli(["run", dat, "--steps", "0"]) == 2
    assert "--steps: must lie in 1 .. " in capsys.readouterr().err
    no_grid = tmp_path / "nogrid.dat"
    no_grid.write_text("PLTRUSS 1 1 2\nX 1 -0.8 0\nX 2 0 0.6\nFIX 1 2\nFIX 2 1\nINPUTX 1 1\n"
                       "END\nHALT\nINPUTX 1 1 -0.8 0.1\nEND\nEND\n")
    assert cli(["run", str(no_grid)]) == 2
    assert "no TIMESTEP" in capsys.readouterr().err
    assert cli(["run", str(no_grid), "--t-end", "1", "--steps", "4"]) == 0
    capsys.readouterr()
    assert cli(["run", dat, "--plot", str(tmp_path / "p.png"), "--columns", "x9.9"]) == 2
    assert "--columns: 'x9.9' is not a result column" in capsys.readouterr().err
    with pytest.raises(SystemExit) as done:
        cli(["run", "--help"])
    assert done.value.code == 0 and "TIMESTEP" in capsys.readouterr().out


def test_results_export_and_plot(tmp_path):
    result = fm.kinematic_analysis(fm.read_dat(EXAMPLES / "sliding_bar.dat").model,
                                   np.linspace(0, 0.5, 6))
    frame = result.to_pandas()
    assert list(frame.columns) == list(result.columns()) and len(frame) == 6
    with np.load(result.save(tmp_path / "r.npz")) as saved:
        np.testing.assert_array_equal(saved["xd2.2"], result["xd2.2"])
    with pytest.raises(fm.FlexmbdError, match=r"use \.csv"):
        result.save(tmp_path / "r.txt")
    with pytest.raises(fm.FlexmbdError, match="cannot write"):
        result.to_csv(tmp_path / "missing" / "r.csv")
    figure = result.plot(["x2.2"], against="x1.1", filename=tmp_path / "r.png")
    assert figure.axes[0].get_xlabel() == "x1.1 [m]" and (tmp_path / "r.png").stat().st_size > 5000
