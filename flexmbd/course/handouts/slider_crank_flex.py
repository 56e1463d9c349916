# %% [markdown]
# # Exercise 4: the flexible slider-crank
#
# Crank `l1 = 0.15 m` (rigid, massless), rod `l2 = 0.30 m` with `EI = 12.72 N m^2`
# and mass `m2 = 0.06676 kg`, slider `m5 = m2/2`, crank at 150 rad/s from `phi2 = 0`.
# Node numbers as in the SPACAR file: 1 O, 2 crank angle, 3 A, 4 rod angle at A,
# 5 B, 6 rod angle at B, then 7, 8, 9, 10, ... for the inner rod nodes (translation,
# rotation) when the rod has `nbeams` beams. `x` lists the nodes' coordinates in
# node order. Part 1 (a-f): one beam, `q = [phi2, e2, e3]`; part 2 (g-h): `nbeams`
# beams, elongation rigid or flexible (`eps1flex`). Check your file with
# `flexmbd exercise check slider-crank-flex THIS_FILE`.
#
# Sign convention of the bending deformations: this flexible beam's are
# `e2 = -n_p . d` and `e3 = n_q . d` (`e2 ~ l theta_p`, `e3 ~ -l theta_q`), with `n`
# the left normal of a node's tangent and `d = r_q - r_p`; exercise 2's rigid beam
# has `e2 = +n_p . d`. The elastic law of the bending pair is
# `[s2, s3] = EI / l^3 [[4, -2], [-2, 4]] [e2, e3]` (part f needs it).

# %%
import numpy as np
from scipy.integrate import solve_ivp

from flexmbd.course.student import not_done, show  # noqa: F401

L1, L2 = 0.15, 0.30  # [m]
M2, EI = 0.06676, 12.72  # rod mass [kg], bending stiffness [N m^2]
M5 = M2 / 2  # slider [kg]
OMEGA = 150.0  # crank speed [rad/s]
# Hermite integrals int_0^1 H_i H_j dxi (THEORY 5)
HH = np.array([[13 / 35, 11 / 210, 9 / 70, -13 / 420], [11 / 210, 1 / 105, 13 / 420, -1 / 140],
               [9 / 70, 13 / 420, 13 / 35, -11 / 210], [-13 / 420, -1 / 140, -11 / 210, 1 / 105]])


def unit(angle):
    """(e, n): the unit vector at angle and its left normal."""
    e = np.array([np.cos(angle), np.sin(angle)])
    return e, np.array([-e[1], e[0]])


# %% [markdown]
# ## Part 1: one beam

# %%
def beam_deformations(xe, l0=L2):
    """Part a: (e1, e2, e3) [m] at xe = [x_p, y_p, phi_p, x_q, y_q, phi_q], beta0 = 0."""
    # part a: write (e1, e2, e3) [m] of the rod beam at xe = [x_p, y_p, phi_p, x_q, y_q, phi_q] (l0 = 0.30, beta0 = 0)
    not_done('a', 'e1 = |d| - l0, e2 = -n_p . d, e3 = n_q . d')


# %%
def beam_jacobian(xe, l0=L2):
    """Part b: D_x (3, 6), the derivative of part a."""
    # part b: write D_x (3, 6) of the beam
    not_done('b', 'differentiate (e1, e2, e3) with respect to the six element coordinates')


# %%
def beam_quadratic(xe, xed, l0=L2):
    """Part c: (D_xx xed) xed (3,)."""
    # part c: write (D_xx xed) xed (3,) [m/s^2] of the beam
    not_done('c', 'e2: w_p^2 (n_p . d) + 2 w_p (e_p . dv); e3: -w_q^2 (n_q . d) - 2 w_q (e_q . dv)')


# %%
def beam_mass(xe, xed, m=M2, l0=L2):
    """Part d: (M (6, 6), h (6,)), the beam's consistent mass and velocity term."""
    # part d: write (M (6, 6) [kg, kg m, kg m^2], h (6,) [N]): the rod's consistent mass and its velocity term (Hermite interpolation)
    not_done('d', 'M = m int N^T N dxi, h = m int N^T a dxi with N = [H1 I, H2 l0 n_p, H3 I, H4 l0 n_q]')


ELEMENTS_1 = {"crank": [0, 1, 2, 3, 4], "rod": [3, 4, 5, 6, 7, 8]}
FIXED, INPUT = [0, 1, 7], [2]
DEPENDENT_1 = [3, 4, 5, 6, 8]


def crank_deformations(xc):
    """The rigid crank's (e1, e2) and Jacobian (2, 5) (exercise 2)."""
    d = xc[3:5] - xc[0:2]
    e_p, n_p = unit(xc[2])
    e_l = d / np.hypot(*d)
    return (np.array([np.hypot(*d) - L1, n_p @ d]),
            np.array([[-e_l[0], -e_l[1], 0.0, e_l[0], e_l[1]],
                      [-n_p[0], -n_p[1], -e_p @ d, n_p[0], n_p[1]]]))


def crank_quadratic(xc, xcd):
    d, dv = xc[3:5] - xc[0:2], xcd[3:5] - xcd[0:2]
    e_p, n_p = unit(xc[2])
    length, w = np.hypot(*d), xcd[2]
    return np.array([(dv @ dv - (d @ dv / length) ** 2) / length,
                     -w**2 * (n_p @ d) - 2 * w * (e_p @ dv)])


