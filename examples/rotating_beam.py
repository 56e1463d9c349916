"""A rotating flexible beam: in-plane and out-of-plane bending respond differently to
the rotation; Campbell diagram and a spin-up under gravity.

A uniform cantilever (``L = 1 m``, ``EI = 100 N m^2`` about both axes, ``rho A = 1
kg/m``, elongation and torsion rigid) of ``--nbeams`` spatial beams (with SPACAR's
bending-linked terms, through which the centrifugal tension stiffens the bending) is
clamped to a hub that a spatial hinge turns about Z. Its bending in the plane of
rotation (XY, lead-lag) and out of it (XZ, flapping) have the same frequency at rest;
rotating at ``Omega`` both stiffen by the centrifugal tension, but the in-plane one is
softened again by the centrifugal field itself, exactly by ``Omega^2``.

Computed, each against a value this example computes on its own or a published one:

* at rest, the first frequency ``1.87510^2 sqrt(EI/(rho A L^4))`` = 35.1602 rad/s
  (within the discretization error, ``2e-2/n^4`` for ``n`` beams);
* rotating, ``omega_out^2 - omega_in^2 = Omega^2`` at every speed (the in-plane equation
  is the out-of-plane one less ``rho A Omega^2`` times the deflection);
* the Southwell coefficient ``(omega_out^2 - omega_0^2)/Omega^2`` of slow rotation,
  1.1933 for the first flapping mode of a uniform cantilever on the axis (Wright, Smith,
  Thresher and Wang 1982);
* a spin-up under gravity (``-Z``) from the static sag: at rest the tip sags by
  ``rho A g L^4/(8 EI)`` (to the large-deflection correction, 1e-4), and while the hub
  accelerates at ``alpha = 20 rad/s^2`` to 60 rad/s the beam lags in the plane of
  rotation and its sag shrinks as the rotation stiffens it.

Nodes: the beam's 1, 3, ..., ``2n+1`` (tip), rotations 2, 4, ...; the ground's rotation
99. Elements: beams 1..n, the hub's hinge 100.

Run: ``flexmbd example rotating-beam --plot campbell.png --movie spinup.gif``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    FINITE,
    Check,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    parse,
    print_checks,
)

import flexmbd as fm
from flexmbd import plot

LENGTH, EI, RHO_A = 1.0, 100.0, 1.0  #: [m], [N m^2], [kg/m]
GRAVITY = 9.81  #: [m/s^2], along -Z in the spin-up
NBEAMS = 8
HUB, GROUND = 100, 99  #: the hub's hinge and the ground's rotational node
SOUTHWELL = 1.1933  #: the published Southwell coefficient of the first flapping mode
SPEEDS = np.linspace(0.0, 60.0, 13)  #: speeds of the Campbell diagram [rad/s]
ACCELERATION = 20.0  #: the hub's angular acceleration in the spin-up [rad/s^2]
SPINUP = 3.0  #: the spin-up's duration [s]


def tip(nbeams: int) -> int:
    return 2 * nbeams + 1


def build_model(nbeams: int = NBEAMS, speed: float = 0.0, acceleration: float = 0.0,
                gravity: bool = False) -> fm.Model:
    """The beam on its hub turning at ``speed + acceleration t`` [rad/s]."""
    b = fm.ModelBuilder(f"rotating beam, {nbeams} beams")
    for k in range(nbeams + 1):
        b.add_node(2 * k + 1, LENGTH * k / nbeams, 0.0, 0.0)
    b.add_spatial_hinge(HUB, GROUND, 2)
    for k in range(nbeams):
        b.add_spatial_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4,
                           orientation=(0, 1, 0))
        b.set_mass(k + 1, RHO_A)
        b.set_stiffness(k + 1, bending_y=EI, bending_z=EI)
        b.dynamic_deformation(k + 1, 3, 4, 5, 6)
    b.fix(1).fix(GROUND)
    b.input_deformation(HUB, 1, law=fm.Polynomial(0.0, speed, acceleration))
    if gravity:
        b.set_gravity(0.0, 0.0, -GRAVITY)
    return b.build()


def frequency_at_rest() -> float:
    """The continuous cantilever's first frequency [rad/s]."""
    return 1.87510407**2 * math.sqrt(EI / (RHO_A * LENGTH**4))


def frequencies(nbeams: int, speed: float) -> tuple[float, float]:
    """The first in-plane and out-of-plane frequencies [rad/s] at steady ``speed``: the
    modes of the state turning at ``speed``, told apart by where their tips move."""
    model = build_model(nbeams, speed)
    qd = np.zeros(model.n_dof)
    qd[model.q_labels.index(f"e{HUB}.1")] = speed
    modes = fm.vibration_modes(fm.linearize(model, model.x0, qd=qd), 4)
    y, z = (model.coordinate_index(f"x{tip(nbeams)}.{k}") for k in (2, 3))
    omega = 2 * np.pi * modes.frequencies
    in_plane = [w for w, m in zip(omega, modes.motion.T, strict=True) if abs(m[y]) > abs(m[z])]
    out_of_plane = [w for w, m in zip(omega, modes.motion.T, strict=True)
                    if abs(m[z]) > abs(m[y])]
    return min(in_plane), min(out_of_plane)


