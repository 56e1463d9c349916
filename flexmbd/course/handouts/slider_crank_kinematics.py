# %% [markdown]
# # Exercise 2: slider-crank kinematics
#
# Crank O-A (`l1 = 1`) and rod A-B (`l2 = sqrt(3)`), both rigid beams with one
# rotational node, stretched along the x axis in the reference configuration
# (`beta0 = 0`). Coordinates `x = [x1, y1, phi2, x3, y3, phi4, x5, y5]`:
# fixed `x1, y1, y5`, input `phi2`, dependent `x3, y3, phi4, x5`. Deformations
# `e = [e1.1, e1.2, e2.1, e2.2]` (elongation and bending of each beam), all rigid.
# Check your file with `flexmbd exercise check slider-crank-kinematics THIS_FILE`.

# %%
import numpy as np

from flexmbd.course.student import not_done, show  # noqa: F401

L1, L2 = 1.0, np.sqrt(3.0)  # crank and rod length [m]
BEAMS = [([0, 1, 2, 3, 4], L1), ([3, 4, 5, 6, 7], L2)]  # coordinates of each beam in x
DEPENDENT, INPUT = [3, 4, 5, 6], [2]


def drawn_guess(phi2):
    """A start for Newton-Raphson near the configuration with the slider right of O."""
    psi = -np.arcsin(L1 * np.sin(phi2) / L2)
    return np.array([0, 0, phi2, L1 * np.cos(phi2), L1 * np.sin(phi2), psi,
                     L1 * np.cos(phi2) + L2 * np.cos(psi), 0.0]) + 0.01


# %%
def deformations(x):
    """Part a: e (4,) [m]: per beam e1 = |d| - l0 and e2 = n_p . d."""
    # part a: write e (4,) [m]: the two rigid beams' elongations and bendings
    not_done('a', 'per rigid beam: e1 = |d| - l0, e2 = n_p . d (beta0 = 0 for both)')


# %%
def jacobian(x):
    """Part b: D (4, 8) = de/dx, columns in the order of x."""
    # part b: write D (4, 8): D_x, columns in the order of x
    not_done('b', 'one row per deformation, one column per coordinate of x')


# %%
def positions(phi2):
    """Part c: (x3, y3, phi4, x5) for the crank angle phi2 [rad], by Newton-Raphson.
    Uses parts a and b."""
    # part c: write (x3, y3, phi4, x5) by Newton-Raphson
    not_done('c', 'Newton on e = 0 for the dependent coordinates, from the drawn configuration')


def configuration(phi2):
    x = np.zeros(8)
    x[2] = phi2
    x[DEPENDENT] = positions(phi2)
    return x


# %%
def velocities(phi2, phi2d):
    """Part d: xd (8,) from the partitioned Jacobian. Uses parts b and c."""
    # part d: write xd (8,) from the partitioned Jacobian
    not_done('d', 'D_c xd_c = -D_m phi2d; the fixed rates are 0')


# %%
def first_order_transfer(phi2):
    """Part e: F_q (8, 1) = dx/dphi2. Uses part d."""
    # part e: write F_q (8, 1) = dx/dphi2
    not_done('e', 'the velocities for phi2d = 1')


# %%
def deformation_transfer(phi2):
    """Part f: E_q (4, 1) = D_x F_q, from your jacobian() and first_order_transfer()."""
    # part f: write E_q (4, 1) = D_x F_q (zero: all rigid)
    not_done('f', 'E_q = D_x F_q, from your parts b and e')


def quadratic(x, xd):
    """(D_xx xd) xd (4,) of both rigid beams (THEORY 2)."""
    out = []
    for c, _ in BEAMS:
        d, dv = x[c[3:5]] - x[c[0:2]], xd[c[3:5]] - xd[c[0:2]]
        length, w = np.hypot(*d), xd[c[2]]
        e_p = np.array([np.cos(x[c[2]]), np.sin(x[c[2]])])
        n_p = np.array([-np.sin(x[c[2]]), np.cos(x[c[2]])])
        out += [(dv @ dv - (d @ dv / length) ** 2) / length,
                -w**2 * (n_p @ d) - 2 * w * (e_p @ dv)]
    return np.array(out)


# %%
def second_order_transfer(phi2):
    """Part g: F_qq (8, 1) = d^2x/dphi2^2 (the accelerations for phi2d = 1, phi2dd = 0).
    Uses parts b, c and d."""
    # part g: write F_qq (8, 1): d^2x/dphi2^2
    not_done('g', 'the accelerations for phi2d = 1, phi2dd = 0')


# %%
def deformation_second_order(phi2):
    """Part h: E_qq (4, 1) = D_x F_qq + (D_xx F_q) F_q (zero for rigid beams), from your
    jacobian(), first_order_transfer() and second_order_transfer() and quadratic()."""
    # part h: write E_qq (4, 1)
    not_done('h', 'E_qq = D_x F_qq + (D_xx F_q) F_q, from your parts b, e and g')


# %%
def accelerations(phi2, phi2d, phi2dd):
    """Part i: xdd (8,) = F_q phi2dd + F_qq phi2d^2. Uses parts e and g."""
    # part i: write xdd (8,) = F_q phi2dd + F_qq phi2d^2
    not_done('i', 'xdd = F_q phi2dd + F_qq phi2d^2')


# %% [markdown]
# ## Run it: the drawn configuration, phi2 = 60 degrees (phi4 = -30 degrees)

# %%
if __name__ == "__main__":
    phi = np.pi / 3
    show("c  (x3, y3, phi4, x5), expect phi4 = -0.5236, x5 = 2", positions, phi)
    show("b  D", jacobian, drawn_guess(phi))
    show("d  xd at phi2d = 2 pi", velocities, phi, 2 * np.pi)
    show("e  F_q", first_order_transfer, phi)
    show("f  E_q (zero: all rigid)", deformation_transfer, phi)
    show("g  F_qq", second_order_transfer, phi)
    show("h  E_qq", deformation_second_order, phi)
    show("i  xdd", accelerations, phi, 2 * np.pi, 2 * np.pi)
