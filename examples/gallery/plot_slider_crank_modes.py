"""
Frequencies of the flexible rod along a crank revolution
========================================================

The linearized equations of motion about each configuration of a revolution
give the rod's vibration frequencies there. At rest the rod of the
slider-crank is pinned at both ends in every configuration, so its frequencies
are those of a pinned-pinned beam; in motion the inertia terms ``N0`` and
``C0`` change them by a few per cent, symmetrically about the half turn.
"""

# %%
import os

from flexmbd.examples import slider_crank_modes as modes

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"

model = modes.build_model(4)
path = modes.motion(model, points=19 if QUICK else 73, simulated=False, omega=modes.OMEGA)
along = fm.modes_along(path, 3, progress=False)
columns = modes.table(along)
print(f"f1 from {along.frequencies[:, 0].min():.5g} to {along.frequencies[:, 0].max():.5g} Hz")

# %%
fig = modes.plot_frequencies(model, columns, window=True)
