# %% [markdown]
# # Exercise 3: slider-crank dynamics
#
# The slider-crank of exercise 2 with the dimensions of exercise 4: crank `l1 = 0.15 m`
# (massless), rod `l2 = 0.30 m` with mass `m2 = 0.06676 kg` spread uniformly, slider
# mass `m5 = m2/2`, no gravity. `x = [x1, y1, phi2, x3, y3, phi4, x5, y5]`; the rod's
# coordinates are `[x3, y3, phi4, x5, y5]` (indices 3-7). Given: the kinematics of
# exercise 2 for these lengths. Check your file with
# `flexmbd exercise check slider-crank-dynamics THIS_FILE`.

# %%
import numpy as np
from scipy.integrate import solve_ivp

from flexmbd.course.student import not_done, show  # noqa: F401

L1, L2 = 0.15, 0.30  # [m]
M2 = 0.06676  # rod mass [kg]
M5 = M2 / 2  # slider mass [kg]
ROD = [3, 4, 5, 6, 7]
BEAMS = [([0, 1, 2, 3, 4], L1), (ROD, L2)]
DEPENDENT, INPUT, FIXED = [3, 4, 5, 6], [2], [0, 1, 7]


# %% [markdown]
# ## Given: the kinematics (exercise 2)

# %%
def geometry(x, c):
    d = x[c[3:5]] - x[c[0:2]]
    e_p = np.array([np.cos(x[c[2]]), np.sin(x[c[2]])])
    n_p = np.array([-e_p[1], e_p[0]])
    return d, e_p, n_p


def jacobian(x):
    D = np.zeros((4, 8))
    for k, (c, _) in enumerate(BEAMS):
        d, e_p, n_p = geometry(x, c)
        e_l = d / np.hypot(*d)
        D[2 * k, c] = [-e_l[0], -e_l[1], 0.0, e_l[0], e_l[1]]
        D[2 * k + 1, c] = [-n_p[0], -n_p[1], -e_p @ d, n_p[0], n_p[1]]
    return D


def configuration(phi2):
    psi = -np.arcsin(L1 * np.sin(phi2) / L2)  # closed form (exercise 2 used Newton)
    return np.array([0.0, 0.0, phi2, L1 * np.cos(phi2), L1 * np.sin(phi2), psi,
                     L1 * np.cos(phi2) + L2 * np.cos(psi), 0.0])


def transfer(phi2):
    """(x, F_q (8,), F_qq (8,)) at the crank angle phi2."""
    x = configuration(phi2)
    D = jacobian(x)
    D_c = D[:, DEPENDENT]
    F_q = np.zeros(8)
    F_q[2] = 1.0
    F_q[DEPENDENT] = np.linalg.solve(D_c, -D[:, INPUT] @ [1.0])
    quadratic = []
    for c, _ in BEAMS:
        d, e_p, n_p = geometry(x, c)
        dv, w = F_q[c[3:5]] - F_q[c[0:2]], F_q[c[2]]
        length = np.hypot(*d)
        quadratic += [(dv @ dv - (d @ dv / length) ** 2) / length,
                      -w**2 * (n_p @ d) - 2 * w * (e_p @ dv)]
    F_qq = np.zeros(8)
    F_qq[DEPENDENT] = np.linalg.solve(D_c, -np.array(quadratic))
    return x, F_q, F_qq


# %% [markdown]
# ## 3a-h

# %%
def rod_mass_lumped(x):
    """Part a: M (5, 5) of the rod over [x3, y3, phi4, x5, y5], lumped."""
    # part a: write M (5, 5) [kg, kg m^2]: lumped rod mass over [x3, y3, phi4, x5, y5]
    not_done('a', 'm2/2 at each end and the rotary inertia m2 l2^2/12 - m2 l2^2/4 at phi4')


# %%
def rod_mass_consistent(x):
    """Part b: M (5, 5) of the rod, consistent: m2/6 [[2I, I], [I, 2I]] over (r_A, r_B)."""
    # part b: write M (5, 5): consistent rod mass
    not_done('b', 'm2/6 [[2I, I], [I, 2I]] over (r_A, r_B), zero on phi4')


def system_mass(x, rod_mass):
    M = np.zeros((8, 8))
    M[np.ix_(ROD, ROD)] = rod_mass(x)
    M[6, 6] += M5
    M[7, 7] += M5
    return M


