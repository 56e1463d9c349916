"""SPACAR Light's front door in Python: arrays of nodes and elements, property sets with
sections and materials, and per load step the positions, reactions, frequencies, buckling
load factors, largest stress and 6x6 compliance of every node.

A SPACAR Light script ports line by line::

    from flexmbd import light
    nodes = [[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.1, 0, 0]]
    elements = [[1, 3], [2, 3], [2, 4]]
    nprops = {1: {"fix": True}, 3: {"moment": [0, 0, 0.05]}, 4: {"fix": True}}
    eprops = [{"elems": [1, 3], "emod": 210e9, "smod": 70e9, "dens": 7800,
               "cshape": "rect", "dim": [50e-3, 0.2e-3], "orien": [0, 0, 1],
               "nbeams": 3, "flex": [1, 2, 3, 4, 5, 6]}, ...]
    res = light.run(nodes, elements, nprops, eprops, {"gravity": [0, 0, -9.81]})
    res.node[3].p          # (3, nsteps), user node 3
    res.step[10].freq      # the eigenfrequencies at load step 10

Numbers are 1-based as in MATLAB. :func:`run` builds an ordinary flexmbd model
(:func:`build` returns it without running), numbered as SPACAR Light numbers its ``.dat``
file; :func:`show_input` draws the numbered input (``opt.showinputonly``).
"""

from .build import LightModel
from .picture import show_input
from .results import ElementResult, LightResult, NodeResult, OneBased, StepResult
from .run import build, run

__all__ = ["ElementResult", "LightModel", "LightResult", "NodeResult", "OneBased",
           "StepResult", "build", "run", "show_input"]
