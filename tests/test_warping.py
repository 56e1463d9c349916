"""The warping beam (BEAMW, FLEXURES 1-2): torsion of a strip with restrained warping
against a one-dimensional Vlasov finite element (an independent formulation: the cubic
Hermite twist with its own stiffness matrices) and the closed forms of non-uniform
torsion; the SPACAR Light form of its files; and the front door's warping."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import light

STEEL = fm.Material.from_poisson(210e9, 0.3, 7800.0)
STRIP = fm.Rectangle(0.02, 0.0005)   # 20 x 0.5 mm: It = 8.20203e-13, Cw = 6.94444e-18
GIT = STEEL.G * STRIP.properties().It
ECW = STEEL.E * STRIP.properties().Cw
LAMBDA = math.sqrt(GIT / ECW)   # 213.14 /m


def _vlasov(L: float, n: int, clamp: bool, tip: bool) -> float:
    """The twist stiffness factor ``k L / GIt`` of ``n`` one-dimensional Vlasov elements
    (nodal twist and rate of twist, cubic Hermite): ``ECw`` times the bending matrix and
    ``GIt`` times the geometric one, the twist held at the clamp, its rate held where
    warping is restrained, a torque at the tip."""
    h = L / n
    bend = ECW / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                                  [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    geo = GIT / (30 * h) * np.array([[36, 3 * h, -36, 3 * h], [3 * h, 4 * h * h, -3 * h, -h * h],
                                     [-36, -3 * h, 36, -3 * h], [3 * h, -h * h, -3 * h, 4 * h * h]])
    K = np.zeros((2 * n + 2, 2 * n + 2))
    for k in range(n):
        K[2 * k:2 * k + 4, 2 * k:2 * k + 4] += bend + geo
    held = [0] + ([1] if clamp else []) + ([2 * n + 1] if tip else [])
    free = [i for i in range(2 * n + 2) if i not in held]
    load = np.zeros(len(free))
    load[free.index(2 * n)] = 1.0
    twist = np.linalg.solve(K[np.ix_(free, free)], load)[free.index(2 * n)]
    return L / (twist * GIT)


def _strip(L: float, n: int, clamp: bool, tip: bool) -> float:
    """The same factor of ``n`` warping beams, from the tip's compliance about the axis."""
    b = fm.ModelBuilder("strip")
    b.add_node(1, 0.0, 0.0, 0.0).add_node(4, L, 0.0, 0.0)
    b.add_spatial_beams(1, 1, 2, 4, 5, n, (0, 1, 0), new_nodes=10, node_step=3,
                        warping=(3, 6), section=STRIP, material=STEEL)
    b.fix(1).fix(2)
    if clamp:
        b.fix(3)
    if tip:
        b.fix(6)
    C = fm.node_compliance(fm.static_equilibrium(b.build()).linearization(), 4, 5)
    return L / (C[3, 3] * GIT)


def _both(lam_l: float) -> float:
    return lam_l / (lam_l - 2 * math.tanh(lam_l / 2))


def _one(lam_l: float) -> float:
    return 1 / (1 - math.tanh(lam_l) / lam_l)


@pytest.mark.parametrize("n", [1, 3, 8])
@pytest.mark.parametrize("clamp, tip", [(True, True), (True, False), (False, False)])
def test_the_warping_beam_is_the_vlasov_element(n, clamp, tip):
    """The warping beams' twist stiffness is the one-dimensional Vlasov element's (the
    same cubic twist) for restrained, one-sided and free warping."""
    assert _strip(0.02, n, clamp, tip) == pytest.approx(_vlasov(0.02, n, clamp, tip), rel=1e-9)


def test_torsion_with_warping_meets_the_closed_forms():
    """FLEXURES 2: at L/w = 1, n = 8: both ends restrained 1.83883 (exact 1.83875), one
    end 1.30636 (exact 1.30634), and free warping St Venant's GIt/L exactly; the error
    falls as n^-4."""
    lam_l = LAMBDA * 0.02
    assert _strip(0.02, 8, True, True) == pytest.approx(1.83883, abs=1e-5)
    assert _strip(0.02, 8, True, True) == pytest.approx(_both(lam_l), rel=5e-5)
    assert _strip(0.02, 8, True, False) == pytest.approx(_one(lam_l), rel=2e-5)
    assert _strip(0.02, 3, False, False) == pytest.approx(1.0, abs=1e-12)
    errors = [_strip(0.02, n, True, True) / _both(lam_l) - 1 for n in (4, 8)]
    assert 12 < errors[0] / errors[1] < 20    # about 2^4


