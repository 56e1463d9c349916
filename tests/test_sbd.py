"""SPACAR's binary result files (.sbd, .sbm, .ltv): the byte layout, SPACAR's numbering,
the records of runs, ``flexmbd spacar MODE FILE`` and ``flexmbd compare``."""

import shutil
import struct
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import flexmbd as fm
from flexmbd.cli import main as cli
from flexmbd.errors import InputFileError
from flexmbd.io.dat import dat_from_text
from flexmbd.io.sbd import read_sbd, write_records
from flexmbd.io.sbd.records import generalized_loads, model_tables
from flexmbd.orientation import euler_forces

EXAMPLES = Path(__file__).parent.parent / "examples"
#: SPACAR's own numbers for a public model, reduced (data/spacar/SOURCE.md says whence)
SPACAR = Path(__file__).parent / "data" / "spacar"

#: an L-shaped spatial frame: a flexible beam clamped at node 1, a rigid beam on it, a
#: point mass and a load at its end, gravity; the load grows in 4 steps
FRAME = """\
X 1 0 0 0
X 3 0.2 0 0
X 5 0.2 0.1 0
BEAM 1 1 2 3 4 0 0 1
BEAM 2 3 4 5 6 0 0 1
DYNE 1 1 2 3 4 5 6
FIX 1
FIX 2
END
HALT
ESTIFF 1 2.1e6 20.0 30.0 40.0
EM 1 0.5
EM 2 2.0
XM 5 0.3
XF 5 0 0 -1.0
DELXF 5 0 0 -2.0
GRAVITY 0 0 -9.81
ITERSTEP 20 4 1e-10
END
END
"""


def _head(name: bytes, kind: int, size: int, rows: int, cols: int) -> bytes:
    return struct.pack("<4s4i", name, kind, size, rows, cols)


def _sample_bytes() -> bytes:
    """A file laid out by hand as SPACAR writes one: identification, an int32 table, a
    float64 table of 2 x 3 values (row after row), two steps of T and X (3 x 1)."""
    return b"".join([
        _head(b"SBD ", 3, 1, 15, 1), b"SBD version 0.0",
        _head(b"NX  ", 1, 4, 1, 1), struct.pack("<i", 3),
        _head(b"RXYZ", 2, 8, 2, 3), struct.pack("<6d", 1, 2, 3, 4, 5, 6),
        _head(b"TDEF", 0, 0, 2, 1),
        _head(b"T   ", 2, 8, 1, 1), _head(b"X   ", 2, 8, 3, 1),
        _head(b"TDAT", 0, 0, 0, 0),
        struct.pack("<4d", 0.0, 1.0, 2.0, 3.0), struct.pack("<4d", 0.5, 4.0, 5.0, 6.0)])


def test_the_layout_spacar_writes_is_read_record_by_record(tmp_path):
    path = tmp_path / "hand.sbd"
    path.write_bytes(_sample_bytes())
    f = read_sbd(path)
    assert (f.kind, f.version, f.n_steps) == ("SBD", "SBD version 0.0", 2)
    assert f["nx"].tolist() == [[3]] and f["NX"].dtype == np.int32
    assert f["RXYZ"].tolist() == [[1, 2, 3], [4, 5, 6]]
    assert f["x"].shape == (2, 3, 1)
    assert f.step("X", 2).ravel().tolist() == [4.0, 5.0, 6.0]
    assert f["T"][:, 0, 0].tolist() == [0.0, 0.5]
    # getfrsbf's names: any case, the first four characters count
    assert f["Rxyzq"] is f["RXYZ"]


def test_the_writer_lays_out_bytes_as_spacar(tmp_path):
    path = write_records(tmp_path / "w.sbd", "SBD",
                         {"NX": np.array([[3]], dtype=np.int64),
                          "RXYZ": np.arange(1.0, 7.0).reshape(2, 3)},
                         {"T": np.array([0.0, 0.5]).reshape(2, 1, 1),
                          "X": np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]).reshape(2, 3, 1)})
    assert path.read_bytes() == _sample_bytes()


