"""EXERCISES 3: dynamics of the rigid slider-crank (mass matrices, torque, reactions, PD control).

The slider-crank of EXERCISES 2 with the parameters of EXERCISES 4: crank
``l1 = 0.15 m`` (massless), rod ``l2 = 0.30 m`` with mass ``m2 = 0.06676 kg``
spread uniformly, slider mass ``m5 = m2/2``; ``--gravity`` adds 9.81 m/s^2
along -y. Nodes: 1 O (fixed), 2 crank angle, 3 A, 4 rod angle, 5 B (y fixed).

Printed and checked, each against an independent route:
* the reduced mass matrix ``Mbar`` with a lumped and with a consistent rod
  mass, over a revolution (equal for a rigid link, THEORY 5);
* the driving torque at constant crank speed (inverse dynamics) against
  Lagrange's equation in closed form, ``tau = J phi'' + J'(phi) phi'^2 / 2 +
  dV/dphi`` with ``J = m2/3 (l1^2 - l1 sin(phi) x_B' + x_B'^2) + m5 x_B'^2``;
* the support reactions against the linear momentum balance of rod and slider;
* a forward simulation with the crank driven by a PD controller tracking a
  reference that speeds up to ``--omega``; the controller torque against the
  inverse dynamics of the realised motion. The plot shows reference and
  realised angle, tracking error and torque, with the torque that exact
  tracking of the reference would need (inverse dynamics).

Run: ``flexmbd example slider-crank-dyn --plot pd.png --movie crank.gif``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    POSITIVE,
    Check,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    format_matrix,
    parse,
    print_checks,
)
from flexmbd.examples.slider_crank_kinematics import closed_form

import flexmbd as fm
from flexmbd import plot

L1, L2 = 0.15, 0.30  #: crank and rod length [m]
M2 = 0.06676  #: rod mass [kg]
M5 = M2 / 2  #: slider mass [kg]
G = 9.81  #: gravitational acceleration [m/s^2]
OMEGA = 150.0  #: crank speed [rad/s]
RAMP = 0.02  #: time constant of the reference's speed-up [s]
BANDWIDTH = 300.0  #: closed-loop natural frequency of the PD controller [rad/s]


def build_model(formulation: str = "consistent", gravity: bool = False,
                driven: bool = True, omega: float = OMEGA) -> fm.Model:
    """The slider-crank; ``driven``: crank angle prescribed ``phi = omega t``, else the
    crank is a dynamic degree of freedom (turned by applied torques)."""
    b = fm.ModelBuilder(f"slider-crank dynamics ({formulation} rod mass)")
    b.add_node(1, 0.0, 0.0).add_node(3, L1, 0.0).add_node(5, L1 + L2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3).add_rigid_beam(2, 3, 4, 5)
    b.fix(1).fix(5, "y")
    if driven:
        b.input_coordinate(2, law=fm.Polynomial(0.0, omega))
    else:
        b.dynamic_coordinate(2)
    b.set_mass(2, M2 / L2, formulation)
    b.add_point_mass(5, M5)
    if gravity:
        b.set_gravity(0.0, -G)
    return b.build()


# --- closed forms -------------------------------------------------------------------------
def generalized_inertia(phi):
    """``J(phi)`` [kg m^2] and ``dJ/dphi`` from the kinetic energy of rod and slider.

    A uniform rod with end velocities ``v_A, v_B`` has ``T = m/6 (v_A^2 + v_A.v_B + v_B^2)``;
    here ``v_A = l1 phi' (-sin, cos)`` and ``v_B = (x_B' phi', 0)``.
    """
    _, dx, ddx = closed_form(phi, L1, L2)["x5.1"]
    s, c = np.sin(phi), np.cos(phi)
    J = M2 / 3 * (L1**2 - L1 * s * dx + dx**2) + M5 * dx**2
    dJ = M2 / 3 * (-L1 * c * dx - L1 * s * ddx + 2 * dx * ddx) + 2 * M5 * dx * ddx
    return J, dJ


def lagrange_torque(phi, omega, alpha, gravity: bool):
    """Driving torque [N m] from Lagrange's equation; the rod's centre is at
    height ``l1 sin(phi) / 2``, so gravity adds ``m2 g l1 cos(phi) / 2``."""
    J, dJ = generalized_inertia(phi)
    return J * alpha + 0.5 * dJ * omega**2 + (M2 * G * L1 * np.cos(phi) / 2 if gravity else 0.0)


def momentum_residual(result: fm.SimulationResult, gravity: bool) -> np.ndarray:
    """``f_support + m g - d(momentum)/dt`` of rod and slider [N], shape ``(nt, 2)``.

    The crank is massless, so the pin force it passes on is the support force at O.
    """
    a_A = np.stack([result["xdd3.1"], result["xdd3.2"]], axis=1)
    a_B = np.stack([result["xdd5.1"], result["xdd5.2"]], axis=1)
    support = np.stack([result["f1.1"], result["f1.2"] + result["f5.2"]], axis=1)
    weight = (M2 + M5) * np.array([0.0, -G if gravity else 0.0])
    return support + weight - (M2 * (a_A + a_B) / 2 + M5 * a_B)


# --- the PD-controlled crank ---------------------------------------------------------------
def reference(omega: float = OMEGA, ramp: float = RAMP) -> fm.Custom:
    """Reference angle speeding up from rest: ``omega (t - ramp (1 - exp(-t/ramp)))``."""
    return fm.Custom(lambda t: omega * (t - ramp * (1 - math.exp(-t / ramp))),
                     lambda t: omega * (1 - math.exp(-t / ramp)),
                     lambda t: omega / ramp * math.exp(-t / ramp))


def pd_gains(bandwidth: float = BANDWIDTH, damping: float = 0.7) -> tuple[float, float]:
    """``Kp`` [N m/rad], ``Kd`` [N m s/rad] for the mean generalized inertia of a turn."""
    J_mean = float(np.mean(generalized_inertia(np.linspace(0, 2 * math.pi, 361))[0]))
    return J_mean * bandwidth**2, 2 * damping * bandwidth * J_mean


def pd_controller(model: fm.Model, law: fm.Custom, gains: tuple[float, float]):
    """Applied loads ``{"x2.1": Kp (phi_ref - phi) + Kd (phi_ref' - phi')}``."""
    kp, kd = gains
    i = model.coordinate_index("x2.1")

    def torque(t, x, xd):
        return {"x2.1": kp * (law.value(t) - x[i]) + kd * (law.rate(t) - xd[i])}
    return torque


def pd_simulation(revolutions: float = 3.0, omega: float = OMEGA, gravity: bool = False,
                  points: int = 600) -> tuple[fm.SimulationResult, np.ndarray, fm.Custom]:
    """Forward simulation of the PD-controlled crank; returns the result, the controller
    torque at the output times [N m] and the reference law."""
    model = build_model(gravity=gravity, driven=False)
    law = reference(omega)
    controller = pd_controller(model, law, pd_gains())
    t_end = RAMP + revolutions * 2 * math.pi / omega
    times = np.linspace(0.0, t_end, points + 1)
    result = fm.simulate(model, times, forces=controller, rtol=1e-9, atol=1e-12,
                         with_reactions=True, on_failure="return")
    torque = np.array([controller(t, x, xd)["x2.1"]
                       for t, x, xd in zip(result.t, result.x, result.xd, strict=True)])
    return result, torque, law


def replay_torque(result: fm.SimulationResult, gravity: bool) -> np.ndarray:
    """Inverse dynamics of the realised crank motion (the same states, crank prescribed)."""
    model = build_model(gravity=gravity, driven=True)
    t, phi, rate, acc = result.t, result["x2.1"], result["xd2.1"], result["xdd2.1"]

    def at(values):
        return lambda time: float(values[int(np.argmin(np.abs(t - time)))])
    replay = fm.inverse_dynamics(model, t, inputs={"x2.1": fm.Custom(at(phi), at(rate),
                                                                     at(acc))})
    return replay["f2.1"]


# --- the checks --------------------------------------------------------------------------
def revolution(omega: float = OMEGA, points: int = 73) -> np.ndarray:
    return np.linspace(0.0, 2 * math.pi / omega, points)


def checks(gravity: bool = False, omega: float = OMEGA) -> list[Check]:
    """Mass matrices, torque, reactions over a revolution at constant speed."""
    times = revolution(omega)
    runs = {f: fm.inverse_dynamics(build_model(f, gravity, omega=omega), times)
            for f in ("lumped", "consistent")}
    mbar = {}
    for f, run in runs.items():
        model = run.model
        mbar[f] = np.array([fm.reduced_mass_matrix(model, x)[0, 0] for x in run.x])
    phi = runs["consistent"]["x2.1"]
    J, _ = generalized_inertia(phi)
    tau_closed = lagrange_torque(phi, omega, 0.0, gravity)
    scale_tau = float(np.max(np.abs(tau_closed)))
    out = [
        Check("max |Mbar lumped - consistent| [kg m^2]",
              float(np.max(np.abs(mbar["lumped"] - mbar["consistent"]))), 0.0,
              rtol=1e-12, scale=float(J.max())),
        Check("max |Mbar - J closed form| [kg m^2]",
              float(np.max(np.abs(mbar["consistent"] - J))), 0.0, rtol=1e-12,
              scale=float(J.max())),
    ]
    for f, run in runs.items():
        out.append(Check(f"max |tau - Lagrange| ({f}) [N m]",
                         float(np.max(np.abs(run["f2.1"] - tau_closed))), 0.0, rtol=1e-9,
                         scale=scale_tau))
        force_scale = float(np.max(np.abs(run["f1.1"])))
        out.append(Check(f"max |momentum balance| ({f}) [N]",
                         float(np.max(np.abs(momentum_residual(run, gravity)))), 0.0,
                         rtol=1e-9, scale=force_scale))
    out.append(Check("mean torque over a turn [N m] (no net work)",
                     float(np.mean(runs["consistent"]["f2.1"][:-1])), 0.0, rtol=1e-9,
                     scale=scale_tau))
    return out


def print_mass_matrices(phi: float = math.radians(60.0)) -> None:
    """Rod element mass matrices and ``Mbar`` at crank angle ``phi``, lumped and consistent."""
    for f in ("lumped", "consistent"):
        model = build_model(f)
        x = fm.solve_position(model, np.array([phi]))
        rod = model.elements[2]
        M = fm.mass_matrix(model, x)[np.ix_(rod.coordinates, rod.coordinates)]
        names = [model.coordinate_labels[i] for i in rod.coordinates]
        print(f"\nrod mass matrix, {f} (coordinates of element 2):\n"
              + format_matrix(M, names, names))
        print(f"Mbar ({f}) at phi = {math.degrees(phi):.0f} deg: "
              f"{fm.reduced_mass_matrix(model, x)[0, 0]:.12g} kg m^2")


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--gravity", action="store_true", help="gravity 9.81 m/s^2 along -y")
    parser.add_argument("--omega", type=POSITIVE, default=OMEGA, help="crank speed [rad/s]")
    parser.add_argument("--revolutions", type=POSITIVE, default=3.0,
                        help="turns of the PD-controlled simulation (default 3)")
    parser.add_argument("--points", type=count(2), default=600,
                        help="output times of the simulation")
    add_output_options(parser)
    args = parse(parser, argv)
    print(build_model(gravity=args.gravity, omega=args.omega).summary())
    print_mass_matrices()
    ok = print_checks(f"\nconstant crank speed {args.omega:g} rad/s over a revolution:",
                      checks(args.gravity, args.omega))

    result, torque, law = pd_simulation(args.revolutions, args.omega, args.gravity,
                                        args.points)
    kp, kd = pd_gains()
    print(f"\nPD-controlled crank (gains Kp = {kp:.4g} N m/rad, Kd = {kd:.4g} N m s/rad): "
          f"{result.message}")
    if len(result.t) < 2:
        return 1
    phi_ref = np.array([law.value(t) for t in result.t])
    error = phi_ref - result["x2.1"]
    ideal = fm.inverse_dynamics(build_model(gravity=args.gravity), result.t,
                                inputs={"x2.1": law})["f2.1"]
    print(f"tracking error: max {np.max(np.abs(error)):.3g} rad; PD torque {torque.min():.4g} .. "
          f"{torque.max():.4g} N m; exact tracking needs {ideal.min():.4g} .. "
          f"{ideal.max():.4g} N m")
    replay = replay_torque(result, args.gravity)
    ok = print_checks("forward against inverse dynamics:", [
        Check("max |PD torque - inverse dynamics of the motion| [N m]",
              float(np.max(np.abs(torque - replay))), 0.0, rtol=1e-6,
              scale=float(np.max(np.abs(torque))))]) and ok

    def draw(filename, window):
        plot.plot_panels(result.t, [
            {"reference": phi_ref, "realised": result["x2.1"]},
            {"phi_ref - phi": error},
            {"PD torque": torque, "exact tracking (inverse dynamics)": ideal},
        ], xlabel="t [s]", ylabels=["crank angle [rad]", "tracking error [rad]",
                                    "torque [N m]"],
            title="slider-crank with a PD-controlled crank", filename=filename, window=window)

    finish_outputs(args, result, draw, movie_title="PD-controlled slider-crank")
    return 0 if ok and result.success else 1


if __name__ == "__main__":
    sys.exit(main())
