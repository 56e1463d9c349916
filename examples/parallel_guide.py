"""A flexure: parallel leaf-spring guide; stiffness, frequencies, buckling load, Bode plot.

Two steel leaf springs (length ``L = 50 mm``, thickness 0.5 mm, width 20 mm,
``E = 210 GPa``, ``rho = 7850 kg/m^3``), clamped at the base ``W = 40 mm`` apart,
carry a rigid stage of 0.2 kg at their tops; a payload of 50 N presses down on
the stage. Each leaf is ``--nbeams`` second-order beams (PLBEAM2: the arc length
of the bending enters the elongation, so axial load changes the bending stiffness
as it should), all deformations flexible. The loop of leaves and stage has three
deformations more than coordinates: the top beam of the right leaf is released
(RLSE), its stiffness kept.

Computed, each against a solution this example computes on its own from the
continuous beam equations (leaves inextensible; their finite axial stiffness lets
the stage tilt, a relative effect of about ``(thickness/W)^2 = 1.6e-4``):

* the lateral stiffness of the stage under the payload, ``2 EI k^3 / (2 tan(kL/2) -
  kL)`` with ``k^2 = P / (2 EI)`` (``24 EI/L^3`` without payload);
* the first sway frequency, from the characteristic equation of two leaves of
  distributed mass, compressed, carrying the stage;
* the buckling load, ``2 pi^2 EI / L^2`` (each leaf clamped-guided);
* the parasitic drop of the stage in a lateral stroke (load steps, large
  deflection), ``1/2 int w'^2`` of the compressed clamped-guided leaf;
* a Bode plot of the stage's lateral compliance with 1 % modal damping, from the
  state space reduced to three modes and drawn by ``scipy.signal.bode``.

The same model as a SPACAR input file: ``parallel_guide.dat`` next to this
example, for ``flexmbd static | modes | buckling | statespace``.

Nodes: left leaf 1, 3, ..., top ``2n+1`` (angles 2, 4, ...), right leaf 101, 103,
..., top ``101+2n`` (angles 102, ...); the stage angle ``2n+2`` is both tops'.
Elements: left leaf beams 1..n, right leaf 101..100+n, stage 200 (rigid beam).
(From 49 beams per leaf on, the right leaf's numbers start at the next hundred.)

Run: ``flexmbd example parallel-guide --plot stroke.png --bode bode.png``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    Check,
    add_file_option,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    parse,
    print_checks,
)
from scipy import integrate, optimize

import flexmbd as fm
from flexmbd import plot

LENGTH = 0.05  #: leaf length L [m]
SPACING = 0.04  #: distance W between the leaves [m]
THICKNESS = 0.5e-3  #: leaf thickness [m]
WIDTH = 0.02  #: leaf width [m]
YOUNG = 210e9  #: Young's modulus [Pa]
DENSITY = 7850.0  #: [kg/m^3]
EI = YOUNG * WIDTH * THICKNESS**3 / 12  #: bending stiffness of a leaf [N m^2]
EA = YOUNG * WIDTH * THICKNESS  #: axial stiffness of a leaf [N]
RHO_A = DENSITY * WIDTH * THICKNESS  #: mass per length of a leaf [kg/m]
STAGE_MASS = 0.2  #: [kg], half on each leaf top
PAYLOAD = 50.0  #: downward load on the stage [N], half on each leaf top
STROKE_LOAD = 20.0  #: lateral load at the end of the stroke [N] (DELXF)
STROKE_STEPS = 10  #: load steps of the stroke (ITERSTEP)
NBEAMS = 8  #: beams per leaf
DAMPING_RATIO = 0.01  #: modal damping of the Bode plot
BODE_MODES = 3  #: modes kept in the reduced state space


def right_offset(nbeams: int) -> int:
    """What the right leaf adds to the left leaf's node and element numbers: 100, or the
    next multiple of 100 that keeps them apart; the stage is element ``2 offset``."""
    return 100 * math.ceil((2 * nbeams + 3) / 100)


def top_nodes(nbeams: int) -> tuple[int, int, int]:
    """The left and right leaf tops and the stage's angle node."""
    return 2 * nbeams + 1, right_offset(nbeams) + 1 + 2 * nbeams, 2 * nbeams + 2


