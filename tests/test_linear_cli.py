"""``flexmbd static | modes | buckling | statespace`` on a SPACAR file, and the .dat
keywords of the linear analyses (DELXF, DELINPX, INPUTF, OUTX, OUTXP)."""

from __future__ import annotations

import csv

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.cli import main
from flexmbd.io.dat.writer import dat_text

#: a cantilever column of two second-order beams: EI = 2, L = 1, axial tip load 1 N plus
#: a transverse increment of 0.5 N over 4 load steps
COLUMN = """\
PLBEAM2 1 1 2 3 4
PLBEAM2 2 3 4 5 6
X 1 0 0
X 3 0.5 0
X 5 1.0 0
FIX 1
FIX 2
DYNE 1
DYNE 2
END
HALT
ESTIFF 1 1e6 2
ESTIFF 2 1e6 2
EM 1 0.5
EM 2 0.5
XF 5 -1 0
DELXF 5 0 -0.5
ITERSTEP 10 4 1e-9
INPUTF 5 2
OUTX 5 2
OUTXP 5 2
END
END
"""


@pytest.fixture
def column(tmp_path):
    path = tmp_path / "column.dat"
    path.write_text(COLUMN)
    return path


def test_the_linear_keywords_are_read_and_written_back(column, tmp_path):
    model, settings = fm.read_dat(column)
    assert dict(settings.load_increment) == {"x5.1": 0.0, "x5.2": -0.5}
    assert settings.load_steps == 4
    assert settings.force_inputs == ("x5.2",) and settings.outputs == ("x5.2",)
    assert settings.rate_outputs == ("x5.2",)
    again = tmp_path / "again.dat"
    again.write_text(dat_text(model, settings))
    assert fm.read_dat(again).settings == settings


def test_delinpx_must_name_an_input(tmp_path):
    path = tmp_path / "bad.dat"
    path.write_text(COLUMN.replace("DELXF 5 0 -0.5", "DELINPX 5 2 0.1"))
    with pytest.raises(fm.InputFileError, match=r"bad.dat:17: DELINPX.*not an input"):
        fm.read_dat(path)


def test_static_writes_one_row_per_load_step(column, tmp_path, capsys):
    out = tmp_path / "static.csv"
    assert main(["static", str(column), "--out", str(out), "--plot",
                 str(tmp_path / "s.png")]) == 0
    rows = list(csv.DictReader(out.read_text().splitlines()))
    assert [float(r["load"]) for r in rows] == [0.0, 0.25, 0.5, 0.75, 1.0]
    # nearly linear in the small transverse load: the tip moves like P L^3 / 3 EI,
    # magnified by the axial compression (1 N of a buckling load of about 4.9 N)
    tip = float(rows[-1]["x5.2"])
    assert -0.5 / 6 * 1.5 < tip < -0.5 / 6
    assert "converged 5 load steps" in capsys.readouterr().out


def test_static_says_why_a_cell_of_its_table_is_empty(column, capsys):
    """More modes than the column has degrees of freedom: the missing ones are NaN and
    the command says why."""
    model, _ = fm.read_dat(column)
    asked = len(model.dynamic_q_labels) + 2
    assert main(["static", str(column), "--modes", str(asked)]) == 0
    out = capsys.readouterr().out
    assert f"note: f{asked - 1}..f{asked} at step 0 (load 0): the state has " in out


def test_modes_buckling_and_statespace_print_tables_and_write_files(column, tmp_path, capsys):
    assert main(["modes", str(column), "--count", "3", "--out", str(tmp_path / "m.csv"),
                 "--plot", str(tmp_path / "m.png")]) == 0
    table = (tmp_path / "m.csv").read_text().splitlines()
    frequencies = [float(r["frequency"]) for r in csv.DictReader(table)]
    model, _ = fm.read_dat(column)
    statics = fm.static_equilibrium(model, load_increment={"x5.2": -0.5}, steps=4)
    expected = fm.vibration_modes(statics.linearization(), 3).frequencies
    np.testing.assert_allclose(frequencies, expected, rtol=1e-6)
    assert (tmp_path / "m.png").stat().st_size > 0
    assert main(["buckling", str(column), "--count", "2", "--plot",
                 str(tmp_path / "b.png")]) == 0
    assert "load factor" in capsys.readouterr().out
    assert main(["statespace", str(column), "--out", str(tmp_path / "ss.npz"), "--bode",
                 str(tmp_path / "bode.png"), "--damping", "0.01"]) == 0
    with np.load(tmp_path / "ss.npz") as matrices:
        assert matrices["A"].shape == (12, 12)
        assert list(matrices["outputs"]) == ["x5.2", "xd5.2"]


def test_statespace_without_inputs_is_a_usage_error(tmp_path, capsys):
    path = tmp_path / "plain.dat"
    path.write_text(COLUMN.replace("INPUTF 5 2\n", ""))
    assert main(["statespace", str(path)]) == 2
    assert "INPUTF" in capsys.readouterr().err


def test_a_bad_output_name_fails_before_any_work(column, capsys):
    assert main(["modes", str(column), "--out", "modes.xlsx"]) == 2
    assert "--out" in capsys.readouterr().err


def test_modes_along_the_motion_of_a_file(capsys, tmp_path):
    path = "examples/slider_crank_flex.dat"
    out = tmp_path / "along.csv"
    assert main(["modes", path, "--along", "--count", "2", "--out", str(out)]) == 0
    rows = list(csv.DictReader(out.read_text().splitlines()))
    first = np.array([float(r["f1"]) for r in rows])
    assert np.all(first > 100) and np.ptp(first) > 0
