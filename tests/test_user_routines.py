"""SPACAR's user routines, USERSIG and USERINP, as Python modules beside the input file:
each is held against the file's own way of saying the same thing."""

import textwrap
from pathlib import Path

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.analysis.runs import analyse
from flexmbd.cli import main as cli
from flexmbd.errors import InputFileError

EXAMPLES = Path(__file__).parent.parent / "examples"

#: a planar pendulum: a massless rigid bar from a fixed pivot, a point mass at its tip,
#: released from the horizontal; {loads} is gravity or the routine that replaces it
PENDULUM = """\
PLRBEAM 1 1 2 3
X 1 0 0
X 3 0.5 0
FIX 1
DYNX 2 1
END
HALT
XM 3 2.0
{loads}
TIMESTEP 0.4 8
END
END
"""

#: a mass on a spring (a planar truss along x whose elongation is dynamic) and a load;
#: {law} is the spring's ESTIFF or the routine that gives its stress
SPRING = """\
PLTRUSS 1 1 2
X 1 0 0
X 2 1 0
FIX 1
FIX 2 2
DYNE 1 1
END
HALT
XM 2 0.5
XF 2 3.0 0
{law}
TIMESTEP 0.3 6
END
END
"""


def _run(tmp_path: Path, name: str, text: str, routines: dict[str, str], mode="dynamic"):
    for routine, body in routines.items():
        (tmp_path / f"{routine}.py").write_text(textwrap.dedent(body))
    path = tmp_path / f"{name}.dat"
    path.write_text(text)
    model, settings = fm.read_dat(path)
    return analyse(model, settings, mode, settings.output_times())


def test_usersig_loads_act_as_the_file_s_own(tmp_path):
    """The routine's weight [node, direction, load] on the tip moves the pendulum as
    GRAVITY does; its arguments are SPACAR's (x numbered by class, lnp 1-based)."""
    reference = _run(tmp_path, "gravity", PENDULUM.format(loads="GRAVITY 0 -9.81"), {})
    routine = """\
        import numpy as np

        def WEIGHT(t, ne, le, e, ep, nx, lnp, x, xp):
            tip = x[lnp[2, 0:2] - 1]          # x(lnp(3, 1:2)) in MATLAB
            assert nx == 5 and ne == 2 and tip.shape == (2,) and np.isfinite(tip).all()
            f = [[3, 2, -2.0 * 9.81]]
            return t, [], f
        """
    user = _run(tmp_path, "user", PENDULUM.format(loads="USERSIG WEIGHT"), {"WEIGHT": routine})
    assert user.success
    np.testing.assert_allclose(user["x3.2"], reference["x3.2"], atol=1e-12)
    assert reference["x3.2"][-1] < -0.3   # it did swing down


def test_usersig_stresses_load_the_nodes_as_the_element_s_own(tmp_path):
    """A spring law given as the routine's stress k e moves the mass as ESTIFF k does:
    the stress loads the nodes with -D^T sig."""
    reference = _run(tmp_path, "estiff", SPRING.format(law="ESTIFF 1 40.0"), {})
    routine = """\
        def SPRINGLAW(t, ne, le, e, ep, nx, lnp, x, xp):
            elongation = e[le[0, 0] - 1]      # e(le(1, 1)): element 1, deformation 1
            return t, [[1, 1, 40.0 * elongation]], []
        """
    user = _run(tmp_path, "law", SPRING.format(law="USERSIG SPRINGLAW"), {"SPRINGLAW": routine})
    np.testing.assert_allclose(user["x2.1"], reference["x2.1"], atol=1e-12)
    assert np.ptp(reference["x2.1"]) > 0.05   # the mass moved


def test_usersig_euler_parameter_forces_are_the_moment(tmp_path):
    """On a spatial rotational node the routine gives forces on the Euler parameters,
    2 E(lam)^T M as the catheter routine of FlexibleInstrumentSimulation builds them
    from 2 [q0 -q'; q q0 I - q~] [0; M]: they turn a flexible cantilever as XF's moment."""
    cantilever = """\
        X 1 0 0 0
        X 3 0.3 0 0
        BEAM 1 1 2 3 4 0 0 1
        DYNE 1 2 3 4 5 6
        FIX 1
        FIX 2
        END
        HALT
        ESTIFF 1 1e5 2.0 3.0 4.0
        EM 1 0.2 1e-3 1e-3 1e-3
        {load}
        TIMESTEP 0.02 4
        END
        END
        """
    moment = "0.3 -0.2 0.5"
    reference = _run(tmp_path, "xf", textwrap.dedent(cantilever).format(
        load=f"XF 4 {moment}"), {})
    routine = f"""\
        import numpy as np

        def TORQUE(t, ne, le, e, ep, nx, lnp, x, xp):
            q = x[lnp[3, :] - 1]              # Euler parameters of node 4
            qt = np.array([[0, -q[3], q[2]], [q[3], 0, -q[1]], [-q[2], q[1], 0]])
            Q = np.block([[q[:1, None], -q[None, 1:]], [q[1:, None], q[0] * np.eye(3) - qt]])
            T = 2 * Q @ np.concatenate([[0.0], [{moment.replace(" ", ", ")}]])
            return t, [], [[4, k + 1, T[k]] for k in range(4)]
        """
    user = _run(tmp_path, "user", textwrap.dedent(cantilever).format(load="USERSIG TORQUE"),
                {"TORQUE": routine})
    for label in ("x4.2", "x4.3", "x4.4", "x3.2", "x3.3"):
        np.testing.assert_allclose(user[label], reference[label], atol=1e-10, err_msg=label)
    assert np.abs(reference["x4.4"]).max() > 1e-4