def one_beam_jacobian(x):
    """D_x (5, 9) of [e1.1, e1.2, e2.1, e2.2, e2.3]."""
    D = np.zeros((5, 9))
    D[0:2, ELEMENTS_1["crank"]] = crank_deformations(x[ELEMENTS_1["crank"]])[1]
    D[2:5, ELEMENTS_1["rod"]] = beam_jacobian(x[ELEMENTS_1["rod"]])
    return D


# %%
def transfer(x):
    """Part e: F_q (9, 3) at x, q = [phi2, e2, e3]. Uses part b (D_x)."""
    # part e: write F_q (9, 3) of the one-beam rod at x, q = [phi2, e2, e3]
    not_done('e', 'D_c F_c = [-D_m | 0; 0 | I] over the rows [e(o); e2, e3]')


# %%
def dynamic_accelerations(x, qd):
    """Part f: (e2dd, e3dd) [m/s^2] at constant crank speed (phi2dd = 0). Uses parts a to e;
    the stresses are [s2, s3] = EI / L2^3 [[4, -2], [-2, 4]] [e2, e3]."""
    # part f: write (e2dd, e3dd) [m/s^2] at constant crank speed: Mbar_dd qdd_d = f_d
    not_done('f', 'Mbar = F_q^T M F_q; f = F_q^T (-h - M (F_qq qd) qd) - E_q^T S e')


# %% [markdown]
# ## Part 2: nbeams beams

# %%
def rod_nodes(nbeams):
    """Coordinate indices of the rod's nodes from A to B: (translations, rotations)."""
    inner = range(nbeams - 1)
    return ([[3, 4], *([9 + 3 * k, 10 + 3 * k] for k in inner), [6, 7]],
            [5, *(11 + 3 * k for k in inner), 8])


def all_deformations(x, nbeams):
    """e (2 + 3 nbeams,) and D_x of the crank and the rod's beams."""
    nx = 9 + 3 * (nbeams - 1)
    e, D = np.zeros(2 + 3 * nbeams), np.zeros((2 + 3 * nbeams, nx))
    e[0:2], D[0:2, ELEMENTS_1["crank"]] = crank_deformations(x[ELEMENTS_1["crank"]])
    translations, rotations = rod_nodes(nbeams)
    for k in range(nbeams):
        c = [*translations[k], rotations[k], *translations[k + 1], rotations[k + 1]]
        rows = slice(2 + 3 * k, 5 + 3 * k)
        e[rows] = beam_deformations(x[c], L2 / nbeams)
        D[rows, c] = beam_jacobian(x[c], L2 / nbeams)
    return e, D


# %%
def positions(q, nbeams, eps1flex):
    """Part g: x for q = [phi2, per beam (e1,) e2, e3], by Newton-Raphson."""
    # part g: write x [m, rad] for nbeams beams by Newton-Raphson, q = [phi2, the beams' (e1,) e2, e3]
    not_done('g', 'Newton on [e(o); e(m) - q_e] = 0 for the dependent coordinates, from the straight rod')


# %%
def midpoint_deflection(x, nbeams):
    """Part h: v/l2 at the middle of the rod (THEORY: a node for even nbeams, the middle
    beam's Hermite point at xi = 1/2 for odd)."""
    # part h: write v/l2 [-] at the rod's middle (a node for even nbeams, the middle beam's Hermite point for odd)
    not_done('h', 'v = (M - A) . n_AB with n_AB the left normal of B - A')


# %% [markdown]
# ## Given: the simulation of part 1
# The crank turns at 150 rad/s; `e2, e3` start at rest, undeformed. Over two turns
# `v/l2` swings between about +0.015 and -0.0155 with a 130 Hz vibration on top.
# For n beams run `flexmbd example slider-crank-flex --nbeams N [--eps1flex]`.

# %%
def simulate_one_beam(revolutions=0.25, points=101):
    times = np.linspace(0.0, revolutions * 2 * np.pi / OMEGA, points)

    def rhs(t, state):
        x = positions(np.array([OMEGA * t, *state[:2]]), 1, False)
        return [*state[2:], *dynamic_accelerations(x, np.array([OMEGA, *state[2:]]))]

    run = solve_ivp(rhs, (0.0, times[-1]), np.zeros(4), t_eval=times, rtol=1e-8, atol=1e-11)
    v = [midpoint_deflection(positions(np.array([OMEGA * t, *s[:2]]), 1, False), 1)
         for t, s in zip(run.t, run.y.T, strict=True)]
    return OMEGA * run.t, np.array(v)


# %%
if __name__ == "__main__":
    straight = np.array([0.15, 0.0, 0.0, 0.45, 0.0, 0.0])
    show("a  beam deformations", beam_deformations, straight)
    show("b  beam Jacobian", beam_jacobian, straight)
    show("d  beam mass and h", beam_mass, straight, np.array([0, 22.5, -75.0, 0, 0, -75.0]))
    x = show("g  positions, one beam, phi2 = 0.5", positions, np.array([0.5, 0.0, 0.0]), 1, False)
    if x is not None:
        show("e  F_q", transfer, x)
        show("f  (e2dd, e3dd)", dynamic_accelerations, x, np.array([OMEGA, 0.0, 0.0]))
        show("h  v/l2", midpoint_deflection, x, 1)
    result = show("simulation, a quarter turn: (crank angle, v/l2)", simulate_one_beam)
    if result is not None:
        print(f"   largest |v/l2| {np.max(np.abs(result[1])):.4f}")
