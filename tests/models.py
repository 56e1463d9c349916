"""Small models from the exercises, shared by the tests."""

import math

import numpy as np

import flexmbd as fm


def slider_crank(l1: float = 1.0, l2: float = math.sqrt(3.0), law=None) -> fm.Model:
    """EXERCISES 2: nodes 1 O, 2 crank angle, 3 A, 4 rod angle, 5 B (y fixed)."""
    b = fm.ModelBuilder("slider-crank")
    b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)
    b.add_rigid_beam(2, 3, 4, 5)
    b.fix(1).fix(5, "y")
    b.input_coordinate(2, law=law or fm.Polynomial(0.0, 2.0, 1.5))
    return b.build()


#: Andrews' squeezing mechanism (Hairer & Wanner, Solving ODEs II, VII.7; the IVP test
#: set of Mazzia and Magherini): masses [kg], inertias about the centres of mass [kg m^2],
#: fixed points and dimensions [m], the drive torque [N m] and the spring [N/m, m]
SQUEEZER = dict(
    m1=0.04325, m2=0.00365, m3=0.02373, m4=0.00706, m5=0.07050, m6=0.00706, m7=0.05498,
    i1=2.194e-6, i2=4.410e-7, i3=5.255e-6, i4=5.667e-7, i5=1.169e-5, i6=5.667e-7,
    i7=1.912e-5, xa=-0.06934, ya=-0.00227, xb=-0.03635, yb=0.03273, xc=0.014, yc=0.072,
    d=28e-3, da=115e-4, e=2e-2, ea=1421e-5, rr=7e-3, ra=92e-5, ss=35e-3, sa=1874e-5,
    sb=1043e-5, sc=18e-3, sd=2e-2, ta=2308e-5, tb=916e-5, u=4e-2, ua=1228e-5, ub=449e-5,
    zf=2e-2, zt=4e-2, fa=1421e-5, mom=0.033, c0=4530.0, l0=0.07785)
#: its consistent initial angles beta, theta, gamma, phi, delta, omega, epsilon [rad]
SQUEEZER_ANGLES = (-0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
                   0.222668390165885884674473185609, 0.487364979543842550225598953530,
                   -0.222668390165885884674473185609, 1.23054744454982119249735015568)


def andrews_squeezer() -> fm.Model:
    """Andrews' squeezing mechanism of seven rigid bodies, each lumped as SPACAR lumps a
    rigid link: its mass at the ends of a rigid beam in the ratio that keeps the centre
    of mass, plus the rotary inertia ``J = i - m c (l - c)`` on its rotational node, which
    is negative for bodies 2, 4 and 6. Bodies 3, 5 and 7 turn about fixed pivots and carry
    their inertia about the pivot there. A torque drives the crank (body 1); a spring
    pulls body 3 towards the fixed point C.

    Translational nodes: 1 O, 2 P (crank pin), 3 E (the joint of bodies 2, 3, 4, 6),
    4 B, 5 D (spring end), 6 A, 7 G, 8 H, 9 C. Rotational nodes 11 to 17 carry the angles
    beta, beta + theta, gamma, delta, phi + delta, epsilon, omega + epsilon, each
    measured from the initial configuration."""
    s = SQUEEZER
    beta, theta, gamma, _, delta, _, epsilon = SQUEEZER_ANGLES
    P = s["rr"] * math.cos(beta), s["rr"] * math.sin(beta)
    E = (P[0] - s["d"] * math.cos(beta + theta), P[1] - s["d"] * math.sin(beta + theta))
    D = (s["xb"] + s["sd"] * math.cos(gamma) + s["sc"] * math.sin(gamma),
         s["yb"] + s["sd"] * math.sin(gamma) - s["sc"] * math.cos(gamma))
    G = s["xa"] + s["zt"] * math.cos(delta), s["ya"] + s["zt"] * math.sin(delta)
    H = s["xa"] + s["u"] * math.sin(epsilon), s["ya"] - s["u"] * math.cos(epsilon)
    b = fm.ModelBuilder("Andrews' squeezer")
    for node, (x, y) in {1: (0.0, 0.0), 2: P, 3: E, 4: (s["xb"], s["yb"]), 5: D,
                         6: (s["xa"], s["ya"]), 7: G, 8: H, 9: (s["xc"], s["yc"])}.items():
        b.add_node(node, x, y)
    links = [(1, 11, 2), (2, 12, 3), (4, 13, 3), (4, 13, 5), (6, 14, 7), (7, 15, 3),
             (6, 16, 8), (8, 17, 3)]
    for number, (p, angle, q) in enumerate(links, start=1):
        b.add_rigid_beam(number, p, angle, q)
    b.add_element(9, "spring-damper", (5, 9)).set_stiffness(9, spring=s["c0"])
    spring_length = math.hypot(D[0] - s["xc"], D[1] - s["yc"])
    b.set_prestress(9, 1, s["c0"] * (spring_length - s["l0"]))

    def lumped(m, i, length, c, p, angle, q):
        """``m`` with its centre ``c`` from ``p`` on the line to ``q`` of ``length``."""
        b.add_point_mass(p, m * (length - c) / length).add_point_mass(q, m * c / length)
        b.add_point_mass(angle, i - m * c * (length - c))

    lumped(s["m1"], s["i1"], s["rr"], s["ra"], 1, 11, 2)
    lumped(s["m2"], s["i2"], s["d"], s["da"], 2, 12, 3)
    lumped(s["m4"], s["i4"], s["e"], s["e"] - s["ea"], 7, 15, 3)
    lumped(s["m6"], s["i6"], s["zf"], s["zf"] - s["fa"], 8, 17, 3)
    for angle, m, i, a, c in ((13, "m3", "i3", "sa", "sb"), (14, "m5", "i5", "ta", "tb"),
                              (16, "m7", "i7", "ua", "ub")):
        b.add_point_mass(angle, s[i] + s[m] * (s[a] ** 2 + s[c] ** 2))
    b.add_force(11, s["mom"])
    return b.fix(1).fix(4).fix(6).fix(9).dynamic_coordinate(11).build()


def squeezer_angles(result: fm.SimulationResult) -> np.ndarray:
    """The test set's seven angles ``(nt, 7)`` [rad] from a result of
    :func:`andrews_squeezer`."""
    beta0, theta0, gamma0, phi0, delta0, omega0, epsilon0 = SQUEEZER_ANGLES
    a = {n: result[f"x{n}.1"] for n in range(11, 18)}
    return np.stack([beta0 + a[11], theta0 + a[12] - a[11], gamma0 + a[13],
                     phi0 + a[15] - a[14], delta0 + a[14], omega0 + a[17] - a[16],
                     epsilon0 + a[16]], axis=1)


def two_beam_column() -> fm.Model:
    """A cantilever of two beams along x (1 m), clamped at node 1, with mass: it can
    buckle under a load along it at node 5."""
    b = fm.ModelBuilder("column")
    for k in range(3):
        b.add_node(2 * k + 1, 0.5 * k, 0.0)
    for k in range(2):
        b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        b.dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
        b.set_stiffness(k + 1, axial=1e6, bending=2.0)
    return b.fix(1).fix(2).build()