def _spacar_light_file(L: float, n: int) -> str:
    """A strip of ``n`` BEAMW as SPACAR Light writes it (its node numbering, FIX lines of
    the warping nodes, ESTIFF with ECw and EM with Jw in %20.15f), a torque at the tip."""
    v = fm.beam_values(STRIP, STEEL)
    lines = ["#Dat-file generated with SPACAR Light version 2.37",
             "X\t\t  1\t\t\t0.000000\t0.000000\t0.000000\t\t#node 1",
             f"X\t\t  4\t\t\t{L:f}\t0.000000\t0.000000\t\t#node 2"]
    chain = [(1, 2, 3)] + [(7 + 3 * k, 8 + 3 * k, 9 + 3 * k) for k in range(n - 1)] + \
        [(4, 5, 6)]
    for k in range(n - 1):
        lines.append(f"X\t\t{7 + 3 * k:3d}\t\t\t{L * (k + 1) / n:f}\t0.000000\t0.000000")
    for e in range(n):
        (a, b, c), (d, f, g) = chain[e], chain[e + 1]
        lines.append(f"BEAMW       {e + 1:4d}{a:4d}{b:4d}{c:4d}{d:6d}{f:4d}{g:4d}    "
                     f"0.000000\t1.000000\t0.000000\t\t#element 1 beam {e + 1}")
        lines.append(f"DYNE\t\t{e + 1:3d}\t\t  1\t  2\t  3\t  4\t  5\t  6")
    lines += ["FIX\t\t  1  ", "FIX\t\t  2", "FIX\t\t  3  #warping", "FIX\t\t  6  #warping",
              "END", "HALT"]
    for e in range(n):
        lines.append(f"ESTIFF\t\t{e + 1:3d}\t" + "\t".join(f"{x:20.15f}" for x in v.estiff))
        lines.append(f"EM\t\t\t{e + 1:3d}\t\t" + "\t".join(f"{x:20.15f}" for x in v.em))
    lines += ["DELXF\t\t  5\t\t0.001000\t0.000000\t0.000000",
              "ITERSTEP\t10\t  1\t0.0000005\t1\t3\t  1", "END", "END"]
    return "\n".join(lines) + "\n"


def test_a_spacar_light_beamw_file_runs(tmp_path):
    """A SPACAR Light file of warping beams: its torque twists the strip by the Vlasov
    element's angle (ECw from the file's 20 digits), its warping nodes are free where not
    fixed and carry Jw; written again by flexmbd and read back, the same model."""
    path = tmp_path / "strip.dat"
    path.write_text(_spacar_light_file(0.02, 4))
    model, settings = fm.read_dat(path)
    assert not settings.notes
    assert [n for n in model.nodes if model.nodes[n].kind == "warping"] == [3, 6, 9, 12, 15]
    statics = fm.static_equilibrium(model, load_increment=dict(settings.load_increment),
                                    steps=1)
    twist = 2 * math.asin(statics["x5.2"][-1])
    assert twist == pytest.approx(1e-3 * 0.02 / (_vlasov(0.02, 4, True, True) * GIT),
                                  rel=1e-5)   # the 1e-3 N m torque turns it 1e-3 rad
    assert model.section_masses[9] == pytest.approx(0.005 * STEEL.rho * STRIP.properties().Cw)
    fm.write_dat(model, tmp_path / "again.dat", settings)
    again, _ = fm.read_dat(tmp_path / "again.dat")
    for m in (model, again):
        lin = fm.static_equilibrium(m).linearization()
        assert fm.vibration_modes(lin, 3).frequencies == pytest.approx(
            fm.vibration_modes(fm.static_equilibrium(model).linearization(), 3).frequencies,
            rel=1e-12)


