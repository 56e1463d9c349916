"""Flexures through the SPACAR Light front door (:mod:`flexmbd.light`): SPACAR Light's
shipped examples ported, and a design study of a parallel guide.

* **Cross hinge** (SPACAR Light's own example, as shipped): two steel leaves 50 x 0.2 mm
  crossing at their middles under a rigid body, with warping and gravity; a force and a
  moment (from -0.025 to 0.025 N m) over 10 load steps. Checked unloaded: the body's
  stiffness about the pivot axis is ``2 EI/L`` (each leaf in pure bending).
* **Parallel guide with its transfer function**: leaves 50 mm long, 20 x 0.5 mm, 40 mm
  apart, a 0.1 kg stage; the state-space model from a force on the stage to its motion,
  1 % modal damping. Checked: the static gain is the guide's compliance, its stiffness
  within 2e-4 of ``24 EI/L^3 / (1 + Phi)`` (shear; the rest is the stage's tilt), and the
  first frequency within 1e-4 of Rayleigh's ``sqrt(k / (M + 2 (13/35) m_leaf))``.
* **Wire flexure buckling**: a stage on four steel wires (1 mm, 50 mm long) at the
  corners of a 40 mm square, 1 N pressing down. Checked: the buckling load factor against
  ``4 pi^2 EI/L^2`` with shear (``P / (1 + P/(k G A))`` per wire), to 1e-3.
* **Study** (:func:`guide_study`): the guide driven along its stroke, its support
  stiffness (along the leaves, the drive held) and peak stress against the stroke and
  the leaf thickness, one case per pair on Dask (:func:`flexmbd.sweep`). At zero stroke
  the stiffness is ``2 EA/L``; the stress of a stroke ``u`` is ``3 E t u / L^2``.

Run: ``flexmbd example flexures --plot hinge.png --movie hinge.gif`` (the cross hinge's
frequencies and stress over its load steps, and the steps as a movie).
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    Check,
    add_output_options,
    example_parser,
    finish_outputs,
    parse,
    print_checks,
)

import flexmbd as fm
from flexmbd import light

ALL = [1, 2, 3, 4, 5, 6]
STEEL_E, STEEL_G, STEEL_RHO = 210e9, 210e9 / 2.6, 7800.0   #: nu = 0.3

# --- the cross hinge, as SPACAR Light ships it --------------------------------------------
HINGE_NODES = [[0, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.1, 0, 0]]
HINGE_ELEMENTS = [[1, 3], [2, 3], [2, 4]]
HINGE_LEAF = {"elems": [1, 3], "emod": 210e9, "smod": 70e9, "dens": 7800,
              "cshape": "rect", "dim": [50e-3, 0.2e-3], "orien": [0, 0, 1], "nbeams": 3,
              "flex": ALL, "color": "grey", "opacity": 0.7, "warping": True}
HINGE_BODY = {"elems": 2, "dens": 3000, "cshape": "rect", "dim": [50e-3, 10e-3],
              "orien": [0, 0, 1], "nbeams": 1, "color": "darkblue", "warping": True}


def cross_hinge(loaded: bool = True) -> light.LightResult:
    """SPACAR Light's example; ``loaded=False``: without loads and gravity, one step."""
    nprops: dict = {1: {"fix": True}, 4: {"fix": True}}
    opt: dict = {"silent": True}
    if loaded:
        nprops[3] = {"force": [0, 1, 0], "moment_initial": [0, 0, -0.025],
                     "moment": [0, 0, 0.05], "mass": 0.1}
        opt["gravity"] = [0, 0, -9.81]
    return light.run(HINGE_NODES, HINGE_ELEMENTS, nprops, [HINGE_LEAF, HINGE_BODY], opt)


def pivot_stiffness() -> float:
    """``2 EI/L``: each leaf, its end turned about its middle, is in pure bending."""
    width, thickness = HINGE_LEAF["dim"]
    return 2 * 210e9 * width * thickness**3 / 12 / (0.1 * math.sqrt(2))


# --- the parallel guide -------------------------------------------------------------------
LENGTH, WIDTH, THICKNESS, SPACING = 0.05, 0.02, 0.5e-3, 0.04   #: the leaves [m]
STAGE_MASS = 0.1   #: [kg]
#: leaves along z from the ground (nodes 1, 3) to the stage (2, 4), its middle node 5
GUIDE_NODES = [[0, 0, 0], [0, 0, LENGTH], [SPACING, 0, 0], [SPACING, 0, LENGTH],
               [SPACING / 2, 0, LENGTH]]
GUIDE_ELEMENTS = [[1, 2], [3, 4], [2, 5], [5, 4]]
STAGE = 5


