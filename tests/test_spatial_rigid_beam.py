"""The spatial rigid beam (SPACAR's RBEAM) against a rigid BEAM, and in a chain of
bodies and hinges as public catheter models use it."""

import textwrap

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.analysis.runs import analyse
from flexmbd.errors import InputFileError
from flexmbd.io.dat import dat_from_text, dat_text

#: a body swinging freely about a fixed point (node 1) under gravity, with a point mass
#: at q: {element} is the RBEAM or a BEAM all of whose deformations are rigid
PENDULUM = """\
X 1 0 0 0
X 3 0.4 0.05 0.1
{element}
FIX 1
DYNX 2
END
HALT
EM 1 1.5 0.01 0.002 0.003 0.0005
XM 3 0.5
GRAVITY 0 0 -9.81
STARTDX 2 3 0.0 1.5
ERROR 1e-10 1e-10
TIMESTEP 0.3 6
END
END
"""


def _swing(element: str):
    model, settings = dat_from_text(PENDULUM.format(element=element))
    return model, analyse(model, settings, "dynamic", settings.output_times())


def test_an_rbeam_body_moves_as_a_rigid_beam():
    """The same body as an RBEAM (a rod's linear velocity field, the section inertia on
    its one rotational node) and as a BEAM held rigid (a Hermite centre line, half the
    section inertia on each end): both are exact for a rigid body."""
    model, rbeam = _swing("RBEAM 1 1 2 3 0 1 0")
    _, beam = _swing("BEAM 1 1 2 3 4 0 1 0")
    assert model.elements[1].type is fm.SpatialRigidBeam and model.n_deformations == 4
    assert rbeam.success and beam.success
    for label in ("x3.1", "x3.2", "x3.3", "x2.2", "x2.3", "x2.4"):
        np.testing.assert_allclose(rbeam[label], beam[label], atol=1e-7, err_msg=label)
    assert np.ptp(rbeam["x3.3"]) > 0.05   # it swung
    # the body stays rigid: q keeps its distance from p
    distance = np.linalg.norm(np.stack([rbeam[f"x3.{k}"] for k in (1, 2, 3)]), axis=0)
    np.testing.assert_allclose(distance, np.sqrt(0.4**2 + 0.05**2 + 0.1**2), rtol=1e-10)


def test_the_orientation_may_be_left_off_and_orients_only_the_section():
    """Without an orientation the body's y axis is the global axis in which the chord is
    smallest (here y); the motion is that of the file that gives it."""
    explicit, given = _swing("RBEAM 1 1 2 3 0 1 0")
    model, default = _swing("RBEAM 1 1 2 3")
    np.testing.assert_array_equal(model.elements[1].reference, explicit.elements[1].reference)
    np.testing.assert_allclose(default["x3.3"], given["x3.3"], atol=1e-12)


def test_an_rbeam_line_reads_and_writes_back():
    text = PENDULUM.format(element="RBEAM 1 1 2 3")
    model, settings = dat_from_text(text)
    again, _ = dat_from_text(dat_text(model, settings))
    assert again.elements[1].type is fm.SpatialRigidBeam
    np.testing.assert_array_equal(again.elements[1].reference, model.elements[1].reference)
    assert "RBEAM    1 1 2 3\n" in dat_text(model, settings)


@pytest.mark.parametrize("line, message", [
    ("RBEAM 1 1 2 3 0.4 0.05 0.1", "lies along the chord"),
    ("RBEAM 1 1 2 3 0 1", r"the orientation takes 3 values \(ox oy oz\), got 2"),
])
def test_a_bad_rbeam_line_is_named(line, message):
    with pytest.raises(InputFileError, match=message):
        dat_from_text(PENDULUM.format(element=line), "body.dat")


def test_only_the_elongation_of_an_rbeam_may_be_classified():
    text = PENDULUM.format(element="RBEAM 1 1 2 3\nRLSE 1 2")
    with pytest.raises(InputFileError, match=r"body\.dat:4: RLSE: element 1 is an RBEAM: .* "
                                             r"only its elongation"):
        dat_from_text(text, "body.dat")


def test_a_chain_of_bodies_and_hinges_pushed_by_a_routine(tmp_path):
    """Three bodies joined by three hinges each (about x, y, z), as public catheter models
    of SPACAR build a rigid instrument: the count of their deformations closes only with
    three per RBEAM. The last node is pushed along x by a USERINP routine."""
    text = textwrap.dedent("""\
        X 1 0 0 0
        X 5 -0.01 0 0
        X 9 -0.02 0 0
        X 13 -0.03 0 0
        RBEAM 1 1 2 5 0 1 0
        HINGE 2 2 3 1 0 0
        HINGE 3 3 4 0 1 0
        HINGE 4 4 6 0 0 1
        RBEAM 5 5 6 9 0 1 0
        HINGE 6 6 7 1 0 0
        HINGE 7 7 8 0 1 0
        HINGE 8 8 10 0 0 1
        RBEAM 9 9 10 13 0 1 0
        DYNX 1 2 3
        DYNX 5 2 3
        DYNX 9 2 3
        DYNX 2 2
        DYNX 6 2
        DYNX 10 2
        INPUTX 13 1
        FIX 13 2
        FIX 13 3
        RLSE 2 1
        RLSE 3 1
        RLSE 4 1
        RLSE 6 1
        RLSE 7 1
        RLSE 8 1
        END
        HALT
        EM 1 0.5
        EM 5 0.5
        EM 9 0.5
        XM 2 1e-7 0 0 1e-7 0 1e-7
        XM 3 1e-7 0 0 1e-7 0 1e-7
        XM 4 1e-7 0 0 1e-7 0 1e-7
        XM 6 1e-7 0 0 1e-7 0 1e-7
        XM 7 1e-7 0 0 1e-7 0 1e-7
        XM 8 1e-7 0 0 1e-7 0 1e-7
        XM 10 1e-7 0 0 1e-7 0 1e-7
        ESTIFF 2 2.8
        ESTIFF 3 3.6
        ESTIFF 4 3.6
        ESTIFF 6 2.8
        ESTIFF 7 3.6
        ESTIFF 8 3.6
        USERINP PUSH
        TIMESTEP 0.05 5
        END
        END
        """)
    (tmp_path / "PUSH.py").write_text("def PUSH(t, flag):\n"
                                      "    return t, [], [13, 1, -0.03 + 0.02 * t, 0.02, 0.0]\n")
    (tmp_path / "chain.dat").write_text(text)
    model, settings = fm.read_dat(tmp_path / "chain.dat")
    rigid = sum(1 for c in model.deformation_class if c == fm.DeformationClass.RIGID)
    # 3 per RBEAM, 2 per hinge (its rotation is released), one per rotational node: as
    # many as the 28 coordinates the 2 fixed and 10 independent ones leave to solve
    assert rigid == 3 * 3 + 6 * 2 + 7 == model.n_coordinates - 2 - 10
    run = analyse(model, settings, "dynamic", settings.output_times())
    assert run.success
    np.testing.assert_allclose(run["x13.1"], -0.03 + 0.02 * run.t, atol=1e-12)
    # undisturbed, the straight chain slides as a whole
    np.testing.assert_allclose(run["x1.1"], 0.02 * run.t, atol=1e-9)
