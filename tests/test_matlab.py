"""flexmbd's MATLAB/Octave face (``matlab/``): SPACAR's calling forms on flexmbd.

``flexmbd stressbeam`` is tested everywhere. The MATLAB files run in GNU Octave where it
is installed (with ``mkoctfile`` to build the MEX gateway), and are skipped, saying so,
where it is not. SPACAR Light's own ``spacarlight.m`` (not part of flexmbd) runs when the
environment variable ``SPACARLIGHT`` names a folder holding SPACAR Light 1.38's
``spacarlight.m`` and ``spacarexample.m``.
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from flexmbd.analysis.modes import vibration_modes
from flexmbd.analysis.statics import file_equilibrium
from flexmbd.cli import main as cli
from flexmbd.io.dat import read_dat
from flexmbd.io.sbd import read_sbd

HERE = Path(__file__).parent
MATLAB = HERE.parent / "matlab"
EXAMPLES = HERE.parent / "examples"

#: a steel-like cantilever (20 x 1 mm, 0.1 m) with a small tip force across its thickness
CANTILEVER = """\
X 1 0 0 0
X 3 0.1 0 0
BEAM 1 1 2 3 4 0 1 0
DYNE 1 1 2 3 4 5 6
FIX 1
FIX 2
END
HALT
ESTIFF 1 4.2e6 0.5 0.35 140
XF 3 0 0 1e-3
ITERSTEP 20 1 1e-14
END
END
"""


def test_stressbeam_gives_the_cantilevers_bending_and_shear_stress(tmp_path, capsys):
    """At the clamp ``6 F L / (w t^2)`` = 3e4 Pa, at the tip only the shear, ``sqrt(3) 1.5 F
    / (w t)`` (von Mises of the largest shear stress)."""
    (tmp_path / "cant.dat").write_text(CANTILEVER)
    assert cli(["spacar", "7", str(tmp_path / "cant")]) == 0
    capsys.readouterr()
    assert cli(["stressbeam", str(tmp_path / "cant.sbd"), "2", "--beam", "1", "rect", "0.02",
                "0.001"]) == 0
    element, p, q = capsys.readouterr().out.split()
    assert int(element) == 1
    assert float(p) == pytest.approx(6 * 1e-3 * 0.1 / (0.02 * 0.001**2), rel=1e-9)
    assert float(q) == pytest.approx(np.sqrt(3) * 1.5 * 1e-3 / (0.02 * 0.001), rel=1e-9)


@pytest.mark.parametrize("spec, words", [(["1", "tri", "1"], "ELEMENT rect WIDTH THICKNESS"),
                                         (["1", "rect", "0.02"], "ELEMENT rect"),
                                         (["9", "circ", "0.01"], "element 9 is not a spatial")])
def test_stressbeam_refuses_a_bad_beam_by_name(tmp_path, capsys, spec, words):
    (tmp_path / "cant.dat").write_text(CANTILEVER)
    assert cli(["spacar", "7", str(tmp_path / "cant")]) == 0
    assert cli(["stressbeam", str(tmp_path / "cant"), "2", "--beam", *spec]) == 2
    assert words in capsys.readouterr().err


# --- in GNU Octave -----------------------------------------------------------------------------
def _flexmbd_program() -> str | None:
    here = Path(sys.executable).parent / "flexmbd"
    return str(here) if here.is_file() else shutil.which("flexmbd")


@pytest.fixture(scope="module")
def octave(tmp_path_factory):
    """A folder with the MEX gateway built, and a function that runs Octave code there with
    matlab/ on the path."""
    if not (shutil.which("octave") and shutil.which("mkoctfile")):
        pytest.skip("GNU Octave with mkoctfile is not installed (apt-get install octave "
                    "liboctave-dev): the MATLAB face is not run here")
    program = _flexmbd_program()
    if program is None:
        pytest.skip("the flexmbd command is not installed beside this Python")
    folder = tmp_path_factory.mktemp("octave")
    built = subprocess.run(["mkoctfile", "--mex", str(MATLAB / "spacar.c"), "-o",
                            str(folder / "spacar.mex")], capture_output=True, text=True,
                           timeout=300)
    assert built.returncode == 0, built.stderr
    env = {**os.environ, "FLEXMBD": program}

    def run(code: str, cwd: Path = folder) -> str:
        script = (f"addpath('{MATLAB}'); addpath('{folder}'); "
                  f"set(0, 'defaultfigurevisible', 'off'); {code}")
        done = subprocess.run(["octave", "--no-gui", "--quiet", "--no-init-file", "--eval",
                               script], cwd=cwd, env=env, capture_output=True, text=True,
                              timeout=600)
        assert done.returncode == 0, done.stdout + done.stderr
        return done.stdout

    run.folder = folder
    return run


def _numbers(text: str) -> np.ndarray:
    return np.array([float(word) for word in text.split()])


def test_the_mex_gateway_runs_flexmbd_as_spacar_does(octave, tmp_path):
    """spacar(mode, file) writes the files `flexmbd spacar` writes, byte for byte; a mode
    flexmbd does not run is an error naming the exit status; exist() says 3 (a MEX file),
    which SPACAR Light checks."""
    for where in (tmp_path / "a", tmp_path / "b"):
        where.mkdir()
        shutil.copy(HERE / "data" / "spacar" / "crosshinge.dat", where)
    out = octave("printf('%d\\n', exist('spacar', 'file')); s = spacar(10, 'crosshinge'); "
                 "printf('%d\\n', s); try, spacar(5, 'crosshinge'); catch e, "
                 "printf('%s\\n', e.message); end", cwd=tmp_path / "a")
    assert out.splitlines()[0] == "3"
    assert "exit status 2" in out
    assert cli(["spacar", "10", str(tmp_path / "b" / "crosshinge")]) == 0
    for suffix in (".sbd", ".sbm"):
        assert (tmp_path / "a" / f"crosshinge{suffix}").read_bytes() == \
            (tmp_path / "b" / f"crosshinge{suffix}").read_bytes()


def test_getfrsbf_reads_what_read_sbd_reads(octave, tmp_path):
    """Tables as stored; a per-step record for every step one row per step in MATLAB's
    column order, one step as its matrix; TDEF the step count; a missing record 'ID not
    found'."""
    shutil.copy(HERE / "data" / "spacar" / "crosshinge.dat", tmp_path)
    assert cli(["spacar", "10", str(tmp_path / "crosshinge")]) == 0
    f = read_sbd(tmp_path / "crosshinge.sbd")
    out = octave("f = 'crosshinge.sbd'; "
                 "printf('%d\\n', getfrsbf(f, 'tdef')); "
                 "l = getfrsbf(f, 'lnp'); printf('%d %d\\n', size(l)); printf('%d ', l.'); "
                 "printf('\\n'); x = getfrsbf(f, 'x'); printf('%d %d\\n', size(x)); "
                 "printf('%.17g ', x(7, :)); printf('\\n'); d = getfrsbf(f, 'DX', 3); "
                 "printf('%d %d\\n', size(d)); printf('%.17g ', d.'); printf('\\n'); "
                 "a = getfrsbf(f, 'dx'); printf('%.17g ', reshape(a(3, :), size(d, 1), [])"
                 ".'); printf('\\n'); try, getfrsbf(f, 'zzz'); catch e, "
                 "printf('%s\\n', e.message); end", cwd=tmp_path)
    lines = out.splitlines()
    assert int(lines[0]) == f.n_steps == 10
    assert [int(v) for v in lines[1].split()] == list(f["LNP"].shape)
    assert np.array_equal(_numbers(lines[2]).reshape(f["LNP"].shape), f["LNP"])
    assert [int(v) for v in lines[3].split()] == [10, f["X"].shape[1]]
    assert np.array_equal(_numbers(lines[4]), f["X"][6, :, 0])
    assert [int(v) for v in lines[5].split()] == list(f["DX"].shape[1:])
    assert np.array_equal(_numbers(lines[6]).reshape(f["DX"].shape[1:]), f["DX"][2])
    assert np.array_equal(_numbers(lines[7]).reshape(f["DX"].shape[1:]), f["DX"][2])
    assert lines[8] == "ID not found"


