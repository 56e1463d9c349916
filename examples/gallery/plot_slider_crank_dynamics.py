"""
A PD-controlled crank and its driving torque (exercise 3)
=========================================================

The rigid slider-crank of exercise 2 with a rod of mass ``m2`` and a slider of
mass ``m5``. Instead of prescribing the crank angle, a PD controller applies a
torque that makes the crank follow a reference angle, and the mechanism is
simulated forward, as the course did in Simulink. The torque the controller
applied is then compared with the inverse dynamics of the motion it realised:
two different computations of the same torque.
"""

# %%
# The model, twice: with the crank angle a degree of freedom, turned by the
# controller's torque, and with it prescribed, for the inverse dynamics of the same
# motion. The rod's mass is distributed; the slider is a point mass at B.
import math
import os

import matplotlib.pyplot as plt
import numpy as np
from flexmbd.examples import slider_crank_dynamics as dyn

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
l1, l2, m2 = 0.15, 0.30, 0.06676                      # crank, rod [m]; rod mass [kg]


def slider_crank(crank=None):
    """The slider-crank; the crank angle follows ``crank`` (a law) or is free."""
    b = fm.ModelBuilder("slider-crank")
    b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3).add_rigid_beam(2, 3, 4, 5)    # crank O-A, rod A-B
    b.fix(1).fix(5, "y")
    if crank is None:
        b.dynamic_coordinate(2)
    else:
        b.input_coordinate(2, law=crank)
    b.set_mass(2, m2 / l2).add_point_mass(5, m2 / 2)
    return b.build()


model = slider_crank()
law = dyn.reference(dyn.OMEGA)                      # speeds up to 150 rad/s
controller = dyn.pd_controller(model, law, dyn.pd_gains())
times = np.linspace(0.0, dyn.RAMP + (1.0 if QUICK else 3.0) * 2 * math.pi / dyn.OMEGA,
                    151 if QUICK else 601)
result = fm.simulate(model, times, forces=controller, rtol=1e-9, atol=1e-12)
torque = np.array([controller(t, x, xd)["x2.1"]
                   for t, x, xd in zip(result.t, result.x, result.xd, strict=True)])


def sampled(values):
    return lambda time: float(values[int(np.argmin(np.abs(result.t - time)))])


realised = fm.Custom(sampled(result["x2.1"]), sampled(result["xd2.1"]),
                     sampled(result["xdd2.1"]))
replayed = fm.inverse_dynamics(slider_crank(realised), result.t)["f2.1"]
reference = np.array([law(t)[0] for t in result.t])
print(f"largest |controller - inverse dynamics|: {np.abs(torque - replayed).max():.1e} N m "
      f"of {np.abs(torque).max():.3g} N m")

# %%
# The reference and the realised crank angle, and the two torques
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
top.plot(result.t, reference, "--", label="reference")
top.plot(result.t, result["x2.1"], label="realised")
top.set_ylabel("crank angle [rad]")
top.legend()
bottom.plot(result.t, torque, label="PD controller")
bottom.plot(result.t, replayed, "--", label="inverse dynamics of the realised motion")
bottom.set_ylabel("torque [N m]")
bottom.set_xlabel("t [s]")
bottom.legend(fontsize="small")
for ax in (top, bottom):
    ax.grid(True, alpha=0.3)
fig.tight_layout()
