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
    # BEGIN SOLUTION
    d = np.array([x[2] - x[0], x[3] - x[1]])
    return np.array([np.hypot(d[0], d[1]) - L0])
    # END SOLUTION


# %%
def truss_jacobian(x):
    """Part b: D_x (1, 4), the derivative of e1 with respect to x."""
    # BEGIN SOLUTION
    d = np.array([x[2] - x[0], x[3] - x[1]])
    e_l = d / np.hypot(d[0], d[1])
    return np.array([[-e_l[0], -e_l[1], e_l[0], e_l[1]]])
    # END SOLUTION


# %%
def truss_position(x_p):
    """Part c: y_q [m] for the input x_p, by Newton-Raphson from y_q = 1. Uses parts a, b."""
    # BEGIN SOLUTION
    x = np.array([x_p, 0.0, 0.0, 1.0])
    for _ in range(50):
        e = truss_elongation(x)[0]
        if abs(e) < 1e-13:
            return x[3]
        x[3] -= e / truss_jacobian(x)[0, 3]
    raise RuntimeError("Newton-Raphson did not converge")
    # END SOLUTION


# %%
def truss_motion(x_p, xd_p, xdd_p):
    """Part d: (yd_q, ydd_q) [m/s, m/s^2] from the partitioned Jacobian and the quadratic
    velocity term."""
    # BEGIN SOLUTION
    x = np.array([x_p, 0.0, 0.0, truss_position(x_p)])
    D = truss_jacobian(x)[0]
    yd_q = -D[0] * xd_p / D[3]
    dv = np.array([-xd_p, yd_q])  # rate of d = r_q - r_p
    d = np.array([-x_p, x[3]])
    length = np.hypot(*d)
    quadratic = (dv @ dv - (d @ dv / length) ** 2) / length
    ydd_q = (-D[0] * xdd_p - quadratic) / D[3]
    return np.array([yd_q, ydd_q])
    # END SOLUTION


# %% [markdown]
# ## 1e-j: the rigid beam

# %%
def rigid_beam_deformations(x):
    """Part e: (e1, e2) [m] at x = [x_p, y_p, phi_p, x_q, y_q]: e1 = l - l0, e2 = n_p . d."""
    # BEGIN SOLUTION
    d = np.array([x[3] - x[0], x[4] - x[1]])
    n_p = np.array([-np.sin(x[2]), np.cos(x[2])])
    return np.array([np.hypot(d[0], d[1]) - L0, n_p @ d])
    # END SOLUTION


# %%
def rigid_beam_jacobian(x):
    """Part f: D_x (2, 5), rows (e1, e2), columns (x_p, y_p, phi_p, x_q, y_q)."""
    # BEGIN SOLUTION
    d = np.array([x[3] - x[0], x[4] - x[1]])
    e_l = d / np.hypot(d[0], d[1])
    e_p = np.array([np.cos(x[2]), np.sin(x[2])])
    n_p = np.array([-np.sin(x[2]), np.cos(x[2])])
    return np.array([[-e_l[0], -e_l[1], 0.0, e_l[0], e_l[1]],
                     [-n_p[0], -n_p[1], -e_p @ d, n_p[0], n_p[1]]])
    # END SOLUTION


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
    # BEGIN SOLUTION
    x = np.array([-L0 * np.cos(phi_p) - 0.1, 0.0, phi_p, 0.0, L0 * np.sin(phi_p) + 0.1])
    for _ in range(50):
        e = rigid_beam_deformations(x)
        if np.max(np.abs(e)) < 1e-13:
            return x[DEPENDENT]
        D_c = rigid_beam_jacobian(x)[:, DEPENDENT]
        x[DEPENDENT] -= np.linalg.solve(D_c, e)
    raise RuntimeError("Newton-Raphson did not converge")
    # END SOLUTION


# %%
def rigid_beam_velocities(phi_p, omega):
    """Part h: (xd_p, yd_q) [m/s] for phi_p [rad] and omega [rad/s]."""
    # BEGIN SOLUTION
    D = rigid_beam_jacobian(_beam_configuration(phi_p))
    return np.linalg.solve(D[:, DEPENDENT], -D[:, INPUT] @ [omega])
    # END SOLUTION


# %%
def rigid_beam_quadratic(x, xd):
    """Part i: (D_xx xd) xd (2,) [m/s^2]."""
    # BEGIN SOLUTION
    d = np.array([x[3] - x[0], x[4] - x[1]])
    dv = np.array([xd[3] - xd[0], xd[4] - xd[1]])
    length = np.hypot(d[0], d[1])
    w = xd[2]
    e_p = np.array([np.cos(x[2]), np.sin(x[2])])
    n_p = np.array([-np.sin(x[2]), np.cos(x[2])])
    return np.array([(dv @ dv - (d @ dv / length) ** 2) / length,
                     -w**2 * (n_p @ d) - 2 * w * (e_p @ dv)])
    # END SOLUTION


# %%
def rigid_beam_accelerations(phi_p, omega, omegad):
    """Part j: (xdd_p, ydd_q) [m/s^2] for phi_p, omega, omegad."""
    # BEGIN SOLUTION
    x = _beam_configuration(phi_p)
    xd = np.zeros(5)
    xd[2] = omega
    xd[DEPENDENT] = rigid_beam_velocities(phi_p, omega)
    D = rigid_beam_jacobian(x)
    rhs = -D[:, INPUT] @ [omegad] - rigid_beam_quadratic(x, xd)
    return np.linalg.solve(D[:, DEPENDENT], rhs)
    # END SOLUTION


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