def test_getss_and_stressbeam_give_flexmbds_numbers(octave, tmp_path):
    """getss: the .ltv's A, B, C, D of a step; stressbeam: `flexmbd stressbeam`'s
    stresses, in MPa."""
    shutil.copy(EXAMPLES / "parallel_guide.dat", tmp_path)
    assert cli(["spacar", "9", str(tmp_path / "parallel_guide")]) == 0
    ltv = read_sbd(tmp_path / "parallel_guide.ltv")
    out = octave("[A, B, C, D] = getss('parallel_guide', 4); for M = {A, B, C, D}, "
                 "printf('%.17g ', M{1}.'); printf('\\n'); end; s = getss('parallel_guide"
                 ".ltv', 4); printf('%d\\n', isequal(s.a, A) || isequal(s.A, A))", cwd=tmp_path)
    lines = out.splitlines()
    for line, name in zip(lines, "ABCD", strict=False):
        assert np.array_equal(_numbers(line), ltv[name][3].ravel()), name
    assert lines[4] == "1"
    (tmp_path / "cant.dat").write_text(CANTILEVER)
    assert cli(["spacar", "7", str(tmp_path / "cant")]) == 0
    out = octave("s.CrossSection = 'rect'; s.Dimensions = [0.02 0.001]; "
                 "[st, el, lg, ex] = stressbeam('cant.sbd', 1, 2, struct(), s); "
                 "printf('%.17g %.17g %.17g\\n', st, ex.max)", cwd=tmp_path)
    p, q, largest = _numbers(out)
    assert p == pytest.approx(6 * 1e-3 * 0.1 / (0.02 * 0.001**2) / 1e6, rel=1e-9)
    assert largest == p and q < p