def campbell(nbeams: int, speeds=SPEEDS) -> np.ndarray:
    """``(len(speeds), 2)``: in-plane and out-of-plane first frequencies [rad/s]."""
    return np.array([frequencies(nbeams, speed) for speed in speeds])


def spin_up(nbeams: int, points: int) -> tuple[fm.StaticResult, fm.SimulationResult]:
    """The static sag under gravity, then the hub accelerating from rest from it."""
    model = build_model(nbeams, acceleration=ACCELERATION, gravity=True)
    sag = fm.static_equilibrium(model)
    dynamic = [label for label, given in zip(model.q_labels, model.q_is_input, strict=True)
               if not given]
    initial = {label: (float(sag[label][0]), 0.0) for label in dynamic}
    run = fm.simulate(model, np.linspace(0.0, SPINUP, points), initial=initial,
                      method="GeneralizedAlpha", step=SPINUP / 600, on_failure="return")
    return sag, run


def checks(nbeams: int, table: np.ndarray, sag: fm.StaticResult,
           run: fm.SimulationResult) -> list[Check]:
    """The beam against the closed forms and the published coefficient (docstring)."""
    slow = 0.5
    _, out_of_plane = frequencies(nbeams, slow)
    southwell = (out_of_plane**2 - table[0, 1] ** 2) / slow**2
    difference = table[:, 1] ** 2 - table[:, 0] ** 2 - SPEEDS**2
    z = f"x{tip(nbeams)}.3"
    discretization = 2e-2 / nbeams**4  # the Hermite beams' error goes as n^-4
    return [
        Check("first frequency at rest [rad/s]", table[0, 0], frequency_at_rest(),
              rtol=discretization),
        Check("out-of-plane^2 - in-plane^2 - Omega^2, largest [rad^2/s^2]",
              float(np.max(np.abs(difference))), 0.0, rtol=1e-9,
              scale=float(table[-1, 1] ** 2)),
        Check("Southwell coefficient of slow rotation", southwell, SOUTHWELL,
              rtol=1e-4 + 5 * discretization),  # the published value has 4 decimals
        Check("static tip sag [m]", float(sag[z][0]),
              -RHO_A * GRAVITY * LENGTH**4 / (8 * EI), rtol=1e-3),
        Check("sag at the end of the spin-up below the start", float(
            abs(run[z][-1]) < abs(run[z][0])), 1.0),
    ]


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--nbeams", type=count(1), default=NBEAMS,
                        help=f"beams along the cantilever (default {NBEAMS})")
    parser.add_argument("--points", type=count(2), default=121,
                        help="output times of the spin-up")
    parser.add_argument("--exaggeration", type=FINITE, default=1.0,
                        help="deflection factor of the movie")
    add_output_options(parser, table=True)
    args = parse(parser, argv)
    table = campbell(args.nbeams)
    print(f"{'Omega [rad/s]':>14} {'in-plane':>10} {'out-of-plane':>13}  first frequencies "
          f"[rad/s]")
    for speed, (w_in, w_out) in zip(SPEEDS, table, strict=True):
        print(f"{speed:>14.3g} {w_in:>10.6f} {w_out:>13.6f}")
    sag, run = spin_up(args.nbeams, args.points)
    print(f"spin-up: {run.message}")
    y, z = (f"x{tip(args.nbeams)}.{k}" for k in (2, 3))
    angle = run[f"e{HUB}.1"]
    lag = -(run[y] * np.cos(angle) - run[f"x{tip(args.nbeams)}.1"] * np.sin(angle))
    print(f"tip sag {run[z][0]:.5f} m at rest, {run[z][-1]:.5f} m at {angle[-1]:.3g} rad and "
          f"{ACCELERATION * SPINUP:.3g} rad/s; in-plane lag up to {np.max(lag):.5f} m")
    if args.out:
        run.save(args.out)
        print(f"{len(run.t)} rows written to {args.out}")
    ok = print_checks("\nchecks:", checks(args.nbeams, table, sag, run)) and run.success

    def draw(filename, window):
        plot.plot_curves(SPEEDS, {"in-plane": table[:, 0], "out-of-plane": table[:, 1],
                                  "speed": SPEEDS},
                         xlabel="Omega [rad/s]", ylabel="first frequency [rad/s]",
                         title="rotating beam: Campbell diagram", filename=filename,
                         window=window)

    finish_outputs(args, run, draw, movie_title="rotating beam: spin-up under gravity",
                   exaggeration=args.exaggeration)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