# %%
def reduced_mass_lumped(phi2):
    """Part c: Mbar (1, 1) [kg m^2] with the lumped rod. Uses part a."""
    # part c: write Mbar (1, 1) [kg m^2] with the lumped rod
    not_done('c', 'Mbar = F_q^T M F_q with the lumped rod and the slider')


# %%
def reduced_mass_consistent(phi2):
    """Part d: Mbar (1, 1) [kg m^2] with the consistent rod. Uses part b."""
    # part d: write Mbar (1, 1) with the consistent rod
    not_done('d', 'Mbar = F_q^T M F_q with the consistent rod and the slider')


# %%
def driving_torque(phi2, phi2d, phi2dd):
    """Part e: tau2 [N m] for the crank motion (phi2, phi2d, phi2dd). Uses part b."""
    # part e: write tau2 [N m] (inverse dynamics)
    not_done('e', 'tau2 = Mbar phi2dd + F_q^T (M F_qq phi2d^2 + h)')


# %%
def constraint_stresses(phi2, phi2d, phi2dd):
    """Part f: sigma(o) (4,) [N, N m] of the rigid deformations."""
    # part f: write sigma(o) (4,) [N, N m]: the rigid deformations' stresses
    not_done('f', 'D_c^T sigma = -(M xdd + h) on the dependent rows')


# %%
def reactions(phi2, phi2d, phi2dd):
    """Part g: f(o) (3,) [N] on x1, y1 and y5."""
    # part g: write f(o) (3,) [N]: the support reactions at O (x, y) and the slider's y
    not_done('g', 'f(o) = D_x^T sigma + M xdd + h on the fixed rows x1, y1, y5')


# %%
def crank_acceleration(phi2, phi2d, tau2):
    """Part h: phi2dd [rad/s^2] under the crank torque tau2 [N m]. Uses part b."""
    # part h: write phi2dd [rad/s^2] under the crank torque tau2 (forward dynamics; the given PD-controlled simulation integrates it)
    not_done('h', 'Mbar phi2dd = tau2 - F_q^T (M F_qq phi2d^2 + h)')


# %% [markdown]
# ## Given: the PD-controlled crank
# The reference speeds up to 150 rad/s with time constant 0.02 s; the controller is
# `tau2 = kp (ref - phi2) + kd (refd - phi2d)` with a closed-loop bandwidth of
# 300 rad/s for the mean inertia.

# %%
def pd_simulation(t_end=0.1, omega=150.0, ramp=0.02, bandwidth=300.0):
    inertia = reduced_mass_consistent(0.0)[0, 0]
    kp, kd = inertia * bandwidth**2, 2 * inertia * bandwidth

    def reference(t):
        return omega * (t - ramp * (1 - np.exp(-t / ramp))), omega * (1 - np.exp(-t / ramp))

    def rhs(t, state):
        ref, refd = reference(t)
        tau2 = kp * (ref - state[0]) + kd * (refd - state[1])
        return [state[1], crank_acceleration(state[0], state[1], tau2)]

    run = solve_ivp(rhs, (0.0, t_end), [0.0, 0.0], rtol=1e-8, atol=1e-10, max_step=1e-3)
    return run.t, run.y[0], reference(run.t)[0]


# %%
if __name__ == "__main__":
    x60 = configuration(np.pi / 3)
    show("a  lumped rod mass", rod_mass_lumped, x60)
    show("b  consistent rod mass", rod_mass_consistent, x60)
    show("c  Mbar lumped", reduced_mass_lumped, np.pi / 3)
    show("d  Mbar consistent (equal to c)", reduced_mass_consistent, np.pi / 3)
    show("e  tau2 at (60 deg, 150 rad/s, 0)", driving_torque, np.pi / 3, 150.0, 0.0)
    show("f  sigma(o)", constraint_stresses, np.pi / 3, 150.0, 0.0)
    show("g  f(o)", reactions, np.pi / 3, 150.0, 0.0)
    result = show("h  PD simulation: (t, phi2, reference)", pd_simulation)
    if result is not None:
        t, phi2, ref = result
        print(f"   largest tracking error {np.max(np.abs(ref - phi2)):.3g} rad")