def leaf(thickness: float = THICKNESS, **more) -> dict:
    """The leaves' property set: steel, ``WIDTH`` x ``thickness``, 4 beams, flexible."""
    return {"elems": [1, 2], "emod": STEEL_E, "smod": STEEL_G, "dens": STEEL_RHO,
            "cshape": "rect", "dim": [WIDTH, thickness], "orien": [0, 1, 0], "nbeams": 4,
            "flex": ALL, **more}


def guide_transfer() -> light.LightResult:
    """The guide with a stage mass, the transfer function from a force along the stroke
    to the stage's motion, 1 % modal damping."""
    nprops = {1: {"fix": True}, 3: {"fix": True},
              STAGE: {"mass": STAGE_MASS, "transfer_in": ["force_x"],
                      "transfer_out": ["displ_x"]}}
    return light.run(GUIDE_NODES, GUIDE_ELEMENTS, nprops, [leaf()],
                     {"transfer": [True, 0.01], "silent": True})


def static_gain(space) -> float:
    """``G(0) = D - C A^-1 B`` of a single-input single-output state-space model."""
    return float((space.D - space.C @ np.linalg.solve(space.A, space.B))[0, 0])


def guide_stiffness() -> float:
    """``24 EI/L^3 / (1 + Phi)``, ``Phi = 12 EI/(k G A L^2)`` (Cowper's ``k``)."""
    nu = STEEL_E / (2 * STEEL_G) - 1
    inertia, area = WIDTH * THICKNESS**3 / 12, WIDTH * THICKNESS
    kga = 10 * (1 + nu) / (12 + 11 * nu) * STEEL_G * area
    return 24 * STEEL_E * inertia / LENGTH**3 / (1 + 12 * STEEL_E * inertia / (kga * LENGTH**2))


def rayleigh_frequency(stiffness: float) -> float:
    """The first frequency [Hz] by Rayleigh with the guided leaves' static shape: the
    stage and ``13/35`` of each leaf's mass."""
    leaf_mass = STEEL_RHO * WIDTH * THICKNESS * LENGTH
    return math.sqrt(stiffness / (STAGE_MASS + 2 * 13 / 35 * leaf_mass)) / (2 * math.pi)


# --- the wire flexure ---------------------------------------------------------------------
WIRE, WIRE_LENGTH, SQUARE = 1e-3, 0.05, 0.04   #: wire diameter, length, corner spacing [m]


def wire_buckling() -> light.LightResult:
    """Four wires at the corners of a square under a rigid stage (a cross of rigid
    elements to its middle, node 9), 1 N pressing down in 2 load steps."""
    corners = [(0, 0), (SQUARE, 0), (SQUARE, SQUARE), (0, SQUARE)]
    nodes = [[x, y, 0] for x, y in corners] + [[x, y, WIRE_LENGTH] for x, y in corners] + \
        [[SQUARE / 2, SQUARE / 2, WIRE_LENGTH]]
    elements = [[k + 1, k + 5] for k in range(4)] + [[9, k + 5] for k in range(4)]
    wires = {"elems": [1, 2, 3, 4], "emod": STEEL_E, "smod": STEEL_G, "dens": STEEL_RHO,
             "cshape": "circ", "dim": [WIRE], "nbeams": 4, "flex": ALL}
    nprops: dict = {k + 1: {"fix": True} for k in range(4)}
    nprops[9] = {"force": [0, 0, -1.0]}
    return light.run(nodes, elements, nprops, [wires],
                     {"calcbuck": True, "loadsteps": 2, "silent": True})


def wire_critical_load() -> float:
    """``4 P / (1 + P/(k G A))``, ``P = pi^2 EI/L^2``: four wires clamped at both ends
    swaying together (the stage does not turn)."""
    nu = STEEL_E / (2 * STEEL_G) - 1
    inertia, area = math.pi * WIRE**4 / 64, math.pi * WIRE**2 / 4
    euler = math.pi**2 * STEEL_E * inertia / WIRE_LENGTH**2
    kga = 6 * (1 + nu) / (7 + 6 * nu) * STEEL_G * area
    return 4 * euler / (1 + euler / kga)


# --- the study ----------------------------------------------------------------------------
STUDY_STEPS = 4   #: load steps of each case's stroke


def guide_case(stroke: float, thickness: float):
    """One case of :func:`guide_study`: the guide's model and its run settings, the stage
    driven ``stroke`` [m] along x in ``STUDY_STEPS`` steps, leaves ``thickness`` [m]."""
    built = light.build(GUIDE_NODES, GUIDE_ELEMENTS,
                        {1: {"fix": True}, 3: {"fix": True}, STAGE: {"displ_x": stroke}},
                        [leaf(thickness)], {"silent": True})
    return built.model, fm.RunSettings(input_increment=built.input_increment,
                                       load_steps=STUDY_STEPS)


