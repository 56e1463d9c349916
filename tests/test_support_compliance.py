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


def _parallel_guide(leaves: int = 4, manual: bool = False):
    """FLEXURES 7's parallel guide: leaves 50 mm long, 20 x 0.5 mm, 40 mm apart along the
    stroke x, clamped below, a rigid stage across their tops (nodes 3, 4 and 7, 8)."""
    b = fm.ModelBuilder("parallel guide")
    b.add_node(1, 0, 0, 0).add_node(3, 0, 0, 0.05).add_node(5, 0.04, 0, 0)
    b.add_node(7, 0.04, 0, 0.05)
    b.add_spatial_beams(1, 1, 2, 3, 4, leaves, orientation=(0, 1, 0), new_nodes=100,
                        section=LEAF, material=STEEL)
    b.add_spatial_beams(21, 5, 6, 7, 8, leaves, orientation=(0, 1, 0), new_nodes=200,
                        section=LEAF, material=STEEL, dynamic=() if manual else (1, 2, 3, 4,
                                                                                 5, 6))
    b.add_spatial_beam(50, 3, 4, 7, 8, (0, 1, 0))   # the stage: all six deformations rigid
    b.fix(1).fix(2).fix(5).fix(6)
    if manual:   # another valid set: the whole last beam of the second leaf released
        for k in range(21, 20 + leaves):
            b.dynamic_deformation(k)
        b.release(20 + leaves)
        return b.build(), []
    releases = b.release_overconstraints()
    return b.build(), releases


def test_over_constraints_are_released_as_spacar_light_does():
    """The rigid stage over-constrains the two leaves six times: six releases from the
    leaves' last beams make D_c square and regular, and the guide's stiffness is that of
    FLEXURES 7 (8396.1190 N/m along the stroke: 24EI/L^3 with shear and the stage's tilt)
    and of any other valid set of releases."""
    model, releases = _parallel_guide()
    assert len(releases) == 6 and {element for element, _ in releases} <= {4, 24}
    D_c = fm.jacobian(model, model.x0)[np.ix_(model.constrained, model.dependent)]
    assert D_c.shape[0] == D_c.shape[1] and np.linalg.cond(D_c) < 1e8
    C = fm.node_compliance(fm.static_equilibrium(model).linearization(), 3, 4)
    assert 1 / C[0, 0] == pytest.approx(8396.1190, rel=1e-7)
    other, _ = _parallel_guide(manual=True)
    C_other = fm.node_compliance(fm.static_equilibrium(other).linearization(), 3, 4)
    np.testing.assert_allclose(C_other, C, rtol=1e-7, atol=1e-9 * np.abs(C).max())


def test_an_under_constrained_model_is_named():
    b = fm.ModelBuilder("loose")
    b.add_node(1, 0, 0, 0).add_node(3, L, 0, 0)
    b.add_spatial_beams(1, 1, 2, 3, 4, 2, orientation=(0, 1, 0), new_nodes=10,
                        section=LEAF, material=STEEL)
    b.fix(1)   # the clamp's rotation is free
    with pytest.raises(fm.ModelError, match="under-constrained"):
        b.release_overconstraints()


def test_a_file_s_over_constraints_are_released_on_request(tmp_path, capsys):
    """A parallel guide written without releases is refused as over-constrained; read
    with release (flexmbd static --release) it runs, the releases are listed, and its
    stiffness is the guide's."""
    from flexmbd.cli import main
    from flexmbd.io.dat import dat_text

    manual, _ = _parallel_guide(manual=True)
    text = dat_text(manual).replace("RLSE     24 1 2 3 4 5 6", "DYNE     24 1 2 3 4 5 6")
    path = tmp_path / "guide.dat"
    path.write_text(text)
    with pytest.raises(fm.InputFileError, match="does not close"):
        fm.read_dat(path)
    model, settings = fm.read_dat(path, release=True)
    assert any(note.startswith("released over-constraints") for note in settings.notes)
    C = fm.node_compliance(fm.static_equilibrium(model).linearization(), 3, 4)
    assert 1 / C[0, 0] == pytest.approx(8396.1190, rel=1e-7)
    assert main(["static", str(path), "--release", "--compliance", "3:4"]) == 0
    assert "RLSE" in capsys.readouterr().err
