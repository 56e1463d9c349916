"""A node's 6x6 compliance (FLEXURES 6) against the cantilever's closed forms, in the body
frame of a turned cantilever, and with its drive held and free."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.errors import ArgumentError, SingularConfigurationError

STEEL = fm.Material.from_poisson(210e9, 0.3, 7800.0)
LEAF = fm.Rectangle(0.02, 0.0005)
L = 0.06


def _cantilever(driven: bool = False, spring: float | None = None) -> fm.Model:
    """A leaf of 6 beams along x clamped at node 1, its tip nodes 3 and 4. ``driven``: the
    clamp's rotation about z (lam3 of node 2) is an input, the clamp held about x and y by
    a hinge about z to the fixed node 50, whose rotation has the stiffness ``spring``."""
    b = fm.ModelBuilder("cantilever")
    b.add_node(1, 0.0, 0.0, 0.0).add_node(3, L, 0.0, 0.0)
    b.add_spatial_beams(1, 1, 2, 3, 4, 6, orientation=(0, 1, 0), new_nodes=10,
                        section=LEAF, material=STEEL)
    b.fix(1)
    if not driven:
        b.fix(2)
        return b.build()
    b.add_spatial_hinge(100, 50, 2, axis=(0, 0, 1)).fix(50).input_coordinate(2, 4)
    b.release(100, 1)
    if spring is not None:
        b.set_stiffness(100, hinge=spring)
    return b.build()


def _turned(model: fm.Model, angle: float):
    """The linearization with the clamp turned by ``angle`` about z (the drive's input)."""
    statics = fm.static_equilibrium(model, input_increment={"x2.4": math.sin(angle / 2)},
                                    steps=2)
    return statics.linearization()


def _closed_form() -> np.ndarray:
    """The linear cantilever's tip compliance in its own axes (x along it, the leaf's
    width along y, its thickness along z), with shear: ``L/(EA)``, ``L^3/(3EI) + L/(kGA)``,
    ``L/(GIt)``, ``L/(EI)`` and the couplings ``L^2/(2EI)``."""
    s, E, G = LEAF.properties(), STEEL.E, STEEL.G
    kGA = LEAF.shear_factor(STEEL.nu) * G * s.A
    C = np.zeros((6, 6))
    C[0, 0] = L / (E * s.A)
    C[1, 1] = L**3 / (3 * E * s.Iz) + L / kGA
    C[2, 2] = L**3 / (3 * E * s.Iy) + L / kGA
    C[3, 3] = L / (G * s.It)
    C[4, 4], C[5, 5] = L / (E * s.Iy), L / (E * s.Iz)
    C[1, 5] = C[5, 1] = L**2 / (2 * E * s.Iz)     # a force along y turns the tip about z
    C[2, 4] = C[4, 2] = -L**2 / (2 * E * s.Iy)    # a force along z turns it about -y
    return C


def test_the_tip_compliance_is_the_cantilever_s():
    lin = fm.static_equilibrium(_cantilever()).linearization()
    C = fm.node_compliance(lin, 3, 4)
    expected = _closed_form()
    np.testing.assert_allclose(C, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())
    assert fm.node_compliance(lin, 3).shape == (3, 3)   # translations only


def test_the_body_frame_is_the_turned_node_s():
    """Turned by 40 degrees about z through its clamp, the cantilever's tip compliance in
    its tip's body frame is the unturned one in global axes; in global axes, it is that
    turned."""
    turned = _turned(_cantilever(driven=True), math.radians(40))
    body = fm.node_compliance(turned, 3, 4, frame="body")
    np.testing.assert_allclose(body, _closed_form(), rtol=1e-9,
                               atol=1e-12 * np.abs(body).max())
    c, s = math.cos(math.radians(40)), math.sin(math.radians(40))
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    T = np.block([[R, np.zeros((3, 3))], [np.zeros((3, 3)), R]])
    np.testing.assert_allclose(fm.node_compliance(turned, 3, 4), T @ _closed_form() @ T.T,
                               rtol=1e-9, atol=1e-12 * np.abs(body).max())


def test_a_free_drive_without_stiffness_is_a_mechanism():
    lin = _turned(_cantilever(driven=True), 0.3)
    held = fm.node_compliance(lin, 3, 4, drive="held")
    assert np.all(np.linalg.eigvalsh(held) > 0)
    with pytest.raises(SingularConfigurationError, match="drive without stiffness"):
        fm.node_compliance(lin, 3, 4, drive="free")


def test_a_free_drive_with_stiffness_adds_its_compliance():
    """The clamp turned by its drive, which has a torsion spring k: held, the tip is the
    cantilever's; free, the spring adds ``v v^T / k`` with ``v = (0, L, 0, 0, 0, 1)`` (a
    turn of the clamp moves the tip sideways by L and turns it alike)."""
    k = 5.0
    lin = _turned(_cantilever(driven=True, spring=k), 0.0)
    held = fm.node_compliance(lin, 3, 4, drive="held")
    free = fm.node_compliance(lin, 3, 4, drive="free")
    np.testing.assert_allclose(held, _closed_form(), rtol=1e-9,
                               atol=1e-12 * np.abs(held).max())
    v = np.array([0.0, L, 0.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(free, _closed_form() + np.outer(v, v) / k, rtol=1e-9,
                               atol=1e-12 * np.abs(free).max())
    assert np.linalg.eigvalsh(free - held).min() > -1e-12 * np.abs(free).max()


def test_bad_requests_are_named():
    lin = fm.static_equilibrium(_cantilever()).linearization()
    with pytest.raises(ArgumentError, match="frame"):
        fm.node_compliance(lin, 3, frame="body")
    with pytest.raises(ArgumentError, match="4 is not a translational node"):
        fm.node_compliance(lin, 4)
    with pytest.raises(ArgumentError, match="drive"):
        fm.node_compliance(lin, 3, 4, drive="loose")


def test_every_load_step_is_linearized_at_its_own_equilibrium(tmp_path, capsys):
    """A leaf column compressed in 4 steps: at each step the buckling factor times the
    step's load is the critical load pi^2 EI / (4 L^2) (with shear), the lowest frequency
    of the unloaded step is the cantilever's 1.8751^2 / (2 pi) sqrt(EI / (rhoA L^4)), and
    the tip's bending compliance grows as the load nears the critical one."""
    model = _cantilever()
    P = 10.0
    statics = fm.static_equilibrium(model, load_increment={"x3.1": -P}, steps=4)
    table = fm.load_step_table(statics, modes=2, buckle=1, compliance=[(3, 4)])
    s, E = LEAF.properties(), STEEL.E
    kGA = LEAF.shear_factor(STEEL.nu) * STEEL.G * s.A
    euler = math.pi**2 * E * s.Iy / (4 * L**2)
    critical = euler / (1 + euler / kGA)
    loads = P * np.arange(5) / 4
    assert np.isnan(table["buckling1"][0])   # no stresses, nothing to buckle
    np.testing.assert_allclose(table["buckling1"][1:] * loads[1:], critical, rtol=2e-5)
    f1 = 1.8751041**2 / (2 * math.pi) * math.sqrt(E * s.Iy / (STEEL.rho * s.A * L**4))
    assert table["f1"][0] == pytest.approx(f1, rel=1e-4)
    assert table["C3.33"][0] == pytest.approx(_closed_form()[2, 2], rel=1e-9)
    assert np.all(np.diff(table["C3.33"]) > 0) and np.all(np.diff(table["f1"]) < 0)
    # the command line: the same columns for a file (no section needed)
    dat = tmp_path / "column.dat"
    fm.write_dat(model, dat, fm.RunSettings(load_increment={"x3.1": -P}, load_steps=4))
    out = tmp_path / "steps.csv"
    from flexmbd.cli import main

    assert main(["static", str(dat), "--modes", "1", "--buckling", "1", "--compliance",
                 "3:4", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "buckling1" in printed and "C3.33" in printed and "C3.12" not in printed
    header = out.read_text().splitlines()[0].split(",")
    assert "C3.12" in header and "f1" in header