@pytest.mark.parametrize("damage, where", [
    (lambda b: b[:40], "byte"),
    (lambda b: b"XYZ " + b[4:], "not a SPACAR binary file"),
    (lambda b: b[:39] + struct.pack("<i", 7) + b[43:], "type 7"),
    (lambda b: b[:-(8 * 3 + 9)], "TDEF announces 2 steps.*not one whole step"),
    (lambda b: b[:45], "ends inside a record head"),
    (lambda b: b"", "not a SPACAR binary file"),
])
def test_a_damaged_file_is_refused_at_its_byte(tmp_path, damage, where):
    path = tmp_path / "bad.sbd"
    path.write_bytes(damage(_sample_bytes()))
    with pytest.raises(InputFileError, match=where) as caught:
        read_sbd(path)
    assert str(path) in str(caught.value)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.data())
def test_any_damage_is_read_or_refused_never_a_crash(tmp_path_factory, data):
    """Bytes changed, cut or inserted anywhere in a file: read_sbd reads it (a file cut
    inside its steps: the whole ones) or refuses it with the file and the byte, whatever
    the damage claims (sizes, types, counts)."""
    raw = bytearray(_sample_bytes())
    for _ in range(data.draw(st.integers(1, 4))):
        at = data.draw(st.integers(0, len(raw)))
        edit = data.draw(st.sampled_from(["byte", "cut", "insert", "int"]))
        if edit == "byte" and at < len(raw):
            raw[at] = data.draw(st.integers(0, 255))
        elif edit == "cut":
            del raw[at:]
        elif edit == "insert":
            raw[at:at] = data.draw(st.binary(max_size=24))
        elif edit == "int" and at + 4 <= len(raw):
            raw[at:at + 4] = struct.pack("<i", data.draw(st.sampled_from(
                [-1, 0, 1, 2, 3, 7, 2**31 - 1, -2**31, 10**6])))
    path = tmp_path_factory.mktemp("fuzz") / "f.sbd"
    path.write_bytes(bytes(raw))
    try:
        with warnings.catch_warnings():   # a cut inside the steps reads the whole ones
            warnings.simplefilter("ignore", fm.ResultFileWarning)
            f = read_sbd(path)
    except InputFileError as error:
        assert str(path) in str(error) and "byte" in str(error)
    else:
        for name in f:
            assert f[name].ndim in (2, 3)


def test_a_missing_record_or_step_is_named():
    f = fm.SpacarFile(None, "SBD", "", {"NX": np.array([[1]])}, {"X": np.zeros((2, 1, 1))}, 2)
    with pytest.raises(KeyError, match=r"no record 'XD'.*NX, X"):
        f["xd"]
    with pytest.raises(KeyError, match=r"steps 1 \.\. 2"):
        f.step("X", 3)
    with pytest.raises(KeyError, match="stored once"):
        f.step("NX", 1)


def test_spacar_numbers_by_class_then_node(tmp_path):
    """The slider-crank's numbers by SPACAR's rule, worked out by hand: fixed x1.1, x1.2,
    x5.2; calculable x3.1, x3.2, x4.1, x5.1; the input x2.1."""
    model, _ = fm.read_dat(EXAMPLES / "slider_crank_rigid.dat")
    result = fm.kinematic_analysis(model, np.linspace(0.0, 0.02, 5))
    f = read_sbd(fm.write_sbd(tmp_path / "crank.sbd", result))
    assert f["LNP"].tolist() == [[1, 2, 0, 0], [8, 0, 0, 0], [4, 5, 0, 0], [6, 0, 0, 0],
                                 [7, 3, 0, 0]]
    assert f["NXP"].tolist() == [[3, 4, 1, 0, 0]] and f["NEP"].tolist() == [[4, 0, 0, 0, 0]]
    assert f["LE"].tolist() == [[1, 2, 0, 0, 0, 0, 0, 0], [3, 4, 0, 0, 0, 0, 0, 0]]
    assert f["LN"].tolist() == [[1, 2, 3, 0, 0, 0], [3, 4, 5, 0, 0, 0]]
    assert f["MODE"].tolist() == [[1]] and f["NDOF"].tolist() == [[1]]
    assert f["RL0"][:, 0] == pytest.approx([0.15, 0.30])
    # X in SPACAR's numbering: the crank pin x3.1 = 0.15 cos(150 t) is number 4
    assert f["X"][:, 3, 0] == pytest.approx(0.15 * np.cos(150.0 * result.t))
    # XD = DX qdot, the input turning at 150 rad/s
    np.testing.assert_allclose(f["XD"][:, :, 0], 150.0 * f["DX"][:, :, 0], atol=1e-12)
    np.testing.assert_allclose(f["ED"][:, :, 0], 150.0 * f["DE"][:, :, 0], atol=1e-12)


