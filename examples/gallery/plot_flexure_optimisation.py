"""
Optimising a flexure: the stiffest parallel guide within a stress limit
=======================================================================

A parallel leaf-spring guide carries a stage 4 mm across its two leaves. Along the
leaves it should be stiff (its support stiffness), but thicker leaves bend with more
stress and need more drive force. ``flexmbd.design`` gives the support compliance, the
largest stress and the drive force with their exact derivatives to the leaves'
thickness and length; ``design.optimize`` finds the best design on them, which a root
search on the analyses alone confirms.
"""

# %%
# The design: two steel leaves (20 mm wide, thickness ``t``, length ``L``) upright,
# 40 mm apart, a stage across their tops driven 4 mm along x (an input coordinate).
# The over-constraint of the closed loop is released as SPACAR Light does.
import os

import matplotlib.pyplot as plt
import numpy as np
from scipy.optimize import brentq

import flexmbd as fm
from flexmbd import design

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
BEAMS = 4 if QUICK else 8
STRESS, FORCE = 300e6, 5.0          # the limits: von Mises stress [Pa], drive force [N]


def guide(t, L, beams=BEAMS):
    steel = fm.Material.from_poisson(210e9, 0.3, 7800.0)
    leaf = fm.Rectangle(0.02, t)
    b = fm.ModelBuilder("parallel guide")
    b.add_node(1, 0, 0, 0).add_node(3, 0, 0, L).add_node(5, 0.04, 0, 0).add_node(7, 0.04, 0, L)
    b.add_spatial_beams(1, 1, 2, 3, 4, beams, (0, 1, 0), new_nodes=1000, section=leaf,
                        material=steel)
    b.add_spatial_beams(101, 5, 6, 7, 8, beams, (0, 1, 0), new_nodes=2000, section=leaf,
                        material=steel)
    b.add_node(9, 0.02, 0, L)        # the stage's middle
    b.add_spatial_beam(201, 3, 4, 9, 10, (0, 1, 0)).add_spatial_beam(202, 9, 10, 7, 8,
                                                                     (0, 1, 0))
    b.fix(1).fix(2).fix(5).fix(6).input_coordinate(9, 1)
    b.add_point_mass(9, 0.1)
    b.release_overconstraints()
    return b.build(), fm.RunSettings(input_increment={"x9.1": 4e-3}, load_steps=4)


# %%
# One design with its gradients: the stage's compliance along the leaves
# (``C[9,10][2,2]``), the largest stress and the drive force (the reaction on the
# driven coordinate, ``f9.1``), each with its derivative to ``t`` and ``L``.
OUTPUTS = ["C[9,10][2,2]", "stress_max", "f9.1"]
start = {"t": 0.3e-3, "L": 0.06}
r = design.evaluate(guide, start, OUTPUTS)
print(r)

# %%
# The gradients against central differences of the analyses, and a Taylor test: the
# remainder of the linear prediction falls with the square of the step.
check = design.check_gradient(guide, start, OUTPUTS)
print(check)
assert check.worst < 1e-4

# %%
# The best design: the least compliance along the leaves with the stress and the drive
# force within their limits, the thickness between 0.1 and 3 mm, the length between 30
# and 200 mm.
found = design.optimize(guide, start, "C[9,10][2,2]",
                        constraints={"stress_max": (None, STRESS), "f9.1": (None, FORCE)},
                        bounds={"t": (0.1e-3, 3e-3), "L": (0.03, 0.2)})
print(f"t = {1e3 * found.x['t']:.6f} mm, L = {1e3 * found.x['L']:.3f} mm: support "
      f"stiffness {1e-6 / found.fun:.4g} N/um, stress {found.outputs['stress_max'] / 1e6:.1f} "
      f"MPa, drive force {found.outputs['f9.1']:.4f} N, in {found.nfev} analyses")

# %%
# Longer leaves are better here at any thickness the force allows, so the optimum has
# the length at its bound and the drive force at its limit; a root search on the drive
# force alone (no gradients) finds the same thickness.
root = brentq(lambda t: design.evaluate(guide, {"t": t, "L": 0.2}, "f9.1", gradient=False)
              .values["f9.1"] - FORCE, 0.3e-3, 3e-3, xtol=1e-16, rtol=1e-15)
print(f"root search: t = {1e3 * root:.6f} mm; the optimiser's is off by "
      f"{abs(found.x['t'] - root) / root:.1e}")
assert abs(found.x["t"] - root) < 1e-6 * root and abs(found.x["L"] - 0.2) < 1e-9

# %%
# The design space: the objective's contours, the two limits and the optimiser's path.
n = 5 if QUICK else 11
ts, Ls = np.linspace(0.3e-3, 1.6e-3, n), np.linspace(0.04, 0.2, n)
grid = {k: np.empty((n, n)) for k in OUTPUTS}
for i, L in enumerate(Ls):
    for j, t in enumerate(ts):
        values = design.evaluate(guide, {"t": t, "L": L}, OUTPUTS, gradient=False).values
        for k in OUTPUTS:
            grid[k][i, j] = values[k]
fig, ax = plt.subplots(figsize=(6.5, 4.5))
T, Lg = np.meshgrid(1e3 * ts, 1e3 * Ls)
shade = ax.contourf(T, Lg, np.log10(1e-6 / grid["C[9,10][2,2]"]), 12, cmap="viridis")
fig.colorbar(shade, label="log10 support stiffness [N/um]")
ax.contour(T, Lg, grid["stress_max"], [STRESS], colors="w", linestyles="--")
ax.contour(T, Lg, grid["f9.1"], [FORCE], colors="orange")
path = np.array([[1e3 * h["params"]["t"], 1e3 * h["params"]["L"]] for h in found.history])
ax.plot(path[:, 0], path[:, 1], "r.-", label="SLSQP's analyses")
ax.plot(1e3 * found.x["t"], 1e3 * found.x["L"], "r*", ms=14, label="optimum")
ax.set_xlabel("leaf thickness t [mm]")
ax.set_ylabel("leaf length L [mm]")
ax.set_title("stress limit (white, dashed), drive-force limit (orange)")
ax.legend(loc="lower right")
fig.tight_layout()