def support_stiffness(statics) -> float:
    """The stage's stiffness along the leaves at the last step, the drive held [N/m]."""
    return 1 / fm.node_compliance(statics.linearization(), 3 * STAGE - 2, 3 * STAGE - 1)[2, 2]


def peak_stress(statics) -> float:
    """The largest von Mises stress over the steps [Pa]."""
    return float(np.max(fm.stress_history(statics).maximum))


def guide_study(strokes, thicknesses, client=None, progress: bool | None = None):
    """Support stiffness and peak stress of the guide for every stroke [m] and leaf
    thickness [m], on a local Dask cluster (``client="serial"``: in this process).
    Returns a pandas DataFrame: ``stroke``, ``thickness``, ``support_stiffness`` [N/m],
    ``peak_stress`` [Pa] and the status of each case."""
    return fm.sweep(guide_case, {"stroke": list(strokes), "thickness": list(thicknesses)},
                    "static", {"support_stiffness": support_stiffness,
                               "peak_stress": peak_stress}, client=client, progress=progress)


def plot_study(data, filename=None, window: bool = False):
    """Support stiffness and peak stress against the stroke, a curve per thickness; saved
    to ``filename`` when given, in a window (a pyplot figure) with ``window``."""
    from flexmbd import plot

    stiffness, stress = {}, {}
    for thickness in sorted(set(data["thickness"])):
        rows = data[data["thickness"] == thickness].sort_values("stroke")
        label = f"t = {thickness * 1e3:g} mm"
        stiffness[label] = rows["support_stiffness"].to_numpy() / 1e6
        stress[label] = rows["peak_stress"].to_numpy() / 1e6
        strokes = rows["stroke"].to_numpy() * 1e3
    return plot.plot_panels(strokes, [stiffness, stress], xlabel="stroke [mm]",
                            ylabels=["support stiffness [N/um]", "peak stress [MPa]"],
                            title="parallel guide: support stiffness and stress",
                            filename=filename, window=window)


# --- checks -------------------------------------------------------------------------------
def checks(hinge_unloaded, guide, wires) -> list[Check]:
    stiffness = 1 / static_gain(guide.statespace)
    return [
        Check("cross hinge: pivot stiffness 1/C_66 [N m/rad] = 2 EI/L",
              1 / hinge_unloaded.node[3].CMglob[5, 5, 0], pivot_stiffness(), rtol=1e-9),
        Check("guide: static gain = compliance C_xx [m/N]", static_gain(guide.statespace),
              guide.node[STAGE].CMglob[0, 0, 0], rtol=1e-9),
        Check("guide: stiffness [N/m] ~ 24 EI/L^3 / (1 + Phi)", stiffness, guide_stiffness(),
              rtol=2e-4),
        Check("guide: first frequency [Hz] ~ Rayleigh", float(guide.freq[0, 0]),
              rayleigh_frequency(stiffness), rtol=1e-4),
        Check("wires: buckling load [N] ~ 4 pi^2 EI/L^2 with shear", float(wires.buck[0, -1]),
              wire_critical_load(), rtol=1e-3),
    ]


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    add_output_options(parser)
    args = parse(parser, argv)
    hinge = cross_hinge()
    print("cross hinge (SPACAR Light's example, with warping and gravity, 10 load steps):")
    print(f"  over-constraints released: {len(hinge.releases)}")
    print(f"  node 3 at the last step [m]: {np.array2string(hinge.node[3].p[:, -1])}")
    print(f"  lowest frequencies at steps 1 and 10 [Hz]: {hinge.freq[:3, 0].round(3)}, "
          f"{hinge.freq[:3, -1].round(3)}")
    print(f"  largest stress [MPa]: {hinge.stressmax.max() / 1e6:.2f}")
    guide, wires = guide_transfer(), wire_buckling()
    print(f"parallel guide: stiffness {1 / static_gain(guide.statespace):.4f} N/m, first "
          f"frequency {guide.freq[0, 0]:.4f} Hz")
    print(f"wire flexure: buckling load factors {wires.buck[:3, -1].round(3)} (of 1 N)")
    ok = print_checks("\nchecks:", checks(cross_hinge(loaded=False), guide, wires))

    def draw(filename, window):
        from flexmbd import plot

        curves = {f"f{k + 1}": hinge.freq[k] for k in range(3)}
        plot.plot_panels(hinge.load, [curves, {"largest": hinge.stressmax / 1e6}],
                         xlabel="load factor", ylabels=["frequency [Hz]", "stress [MPa]"],
                         title="cross hinge over its load steps", filename=filename,
                         window=window)

    finish_outputs(args, hinge.statics, draw, movie_title="cross hinge: load steps")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