def test_static_records_carry_the_weight_and_the_loads(tmp_path):
    (tmp_path / "frame.dat").write_text(FRAME)
    assert cli(["spacar", "10", str(tmp_path / "frame")]) == 0
    f, m = read_sbd(tmp_path / "frame.sbd"), read_sbd(tmp_path / "frame.sbm")
    assert f.n_steps == m.n_steps == 5 and f["MODE"].tolist() == [[10]]
    lnp = f["LNP"]
    z1 = lnp[0, 2] - 1   # z of the clamped node 1
    # the support carries the weight (0.5*0.2 + 2*0.1 + 0.3 kg) and the load, -1 to -3 N
    weight = (0.5 * 0.2 + 2.0 * 0.1 + 0.3) * 9.81
    np.testing.assert_allclose(f["FXT"][:, z1, 0], weight + 1.0 + 2.0 * np.arange(5) / 4,
                               rtol=1e-10)
    z5 = lnp[4, 2] - 1
    np.testing.assert_allclose(f["FX"][:, z5, 0], -1.0 - 2.0 * np.arange(5) / 4)
    assert f["X"][0, lnp[2, 0] - 1, 0] == pytest.approx(0.2, abs=1e-3)   # x of node 3
    # a static state does not move, and every stored step is an equilibrium
    assert not np.any(f["XD"]) and not np.any(f["XDD"])
    # the .sbm holds M0, K0, ... over the 6 dynamic deformations of beam 1
    assert m["M0"].shape == (5, 6, 6) and m["nddof"].tolist() == [[6]]
    assert f["BIGD"].shape == (5, 15, 21)   # 2 beams and 3 Euler elements; 3 + 3 nodes
    # beam 2 (rigid) and the Euler elements have no stiffness
    assert f["STIF"].shape == (5, 12) and not np.any(f["STIF"][1:])


def test_euler_parameter_loads_do_the_work_of_the_moment():
    """SPACAR's loads on a rotational node are forces on its Euler parameters: their
    power on any rate of the parameters is the moment's power on the angular velocity,
    and the force is zero on the calculable parameter (here lam0)."""
    model, _ = dat_from_text(FRAME)
    node = model.nodes[2]
    rng = np.random.default_rng(4)
    lam = rng.normal(size=4)
    lam /= np.linalg.norm(lam)
    x = np.tile(model.x0, (1, 1))
    x[0, list(node.coordinates)] = lam
    moment = rng.normal(size=3)
    loads = np.zeros((1, model.n_coordinates))
    loads[0, list(node.coordinates[1:])] = moment
    force = generalized_loads(model, x, loads, reactions=True)[0, list(node.coordinates)]
    assert force[0] == pytest.approx(0.0, abs=1e-14)
    rate = rng.normal(size=4)
    rate -= (rate @ lam) * lam   # a rate that keeps |lam| = 1
    omega = fm.angular_velocity(lam, rate)
    assert force @ rate == pytest.approx(moment @ omega, rel=1e-12)
    assert euler_forces(lam, moment) @ rate == pytest.approx(moment @ omega, rel=1e-12)
    applied = generalized_loads(model, x, loads)[0, list(node.coordinates)]   # FX's form
    assert applied == pytest.approx(euler_forces(lam, moment), abs=1e-15)


