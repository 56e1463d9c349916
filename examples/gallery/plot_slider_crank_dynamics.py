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
import os

import matplotlib.pyplot as plt
import numpy as np
from flexmbd.examples import slider_crank_dynamics as dyn

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"

result, torque, law = dyn.pd_simulation(revolutions=1.0 if QUICK else 3.0,
                                        points=150 if QUICK else 600)
replayed = dyn.replay_torque(result, gravity=False)
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