def build_model(nbeams: int = NBEAMS) -> fm.Model:
    """The guide with ``nbeams`` second-order beams per leaf, payload applied (XF)."""
    if nbeams < 1:
        raise fm.ModelError(f"nbeams must be at least 1, got {nbeams}")
    left_top, right_top, stage_angle = top_nodes(nbeams)
    b = fm.ModelBuilder(f"parallel leaf-spring guide, {nbeams} beams per leaf")
    for offset, x in ((0, 0.0), (right_offset(nbeams), SPACING)):
        positions = [offset + 1 + 2 * k for k in range(nbeams + 1)]
        angles = [offset + 2 + 2 * k for k in range(nbeams)] + [stage_angle]
        for k, node in enumerate(positions):
            b.add_node(node, x, LENGTH * k / nbeams)
        for k in range(nbeams):
            element = offset + k + 1
            b.add_beam(element, positions[k], angles[k], positions[k + 1], angles[k + 1],
                       second_order=True)
            b.set_mass(element, RHO_A).set_stiffness(element, axial=EA, bending=EI)
            if offset and k == nbeams - 1:  # the loop's three surplus deformations
                b.release(element, 1, 2, 3)
            else:
                b.dynamic_deformation(element, 1, 2, 3)
        b.fix(positions[0]).fix(angles[0])
        b.add_point_mass(positions[-1], STAGE_MASS / 2)
        b.add_force(positions[-1], 0.0, -PAYLOAD / 2)
    b.add_rigid_beam(2 * right_offset(nbeams), left_top, stage_angle, right_top)
    return b.build()


# --- the continuous leaves: closed forms and characteristic equations -------------------

def guided_stiffness(compression: float) -> float:
    """Lateral stiffness [N/m] of one clamped-guided leaf under axial ``compression`` [N]."""
    if compression == 0.0:
        return 12 * EI / LENGTH**3
    kl = math.sqrt(compression / EI) * LENGTH
    return EI * (kl / LENGTH) ** 3 / (2 * math.tan(kl / 2) - kl)


def sway_frequency(compression: float) -> float:
    """First sway frequency [Hz] of the guide: two compressed leaves of mass ``RHO_A`` per
    length, clamped at the base and guided by the stage (half its mass on each).

    A leaf moves as ``w = c1 (cosh ax - cos bx) + c2 (sinh ax - (a/b) sin bx)`` with
    ``EI s^4 + P s^2 - rho A omega^2 = 0`` (``s = a, i b``); the top has ``w' = 0`` and
    ``EI w''' = -(m/2) omega^2 w``: the frequency makes that 2 x 2 system singular.
    """
    def determinant(omega: float) -> float:
        root = math.sqrt(compression**2 + 4 * EI * RHO_A * omega**2)
        a = math.sqrt((root - compression) / (2 * EI))
        b = math.sqrt((root + compression) / (2 * EI))
        ch, sh = math.cosh(a * LENGTH), math.sinh(a * LENGTH)
        c, s = math.cos(b * LENGTH), math.sin(b * LENGTH)
        slope = (a * sh + b * s, a * ch - a * c)
        shear = (EI * (a**3 * sh - b**3 * s) + STAGE_MASS / 2 * omega**2 * (ch - c),
                 EI * (a**3 * ch + a * b**2 * c) + STAGE_MASS / 2 * omega**2 * (sh - a / b * s))
        return slope[0] * shear[1] - slope[1] * shear[0]

    # bracket the lowest root from below the massless-leaf estimate
    estimate = math.sqrt(2 * guided_stiffness(compression) / STAGE_MASS)
    grid = np.linspace(0.05 * estimate, 2.0 * estimate, 400)
    signs = np.sign([determinant(w) for w in grid])
    first = int(np.flatnonzero(signs[:-1] != signs[1:])[0])
    return optimize.brentq(determinant, grid[first], grid[first + 1], xtol=1e-13) / (2 * math.pi)