def test_the_warping_deformations_are_always_computed():
    b = fm.ModelBuilder("w")
    b.add_node(1, 0, 0, 0).add_node(4, 0.02, 0, 0)
    b.add_warping_beam(1, 1, 2, 3, 4, 5, 6, (0, 1, 0)).fix(1).fix(2)
    b.dynamic_deformation(1, 7)
    with pytest.raises(fm.ModelError, match="deformations 7 and 8 of a warping beam are "
                                            "always computed"):
        b.build()
    beam = fm.ModelBuilder("b")
    beam.add_node(1, 0, 0, 0).add_node(3, 0.02, 0, 0).add_spatial_beam(1, 1, 2, 3, 4, (0, 1, 0))
    beam.set_mass(1, 1.0, section_inertia=(1, 1, 1, 0, 1)).fix(1).fix(2)
    with pytest.raises(fm.ModelError, match="Jw is a warping beam's"):
        beam.build()


def test_the_front_door_restrains_warping_where_spacar_light_does():
    """warping=True: the clamp (fix) restrains warping, the tip's is free: one-sided
    warping's factor; with fix_warp at the tip both ends'. A rigid warping element's
    warping nodes are held."""
    leaf = {"elems": 1, "emod": STEEL.E, "smod": STEEL.G, "dens": STEEL.rho,
            "cshape": "rect", "dim": [0.02, 0.0005], "orien": [0, 1, 0], "nbeams": 8,
            "flex": [1, 2, 3, 4, 5, 6], "warping": True}
    for tip, clamped in (({}, False), ({"fix_warp": True}, True)):
        res = light.run([[0, 0, 0], [0.02, 0, 0]], [[1, 2]], {1: {"fix": True}, 2: tip},
                        [leaf], {"silent": True})
        factor = 0.02 / (res.node[2].CMglob[3, 3, 0] * GIT)
        assert factor == pytest.approx(_vlasov(0.02, 8, True, clamped), rel=1e-9)
    hinge = light.run([[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.1, 0, 0]],
                      [[1, 3], [2, 3], [2, 4]], {1: {"fix": True}, 3: {"moment": [0, 0, 0.01]},
                                                  4: {"fix": True}},
                      [dict(leaf, elems=[1, 3], nbeams=3, dim=[0.05, 0.0002], orien=[0, 0, 1]),
                       {"elems": 2, "dens": 3000, "cshape": "rect", "dim": [0.05, 0.01],
                        "orien": [0, 0, 1], "warping": True}], {"silent": True})
    model = hinge.model
    assert {6, 9} <= set(model.nodes) and all(
        model.coordinate_class[model.nodes[w].coordinates[0]] == fm.CoordinateClass.FIXED
        for w in (3, 6, 9, 12))
    assert hinge.ndof == 30 + 4    # the leaves' inner warping nodes are free


def test_restrained_warping_adds_the_bimoment_s_normal_stress():
    """A strip with warping restrained at both ends, twisted by T at its tip: the torque
    is T in every beam; at the clamp the bimoment is T tanh(lam L / 2) / lam (Vlasov's
    solution, -ECw phi'' there, negative) and the corners carry its normal stress
    36 B / (w^2 t^2)."""
    L, T, n = 0.02, 1e-3, 8
    b = fm.ModelBuilder("strip")
    b.add_node(1, 0.0, 0.0, 0.0).add_node(4, L, 0.0, 0.0)
    b.add_spatial_beams(1, 1, 2, 4, 5, n, (0, 1, 0), new_nodes=10, node_step=3,
                        warping=(3, 6), section=STRIP, material=STEEL)
    b.fix(1).fix(2).fix(3).fix(6)
    statics = fm.static_equilibrium(b.build(), load_increment={"x5.2": T}, steps=1)
    stresses = fm.beam_stresses(statics.model, statics.x[-1], statics.sigma[-1])
    for beam in stresses.values():
        assert beam.resultants.shape == (2, 7)
        np.testing.assert_allclose(beam.resultants[:, 3], T, rtol=1e-6)
    clamp = stresses[1]
    bimoment = T * math.tanh(LAMBDA * L / 2) / LAMBDA
    assert clamp.resultants[0, 6] == pytest.approx(-bimoment, rel=1e-4)   # 4.8e-5 off
    w, t = 0.02, 0.0005
    assert clamp.von_mises == pytest.approx(36 * abs(clamp.resultants[0, 6]) / (w * t)**2,
                                            rel=1e-9)
    assert clamp.where.startswith("p, corner")