def test_spacar_modes_run_and_write_their_files(tmp_path, capsys):
    for name in ("slider_crank_rigid.dat", "parallel_guide.dat"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    crank, guide = tmp_path / "slider_crank_rigid", tmp_path / "parallel_guide"
    assert cli(["spacar", "0", str(crank)]) == 0
    check = read_sbd(tmp_path / "slider_crank_rigid.sbd")
    assert check.n_steps == 1 and check["MODE"].tolist() == [[0]] and "BIGD" in check
    assert cli(["spacar", "-2", str(crank) + ".dat"]) == 0   # negative: as positive
    inverse = read_sbd(tmp_path / "slider_crank_rigid.sbd")
    assert inverse.n_steps == 73 and inverse["MODE"].tolist() == [[2]] and "SIG" in inverse
    assert cli(["spacar", "9", str(guide)]) == 0
    ltv, sbm = read_sbd(tmp_path / "parallel_guide.ltv"), read_sbd(tmp_path / "parallel_guide.sbm")
    # the state-space form of the linearized equations of the same step
    M, K = sbm["M0"][-1], sbm["K0"][-1] + sbm["N0"][-1] + sbm["G0"][-1]
    n = len(M)
    expected = -np.linalg.solve(M, K)
    np.testing.assert_allclose(ltv["A"][-1][n:, :n], expected, rtol=0,
                               atol=1e-9 * np.abs(expected).max())
    assert ltv["NU"].tolist() == [[1]] and ltv["NY"].tolist() == [[3]]   # INPUTF, 3 OUTX
    assert ltv["C"].shape == (11, 3, 2 * n)
    # mode 3 along the path of mode 10, with its loads: equilibria, so the free motion does
    # not accelerate (but for the static tolerance's residual; without the path's loads
    # FX the guide would accelerate at 3e4 m/s^2)
    assert cli(["spacar", "10", str(guide)]) == 0
    path = read_sbd(tmp_path / "parallel_guide.sbd")
    assert cli(["spacar", "3", str(guide)]) == 0
    linear = read_sbd(tmp_path / "parallel_guide.sbd")
    assert linear["MODE"].tolist() == [[3]]
    assert np.abs(linear["XDD"]).max() < 1e-3
    np.testing.assert_array_equal(linear["FX"], path["FX"])
    np.testing.assert_array_equal(linear["X"], path["X"])
    out = capsys.readouterr().out
    assert "parallel_guide.ltv" in out and "linearized along" in out


def test_spacar_mode_errors_are_one_line(tmp_path, capsys):
    shutil.copy(EXAMPLES / "sliding_bar.dat", tmp_path / "bar.dat")
    assert cli(["spacar", "5", str(tmp_path / "bar")]) == 2
    assert cli(["spacar", "3", str(tmp_path / "bar")]) == 1
    assert cli(["spacar", "1", str(tmp_path / "nothing")]) == 2
    (tmp_path / "junk.sbd").write_bytes(b"not a result file at all")
    assert cli(["compare", str(tmp_path / "junk.sbd"), str(tmp_path / "junk.sbd")]) == 1
    err = capsys.readouterr().err
    assert "modes 0, 1, 2, 3, 4, 7, 9, 10" in err
    assert "run mode 1, 2, 7 or 10 first" in err and "no input file" in err
    assert "not a SPACAR binary file" in err and "Traceback" not in err


def test_compare_agrees_with_a_run_and_flags_a_change(tmp_path, capsys):
    (tmp_path / "frame.dat").write_text(FRAME)
    assert cli(["spacar", "10", str(tmp_path / "frame")]) == 0
    assert cli(["compare", str(tmp_path / "frame.sbd"), str(tmp_path / "frame.dat")]) == 0
    assert cli(["compare", str(tmp_path / "frame.sbm"), str(tmp_path / "frame.dat")]) == 0
    (tmp_path / "stiffer.dat").write_text(FRAME.replace("ESTIFF 1 2.1e6 20.0", "ESTIFF 1 "
                                                                              "2.1e6 25.0"))
    assert cli(["compare", str(tmp_path / "frame.sbd"), str(tmp_path / "stiffer.dat")]) == 1
    out = capsys.readouterr().out
    assert "DIFFERS" in out and "records agree" in out


def test_run_static_and_modes_write_spacar_files(tmp_path):
    out = tmp_path / "crank.sbd"
    assert cli(["run", str(EXAMPLES / "slider_crank_rigid.dat"), "--mode", "inverse",
                "--out", str(out)]) == 0
    f = read_sbd(out)
    assert f["MODE"].tolist() == [[2]] and f.n_steps == 73
    (tmp_path / "frame.dat").write_text(FRAME)
    assert cli(["static", str(tmp_path / "frame.dat"), "--out", str(tmp_path / "s.sbd")]) == 0
    assert read_sbd(tmp_path / "s.sbd").n_steps == 5
    assert cli(["modes", str(tmp_path / "frame.dat"), "--out", str(tmp_path / "m.sbm")]) == 0
    assert read_sbd(tmp_path / "m.sbm")["K0"].shape == (5, 6, 6)


def test_spacar_own_output_is_reproduced(tmp_path):
    """SPACAR 2018's output for a public cross hinge (tests/data/spacar/SOURCE.md):
    positions to 1e-9 of their size at every step, frequencies to 2e-6, the numbering
    exactly, and along the stored path (mode 3) the stiffness G0 + N0 to 1e-8."""
    for name in ("crosshinge", "crosshinge_3"):
        shutil.copy(SPACAR / f"{name}.dat", tmp_path / f"{name}.dat")
    assert cli(["spacar", "10", str(tmp_path / "crosshinge")]) == 0
    with np.load(SPACAR / "crosshinge.npz") as stored:
        theirs = dict(stored)
    # mode 3 linearizes along the path SPACAR stored: its steps, positions, rates, loads
    write_records(tmp_path / "crosshinge_3.sbd", "SBD", {"LNP": theirs["crosshinge.sbd.LNP"]},
                  {r: theirs[f"crosshinge.sbd.{r}"] for r in ("T", "X", "XD", "FX")})
    assert cli(["spacar", "3", str(tmp_path / "crosshinge_3")]) == 0
    for name in ("crosshinge", "crosshinge_3"):
        for kind in ("sbd", "sbm"):
            mine = read_sbd(tmp_path / f"{name}.{kind}")
            records = {key.split(".")[2]: value for key, value in theirs.items()
                       if key.startswith(f"{name}.{kind}.")}
            for record in ("X", "E", "DX", "DE") if kind == "sbd" else ("M0", "K0"):
                expected = records[record]
                assert np.abs(mine[record] - expected).max() < \
                    1e-9 * np.abs(expected).max(), record
            for record in ("NX", "NE", "NDOF", "NDDO", "LNP", "LE", "LN", "IT"):
                if record in records:
                    assert np.array_equal(mine[record], records[record]), record
            if kind == "sbd":
                np.testing.assert_allclose(mine["STIF"], records["STIF"], rtol=1e-15)
        matrices = {r: theirs[f"{name}.sbm.{r}"] for r in ("M0", "K0", "N0", "G0")}
        mine = read_sbd(tmp_path / f"{name}.sbm")
        for k in range(len(matrices["M0"])):
            np.testing.assert_allclose(_squared_frequencies(mine, k),
                                       _squared_frequencies(matrices, k), rtol=2e-6)
            if name == "crosshinge_3":   # the leaves' weight turns with them: its load
                # stiffness is in G0 + N0 (without it they differ by 3.5e-3)
                expected = matrices["G0"][k] + matrices["N0"][k]
                ours = mine["G0"][k] + mine["N0"][k]
                assert np.abs(ours - expected).max() < 1e-8 * np.abs(expected).max()


def _squared_frequencies(sbm, k: int) -> np.ndarray:
    stiffness = sbm["K0"][k] + sbm["N0"][k] + sbm["G0"][k]
    return np.sort(np.linalg.eigvals(np.linalg.solve(sbm["M0"][k], stiffness)).real)


def test_warping_beams_have_spacars_tables():
    """SPACAR's output for four BEAMWs and six BEAMs (tests/data/spacar/SOURCE.md): the
    element types, frames, stiffness constants (with ``ECw/l0^5``), the zero ``RQ`` and
    the numbering, which puts the calculable warping deformations after all others."""
    model, _ = fm.read_dat(SPACAR / "beamw.dat")
    mine = model_tables(model, 9)
    with np.load(SPACAR / "beamw.npz") as stored:
        theirs = {key.split(".")[2]: stored[key] for key in stored.files
                  if key.startswith("beamw.sbd.")}
    for record in ("NXP", "NEP", "LE", "IT"):
        assert np.array_equal(mine[record], theirs[record]), record
    assert mine["RQ"].shape == theirs["RQ"].shape and not np.any(theirs["RQ"])
    for record in ("RL0", "RXYZ"):
        np.testing.assert_allclose(mine[record], theirs[record], rtol=0, atol=1e-10)
    np.testing.assert_allclose(mine["STIF"], theirs["STIF"], rtol=1e-12)


def test_a_moment_is_stored_as_spacar_stores_it(tmp_path):
    """SPACAR's ``FX`` of a moment on a rotational node is ``2 E(lam)^T M`` on the four
    Euler parameters (tests/data/spacar/SOURCE.md, ``moment``: 24 beams, 4 load steps)."""
    shutil.copy(SPACAR / "moment.dat", tmp_path / "moment.dat")
    assert cli(["spacar", "10", str(tmp_path / "moment")]) == 0
    mine = read_sbd(tmp_path / "moment.sbd")
    with np.load(SPACAR / "moment.npz") as stored:
        theirs = {key.split(".")[2]: stored[key] for key in stored.files}
    assert np.array_equal(mine["LNP"], theirs["LNP"])
    for record in ("X", "FX", "FXT"):
        scale = np.abs(theirs[record]).max()
        assert np.abs(mine[record] - theirs[record]).max() < 1e-9 * scale, record


def test_a_file_cut_inside_its_steps_reads_the_whole_ones(tmp_path):
    """A run stopped while writing: the steps written whole are read, with a warning that
    names the file and the step it ends in."""
    whole = _sample_bytes()
    full = tmp_path / "full.sbd"
    full.write_bytes(whole)
    expected = read_sbd(full)
    cut = tmp_path / "cut.sbd"
    cut.write_bytes(whole[:-9])
    with pytest.warns(fm.ResultFileWarning, match=r"cut\.sbd: TDEF announces 2 steps, the "
                                                  r"file ends inside step 2; read steps 1 \.\. 1"):
        f = read_sbd(cut)
    assert f.n_steps == 1
    for name in expected.steps:
        assert np.array_equal(f[name], expected[name][:1])
    for name in expected.tables:
        assert np.array_equal(f[name], expected[name])


CLAMPED_CHAIN = """\
PLBEAM 1 1 2 3 4
PLBEAM 2 3 4 5 6
PLBEAM 3 5 6 7 8
X 1 0 0
X 3 1 0
X 5 2 0
X 7 3 0
FIX 1
FIX 2
FIX 7
FIX 8
END
END
"""


def test_mode_0_writes_d_x_when_the_count_does_not_close(tmp_path, capsys):
    """A chain of three rigid beams clamped at both ends is three times over-constrained:
    mode 0 says so and still writes the initial configuration with ``BIGD``, from which
    the over-constraints are found as SPACAR's tools find them (an SVD of the rows of the
    fixed deformations against the calculable coordinates)."""
    (tmp_path / "chain.dat").write_text(CLAMPED_CHAIN)
    assert cli(["spacar", "0", str(tmp_path / "chain")]) == 0   # the check completes
    assert "the degree-of-freedom count does not close" in capsys.readouterr().out
    f = read_sbd(tmp_path / "chain.sbd")
    nep, nxp, D = f["NEP"][0], f["NXP"][0], f["BIGD"][0]
    assert "DX" not in f and D.shape == (9, 12)
    D_cc = D[:nep[0] + nep[2] + nep[3], nxp[0]:nxp[0] + nxp[1]]
    s = np.linalg.svd(D_cc, compute_uv=False)
    assert D_cc.shape == (9, 6) and int(np.sum(s > 1e-8 * s[0])) == 6   # 9 - 6 = 3 over
    # beam 1's elongation: -1 on node 1's x (fixed, first), +1 on node 3's x (calculable)
    assert D[0, 0] == pytest.approx(-1.0) and D[0, nxp[0]] == pytest.approx(1.0)


def test_mode_9_writes_spacars_records(tmp_path):
    """SPACAR's mode 9 of the warping-beam model (tests/data/spacar/SOURCE.md): one step
    (``ITERSTEP .. 1 1 0``: the equilibrium of loads without increments), ``.sbm`` with
    ``NDOF NKDO NNOM`` and the inputs' generalized forces ``B0``, ``.ltv`` with ``DFT`` 1
    and ``D``, ``NNOM NYS X0 U0 Y0``. SPACAR stopped its Newton iteration with the free
    warping coordinates 2.5e-5 from equilibrium (its accelerations there 2e6), which
    moves the input matrices by 4e-7 of their size."""
    shutil.copy(SPACAR / "beamw.dat", tmp_path / "beamw.dat")
    assert cli(["spacar", "9", str(tmp_path / "beamw")]) == 0
    with np.load(SPACAR / "beamw.npz") as stored:
        theirs = {key.removeprefix("beamw."): stored[key] for key in stored.files}
    sbd = read_sbd(tmp_path / "beamw.sbd")
    assert sbd.n_steps == 1
    for kind, exact, close in (("sbm", ("NDOF", "NKDO", "NNOM"), ("B0",)),
                               ("ltv", ("NX", "NU", "NY", "NNOM", "NYS", "DFT", "X0", "D",
                                        "U0"), ("C", "Y0"))):
        mine = read_sbd(tmp_path / f"beamw.{kind}")
        assert mine.n_steps == 1
        for record in exact:
            assert np.array_equal(mine[record], theirs[f"{kind}.{record}"]), record
        for record in close:
            expected = theirs[f"{kind}.{record}"]
            assert np.abs(mine[record] - expected).max() < 1e-6 * np.abs(expected).max(), \
                record