def buckling_load() -> float:
    """Payload [N] at which the guide sways out: ``2 pi^2 EI / L^2``."""
    return 2 * math.pi**2 * EI / LENGTH**2


def parasitic_drop(compression: float, stroke: float) -> float:
    """Second-order drop [m] of a clamped-guided leaf's top moved ``stroke`` [m] sideways:
    ``1/2 int w'^2 dx`` of the compressed leaf's deflection ``w = c1 + c2 x + c3 cos kx +
    c4 sin kx`` (``3/5 stroke^2 / L`` without compression)."""
    k = math.sqrt(compression / EI)
    kl = k * LENGTH
    conditions = np.array([[1.0, 0.0, 1.0, 0.0],            # w(0) = 0
                           [0.0, 1.0, 0.0, k],              # w'(0) = 0
                           [0.0, 1.0, -k * math.sin(kl), k * math.cos(kl)],    # w'(L) = 0
                           [1.0, LENGTH, math.cos(kl), math.sin(kl)]])         # w(L) = stroke
    c = np.linalg.solve(conditions, [0.0, 0.0, 0.0, stroke])

    def slope_squared(x: float) -> float:
        return (c[1] - c[2] * k * math.sin(k * x) + c[3] * k * math.cos(k * x)) ** 2

    return 0.5 * integrate.quad(slope_squared, 0.0, LENGTH, epsabs=0.0, epsrel=1e-12)[0]


# --- the analyses ------------------------------------------------------------------------

def stroke(model: fm.Model, steps: int = STROKE_STEPS) -> fm.StaticResult:
    """Static load steps from the payload alone to ``STROKE_LOAD`` on the left top (DELXF)."""
    left_top = top_nodes(nbeams_of(model))[0]
    return fm.static_equilibrium(model, load_increment={f"x{left_top}.1": STROKE_LOAD},
                                 steps=steps)


def nbeams_of(model: fm.Model) -> int:
    """Beams per leaf."""
    return sum(e.type is fm.SecondOrderBeam for e in model.elements.values()) // 2


def stage_motion(statics) -> tuple[np.ndarray, np.ndarray]:
    """Lateral stroke and drop [m] of the stage per load step, from the payload's row 0;
    the drop is the mean of both tops (a tilt cancels)."""
    left_top, right_top, _ = top_nodes(nbeams_of(statics.model))
    lateral = statics[f"x{left_top}.1"] - statics[f"x{left_top}.1"][0]
    height = 0.5 * (statics[f"x{left_top}.2"] + statics[f"x{right_top}.2"])
    return lateral, height[0] - height


def reduced_bode(lin, omega: np.ndarray):
    """Magnitude [dB] and phase [deg] of the stage's lateral compliance at ``omega``
    [rad/s], from the state space with modal damping reduced to ``BODE_MODES`` modes."""
    from scipy import signal

    lateral = f"x{top_nodes(nbeams_of(lin.model))[0]}.1"
    system = fm.state_space(lin, [lateral], [lateral], damping_ratio=DAMPING_RATIO)
    _, magnitude, phase = signal.bode(system.truncated(BODE_MODES).to_scipy(), omega)
    return magnitude, phase


def analyse(model: fm.Model) -> dict:
    """Stroke, stiffness, frequencies, buckling and Bode data of the guide."""
    statics = stroke(model)
    if not statics.success:
        raise fm.ConvergenceError(statics.message)
    lin = statics.linearization(0)  # the payload alone
    lateral = f"x{top_nodes(nbeams_of(model))[0]}.1"
    modes = fm.vibration_modes(lin, 4)
    omega = 2 * np.pi * np.geomspace(1.0, 3000.0, 800)
    magnitude, phase = reduced_bode(lin, omega)
    return {"statics": statics, "stiffness": 1.0 / fm.compliance(lin, [lateral])[0, 0],
            "modes": modes, "buckling": fm.buckling(lin, 1), "omega": omega,
            "magnitude": magnitude, "phase": phase}


