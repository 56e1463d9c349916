# %% [markdown]
# # Exercise 1: the sliding bar
#
# A rigid bar of length `l0 = 2 m` has end p on the x axis and end q on the y axis.
# Parts a-d model it as a truss, `x = [x_p, y_p, x_q, y_q]` with `x_p` prescribed;
# parts e-j as a rigid beam with a rotational node at p,
# `x = [x_p, y_p, phi_p, x_q, y_q]` with `phi_p` prescribed (horizontal at
# `phi_p = 0`, `beta0 = 0`). Write each function below; check your file with
# `flexmbd exercise check sliding-bar THIS_FILE`.

# %%
import numpy as np

from flexmbd.course.student import not_done, show  # noqa: F401

L0 = 2.0  # bar length [m]


# %% [markdown]
# ## 1a-d: the truss

# %%
def truss_elongation(x):
    """Part a: e1 = l - l0 [m] at x = [x_p, y_p, x_q, y_q]."""
    # part a: write e1 = l - l0 [m] of the truss p-q at x = [x_p, y_p, x_q, y_q]
    not_done('a', 'e1 = |r_q - r_p| - l0')


# %%
def truss_jacobian(x):
    """Part b: D_x (1, 4), the derivative of e1 with respect to x."""
    # part b: write D_x (1, 4): de1/dx
    not_done('b', 'differentiate e1 with respect to each of x_p, y_p, x_q, y_q: a row (1, 4)')


# %%
def truss_position(x_p):
    """Part c: y_q [m] for the input x_p, by Newton-Raphson from y_q = 1. Uses parts a, b."""
    # part c: write y_q [m] by Newton-Raphson from y_q = 1
    not_done('c', 'iterate y_q -= e1 / (de1/dy_q) from y_q = 1 until |e1| < 1e-12')


# %%
def truss_motion(x_p, xd_p, xdd_p):
    """Part d: (yd_q, ydd_q) [m/s, m/s^2] from the partitioned Jacobian and the quadratic
    velocity term."""
    # part d: write (yd_q, ydd_q) [m/s, m/s^2] from the partitioned Jacobian and the quadratic velocity term
    not_done('d', 'D_c yd_q = -D_m xd_p; D_c ydd_q = -D_m xdd_p - (D_xx xd) xd')


# %% [markdown]
# ## 1e-j: the rigid beam

# %%
def rigid_beam_deformations(x):
    """Part e: (e1, e2) [m] at x = [x_p, y_p, phi_p, x_q, y_q]: e1 = l - l0, e2 = n_p . d."""
    # part e: write (e1, e2) [m] of the rigid beam at x = [x_p, y_p, phi_p, x_q, y_q], beta0 = 0
    not_done('e', 'e1 = |d| - l0, e2 = n_p . d with d = r_q - r_p, n_p = (-sin phi_p, cos phi_p)')


# %%
def rigid_beam_jacobian(x):
    """Part f: D_x (2, 5), rows (e1, e2), columns (x_p, y_p, phi_p, x_q, y_q)."""
    # part f: write D_x (2, 5)
    not_done('f', 'rows e1, e2; columns x_p, y_p, phi_p, x_q, y_q')


DEPENDENT = [0, 4]  # x_p and y_q
INPUT = [2]  # phi_p


def _beam_configuration(phi_p):
    x = np.array([-L0, 0.0, phi_p, 0.0, 0.0])
    x[[0, 4]] = rigid_beam_position(phi_p)
    return x


# %%
def rigid_beam_position(phi_p):
    """Part g: (x_p, y_q) [m] for the input phi_p [rad], by Newton-Raphson. Uses parts e
    and f."""
    # part g: write (x_p, y_q) [m] by Newton-Raphson
    not_done('g', 'Newton on (e1, e2) = 0 for the dependent x_p, y_q')


# %%
def rigid_beam_velocities(phi_p, omega):
    """Part h: (xd_p, yd_q) [m/s] for phi_p [rad] and omega [rad/s]."""
    # part h: write (xd_p, yd_q) [m/s]
    not_done('h', 'D_c [xd_p, yd_q] = -D_m omega')


# %%
def rigid_beam_quadratic(x, xd):
    """Part i: (D_xx xd) xd (2,) [m/s^2]."""
    # part i: write (D_xx xd) xd (2,) [m/s^2]
    not_done('i', 'e1: (dv.dv - (e_l.dv)^2)/l; e2: -w^2 (n_p . d) - 2 w (e_p . dv)')


# %%
def rigid_beam_accelerations(phi_p, omega, omegad):
    """Part j: (xdd_p, ydd_q) [m/s^2] for phi_p, omega, omegad."""
    # part j: write (xdd_p, ydd_q) [m/s^2]
    not_done('j', 'D_c xdd_c = -D_m omegad - (D_xx xd) xd')


# %% [markdown]
# ## Run it
# In the drawn configuration (30 degrees) the truss with `xd_p = 4` gives
# `yd_q = 4 sqrt(3)` and `ydd_q = -64`; the rigid beam with `omega = 4` gives
# `xd_p = 4`, and `omegad = -16 sqrt(3)` keeps `xdd_p = 0`.

# %%
if __name__ == "__main__":
    drawn = np.array([-np.sqrt(3.0), 0.0, 0.0, 1.0])
    show("a  e1", truss_elongation, drawn)
    show("b  D_x", truss_jacobian, drawn)
    show("c  y_q", truss_position, -np.sqrt(3.0))
    show("d  (yd_q, ydd_q), expect (6.928, -64)", truss_motion, -np.sqrt(3.0), 4.0, 0.0)
    beam = np.array([-np.sqrt(3.0), 0.0, np.pi / 6, 0.0, 1.0])
    show("e  (e1, e2)", rigid_beam_deformations, beam)
    show("f  D_x", rigid_beam_jacobian, beam)
    show("g  (x_p, y_q)", rigid_beam_position, np.pi / 6)
    show("h  (xd_p, yd_q), expect (4, 6.928)", rigid_beam_velocities, np.pi / 6, 4.0)
    show("i  (D_xx xd) xd", rigid_beam_quadratic, beam, np.array([4, 0, 4, 0, 4 * np.sqrt(3)]))
    show("j  (xdd_p, ydd_q), expect xdd_p = 0", rigid_beam_accelerations, np.pi / 6, 4.0,
         -16 * np.sqrt(3.0))