def test_userinp_gives_the_input_motion_as_the_file_s_law(tmp_path):
    """The slider-crank driven by the routine's rows [node, direction, value, rate,
    acceleration] needs the torque it needs with the file's INPUTX 2 1 0 150 0."""
    text = (EXAMPLES / "slider_crank_rigid.dat").read_text()
    reference = _run(tmp_path, "crank", text, {}, mode="inverse")
    routine = """\
        def CRANK(t, flag):
            assert flag == 0
            return t, [], [2, 1, 150.0 * t, 150.0, 0.0]
        """
    user = _run(tmp_path, "user", text.replace("TIMESTEP", "USERINP CRANK\nTIMESTEP"),
                {"CRANK": routine}, mode="inverse")
    np.testing.assert_allclose(user["f2.1"], reference["f2.1"], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(user["x5.1"], reference["x5.1"], atol=1e-13)


def test_routines_are_found_beside_the_file_or_named(tmp_path, capsys):
    text = PENDULUM.format(loads="USERSIG CONTACT")
    (tmp_path / "p.dat").write_text(text)
    with pytest.raises(InputFileError, match=r"p\.dat:9: USERSIG: no CONTACT\.py in"):
        fm.read_dat(tmp_path / "p.dat")
    (tmp_path / "CONTACT.m").write_text("function [time, sig, f] = CONTACT(t)\n")
    with pytest.raises(InputFileError, match=r"CONTACT\.m is there: .* port it to CONTACT\.py"):
        fm.read_dat(tmp_path / "p.dat")
    (tmp_path / "q.dat").write_text(PENDULUM.format(loads="USERSIG ../evil"))
    with pytest.raises(InputFileError, match="must be a routine name"):
        fm.read_dat(tmp_path / "q.dat")


@pytest.mark.parametrize("body, message", [
    ("def BAD(t, ne, le, e, ep, nx, lnp, x, xp):\n    raise ValueError('oops')\n",
     "ValueError: oops"),
    ("def BAD(t, ne, le, e, ep, nx, lnp, x, xp):\n    return t, [], [[3, 2]]\n",
     "rows of 3 values"),
    ("def BAD(t, ne, le, e, ep, nx, lnp, x, xp):\n    return t, [], [[9, 1, 1.0]]\n",
     "node 9 direction 1"),
    ("def OTHER():\n    pass\n", "defines no function BAD"),
    ("import nosuchmodule\n", "ModuleNotFoundError"),
])
def test_a_failing_routine_is_named_and_the_run_keeps_its_work(tmp_path, capsys, body,
                                                                 message):
    (tmp_path / "BAD.py").write_text(body)
    (tmp_path / "p.dat").write_text(PENDULUM.format(loads="USERSIG BAD"))
    code = cli(["run", str(tmp_path / "p.dat"), "--out", str(tmp_path / "p.csv")])
    captured = capsys.readouterr()
    assert code == 1 and message in captured.out + captured.err
    assert "Traceback" not in captured.err


def test_static_analyses_refuse_routines_of_time(tmp_path, capsys):
    (tmp_path / "WEIGHT.py").write_text("def WEIGHT(*args):\n    return 0, [], []\n")
    (tmp_path / "p.dat").write_text(PENDULUM.format(loads="USERSIG WEIGHT"))
    assert cli(["static", str(tmp_path / "p.dat")]) == 2
    assert cli(["spacar", "10", str(tmp_path / "p")]) == 2
    assert "routine of time" in capsys.readouterr().err


def test_routines_are_written_back(tmp_path):
    (tmp_path / "WEIGHT.py").write_text("def WEIGHT(*args):\n    return 0, [], []\n")
    (tmp_path / "p.dat").write_text(PENDULUM.format(loads="USERSIG WEIGHT"))
    model, settings = fm.read_dat(tmp_path / "p.dat")
    fm.write_dat(model, tmp_path / "copy.dat", settings)
    assert fm.read_dat(tmp_path / "copy.dat")[1].user_loads == "WEIGHT"