def checks(found: dict) -> list[Check]:
    """The guide against the continuous leaves (module docstring); tolerances 1e-3:
    the stage's tilt (1.6e-4) and the discretisation (below 1e-4 at 8 beams per leaf)."""
    per_leaf = PAYLOAD / 2
    lateral, drop = stage_motion(found["statics"])
    return [
        Check("lateral stiffness [N/m]", found["stiffness"], 2 * guided_stiffness(per_leaf),
              rtol=1e-3),
        Check("first frequency [Hz]", found["modes"].frequencies[0], sway_frequency(per_leaf),
              rtol=1e-3),
        Check("buckling payload [N]", found["buckling"].factors[0] * PAYLOAD, buckling_load(),
              rtol=1e-3),
        Check(f"drop at stroke {lateral[1] * 1e3:.3f} mm [um]", drop[1] * 1e6,
              parasitic_drop(per_leaf, lateral[1]) * 1e6, rtol=1e-3),
    ]


def describe(found: dict) -> None:
    """Print the stroke table and the frequencies."""
    lateral, drop = stage_motion(found["statics"])
    per_leaf = PAYLOAD / 2
    print("stroke (load steps to a lateral load of "
          f"{STROKE_LOAD:g} N; second order: 1/2 int w'^2 of the compressed leaf):")
    print(f"  {'load [N]':>9} {'stroke [mm]':>12} {'drop [um]':>10} {'second order':>13}")
    for load, u, v in zip(found["statics"]["load"], lateral, drop, strict=True):
        print(f"  {load * STROKE_LOAD:>9.3g} {u * 1e3:>12.5f} {v * 1e6:>10.5f} "
              f"{parasitic_drop(per_leaf, u) * 1e6:>13.5f}")
    frequencies = ", ".join(f"{f:.5g}" for f in found["modes"].frequencies)
    print(f"first frequencies [Hz]: {frequencies} (sway, leaves in anti-phase, second sway, "
          "...)")
    print(f"without payload: stiffness {2 * guided_stiffness(0.0):.6g} N/m, first frequency "
          f"{sway_frequency(0.0):.5g} Hz")


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--nbeams", type=count(1), default=NBEAMS,
                        help=f"beams per leaf (default {NBEAMS})")
    add_file_option(parser, "--bode", "plot", "save the Bode plot of the stage's lateral "
                                              "compliance (.png, .pdf, .svg)")
    add_output_options(parser, table=True)
    args = parse(parser, argv)

    model = build_model(args.nbeams)
    print(model.summary())
    found = analyse(model)
    if args.out:
        found["statics"].save(args.out)
        print(f"{len(found['statics'].load)} load steps written to {args.out}")
    describe(found)
    ok = print_checks("\nchecks:", checks(found))
    if args.bode:
        fig = plot.plot_panels(found["omega"] / (2 * np.pi),
                               [{"x/F": found["magnitude"]}, {"x/F": found["phase"]}],
                               xlabel="frequency [Hz]", ylabels=["magnitude [dB m/N]",
                                                                 "phase [deg]"],
                               title=f"{model.name}: stage compliance, {BODE_MODES} modes")
        for ax in fig.axes:
            ax.set_xscale("log")
        plot.save_figure(fig, args.bode)
        print(f"Bode plot saved to {args.bode}")

    def draw(filename, window):
        lateral, drop = stage_motion(found["statics"])
        theory = [parasitic_drop(PAYLOAD / 2, u) for u in lateral]
        plot.plot_curves(lateral * 1e3, {"flexmbd": drop * 1e6, "second order": np.array(theory)
                                         * 1e6}, xlabel="stroke [mm]", ylabel="drop [um]",
                         title=f"{model.name}: parasitic motion", filename=filename,
                         window=window)

    finish_outputs(args, found["statics"], draw, movie_title=f"{model.name}: stroke")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
