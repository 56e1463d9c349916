"""
Convergence in the number of beams: a parameter study (exercise 4, part 2)
==========================================================================

How many beams does the rod need? :func:`flexmbd.sweep` runs the flexible
slider-crank once per number of beams and keeps the ``v/l2`` history and its
peak of each case. Here it runs in this process (``client="serial"``); without
that argument the same call runs the cases on a local Dask cluster, one worker
per core. The peaks settle as the rod is refined: from 2 to 8 beams the curve
changes by about 1e-3 of ``l2`` or less.
"""

# %%
import os

from flexmbd.examples import slider_crank_flex as flex

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"

nbeams = [1, 2, 4] if QUICK else [1, 2, 3, 4, 6, 8]
data = flex.study(nbeams, revolutions=1.0 if QUICK else 2.0, client="serial", progress=False)
for n, peak in zip(data["nbeams"].values, data["peak"].values, strict=True):
    print(f"{n} beams: peak |v/l2| = {peak:.6f}")

# %%
# The histories together, and the peak against the number of beams
fig = flex.plot_convergence(data, window=True)