# --- SPACAR Light's own code ---------------------------------------------------------------------
def _patched_spacar_light(source: Path, target: Path) -> None:
    """SPACAR Light 1.38 with the platform patches Octave on Linux needs (docs: SPACAR
    files, the MATLAB face): its user name is set on Windows and macOS only; Octave has no
    ``datetime``; the example runs silent (SPACAR Light's figure handling after spavisual
    crashes Octave 7)."""
    text = (source / "spacarlight.m").read_text()
    text = text.replace("        elseif ismac\n            username = getenv('USER');",
                        "        else\n            username = getenv('USER');")
    text = text.replace("datestr(datetime)", "datestr(now)")
    (target / "spacarlight.m").write_text(text)
    example = (source / "spacarexample.m").read_text().replace("\nclc\n", "\n")
    example = example.replace("% opt.silent      = true;", "opt.silent      = true;")
    (target / "spacarexample.m").write_text(example)


def test_spacar_lights_own_cross_hinge_runs_on_flexmbd(octave, tmp_path):
    """SPACAR Light 1.38's shipped example (a cross hinge with warping, 10 load steps),
    run by its own spacarlight.m through matlab/, equals flexmbd.light's run of the same
    model (frequencies, the stage's position and the largest stress at every step) to the
    precision of the file SPACAR Light writes, and flexmbd's analysis of that file to
    1e-8."""
    source = os.environ.get("SPACARLIGHT")
    if not source or not (Path(source) / "spacarlight.m").is_file():
        pytest.skip("set SPACARLIGHT to a folder with SPACAR Light 1.38's spacarlight.m and "
                    "spacarexample.m (precision-utwente/spalight) to run its own code")
    _patched_spacar_light(Path(source), tmp_path)
    out = octave("spacarexample; for i = 1:10, printf('%.17g ', out.step(i).freq(1:3), "
                 "out.step(i).node(3).p, out.step(i).stressmax); printf('\\n'); end",
                 cwd=tmp_path)
    theirs = np.array([_numbers(line) for line in out.splitlines()[-10:]])
    from flexmbd import light

    # SPACAR Light writes the positions of the nodes between a leaf's beams with six
    # decimals (0.033333 for 0.1 / 3): 1e-5 of their place, which flexmbd.light keeps exact
    ours = light.run(*_light_example())
    for i in range(10):
        step = ours.step[i + 1]
        expected = np.concatenate([step.freq[:3], ours.node[3].p[:, i], [step.stressmax]])
        np.testing.assert_allclose(theirs[i], expected, rtol=3e-5, atol=1e-9)
    # the model SPACAR Light wrote, analysed by flexmbd itself: its post-processing
    # (frequencies from the .sbm, the stage's position from the .sbd) to 1e-8
    model, settings = read_dat(tmp_path / "crosshinge.dat")
    statics = file_equilibrium(model, settings)
    for i in range(10):
        frequencies = vibration_modes(statics.linearization(i), 3).frequencies
        np.testing.assert_allclose(theirs[i][:3], frequencies, rtol=1e-7)   # eig vs ours
        np.testing.assert_allclose(theirs[i][3:6], statics["x7.1"][i:i + 1].tolist() +
                                   statics["x7.2"][i:i + 1].tolist() +
                                   statics["x7.3"][i:i + 1].tolist(), rtol=1e-8, atol=1e-12)


def _light_example():
    """SPACAR Light 1.38's spacarexample.m, in flexmbd.light's form."""
    nodes = np.array([[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.1, 0, 0]], dtype=float)
    elements = np.array([[1, 3], [2, 3], [2, 4]])
    nprops = {1: {"fix": True}, 3: {"force": [0, 1, 0], "moment_initial": [0, 0, -0.025],
                                    "moment": [0, 0, 0.05], "mass": 0.1}, 4: {"fix": True}}
    eprops = [{"elems": [1, 3], "emod": 210e9, "smod": 70e9, "dens": 7800, "cshape": "rect",
               "dim": [50e-3, 0.2e-3], "orien": [0, 0, 1], "nbeams": 3,
               "flex": list(range(1, 7)), "warping": True},
              {"elems": [2], "dens": 3000, "cshape": "rect", "dim": [50e-3, 10e-3],
               "orien": [0, 0, 1], "nbeams": 1, "warping": True}]
    return nodes, elements, nprops, eprops, {"gravity": [0, 0, -9.81], "silent": True}
