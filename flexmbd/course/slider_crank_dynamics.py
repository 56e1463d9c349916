"""Exercise 3, the rigid slider-crank's dynamics: its parts and flexmbd's answers.

The slider-crank of ``flexmbd.examples.slider_crank_dynamics`` (EXERCISES 3): crank
``l1 = 0.15 m`` (massless), rod ``l2 = 0.30 m`` with mass ``m2 = 0.06676 kg`` spread
uniformly, slider mass ``m5 = m2 / 2``, no gravity; ``phi2`` the input.
"""

from __future__ import annotations

import functools

import numpy as np

from ..analysis import dynamics
from ..analysis import kinematics as kin
from ..motion import Polynomial
from .parts import Exercise, Mistake, lettered, without_nodal_masses

DRAWN = np.pi / 3  #: the exercise's configuration, phi2 = 60 degrees
ROD = [3, 4, 5, 6, 7]  #: the rod's coordinates [x3, y3, phi4, x5, y5]


@functools.cache
def model(formulation: str = "consistent", slider: bool = True):
    """The slider-crank with a ``formulation`` rod mass; without the slider's mass if not
    ``slider``."""
    from ..examples import slider_crank_dynamics as example

    built = example.build_model(formulation)
    return built if slider else without_nodal_masses(built)


def configuration(phi2: float) -> np.ndarray:
    """``x`` at crank angle ``phi2`` [rad]."""
    return kin.solve_position(model(), np.array([phi2]))


def rod_mass(x, formulation: str):
    """The rod's mass matrix over its coordinates (the slider's point mass removed)."""
    M = dynamics.mass_matrix(model(formulation, slider=False), np.asarray(x, dtype=float))
    return M[np.ix_(ROD, ROD)]


def reduced_mass(phi2, formulation: str = "consistent", slider: bool = True):
    return dynamics.reduced_mass_matrix(model(formulation, slider), configuration(phi2))


@functools.cache
def inverse(phi2, phi2d, phi2dd):
    """The inverse dynamics at one state: ``(driving, sigma, reactions)``."""
    run = dynamics.inverse_dynamics(model(), [0.0],
                                    inputs={"x2.1": Polynomial(phi2, phi2d, phi2dd)})
    return run.driving[0, 0], run.sigma[0], run.reactions[0, [0, 1, 7]]


def crank_acceleration(phi2, phi2d, tau2, quadratic=True):
    """``phi2dd`` under the torque ``tau2`` [N m]: ``Mbar phi2dd = tau2 - tau(phi2dd = 0)``."""
    still = inverse(phi2, phi2d if quadratic else 0.0, 0.0)[0]
    return (tau2 - still) / reduced_mass(phi2)[0, 0]


def _state(rng, with_torque: bool = False):
    drawn = (DRAWN, 150.0, 1.5 if with_torque else 30.0)
    return [drawn] + [(rng.uniform(-np.pi, np.pi), rng.uniform(-150, 150),
                       rng.uniform(-3, 3) if with_torque else rng.uniform(-500, 500))
                      for _ in range(3)]


def _x(rng):
    return [(configuration(DRAWN),)] + [(configuration(v),) for v in rng.uniform(-3, 3, 2)]


def _phi(rng):
    return [(DRAWN,)] + [(v,) for v in rng.uniform(-np.pi, np.pi, 3)]


_QUADRATIC = ("the torque needs the velocity terms: tau2 = Mbar phi2dd + F_q^T (M F_qq "
              "phi2d^2 + h)")
_SLIDER = "Mbar includes the slider's mass m5 at x5 (F_q^T M F_q over the whole system)"


def _symbolic_mass(lumped: bool):
    def reference():
        import sympy as sp

        from ..analysis import symbolic

        M = symbolic.mass_matrix(model(), lumped=lumped, nodal_masses={5: 0})
        names = [str(s) for s in symbolic.coordinate_symbols(model())]
        return [names], sp.Matrix(M.extract(ROD, ROD))
    return reference


EXERCISE = Exercise(
    3, "slider-crank-dynamics", "Slider-crank dynamics: the rigid mechanism with masses",
    "the slider-crank of EXERCISES 3: l1 = 0.15, l2 = 0.30, rod mass m2 = 0.06676 spread "
    "over it, m5 = m2/2 at the slider", lettered(
        dict(function="rod_mass_lumped", arguments="x",
             returns="M (5, 5) [kg, kg m^2]: lumped rod mass over [x3, y3, phi4, x5, y5]",
             hint="m2/2 at each end and the rotary inertia m2 l2^2/12 - m2 l2^2/4 at phi4",
             answer=lambda x: rod_mass(x, "lumped"), cases=_x,
             symbolic=_symbolic_mass(True),
             mistakes=(Mistake("the lumped rigid beam keeps the rod's rotary inertia at "
                               "phi4: J = m2 l2^2/12 - m2 l2^2/4 = -m2 l2^2/6",
                               lambda x: np.diag([M2 / 2, M2 / 2, 0.0, M2 / 2, M2 / 2])),)),
        dict(function="rod_mass_consistent", arguments="x", returns="M (5, 5): consistent "
                                                                      "rod mass",
             hint="m2/6 [[2I, I], [I, 2I]] over (r_A, r_B), zero on phi4",
             answer=lambda x: rod_mass(x, "consistent"), cases=_x,
             symbolic=_symbolic_mass(False),
             mistakes=(Mistake("consistent mass was asked, you gave the lumped one: "
                               "m2/6 [[2I, I], [I, 2I]] over the rod's end positions",
                               lambda x: rod_mass(x, "lumped")),)),
        dict(function="reduced_mass_lumped", arguments="phi2",
             returns="Mbar (1, 1) [kg m^2] with the lumped rod",
             hint="Mbar = F_q^T M F_q with the lumped rod and the slider",
             answer=lambda phi2: reduced_mass(phi2, "lumped"), cases=_phi, angles=(0,),
             mistakes=(Mistake(_SLIDER, lambda phi2: reduced_mass(phi2, "lumped", False)),)),
        dict(function="reduced_mass_consistent", arguments="phi2",
             returns="Mbar (1, 1) with the consistent rod",
             hint="Mbar = F_q^T M F_q with the consistent rod and the slider",
             answer=reduced_mass, cases=_phi, angles=(0,),
             mistakes=(Mistake(_SLIDER, lambda phi2: reduced_mass(phi2, "consistent",
                                                                  False)),)),
        dict(function="driving_torque", arguments="phi2, phi2d, phi2dd",
             returns="tau2 [N m] (inverse dynamics)",
             hint="tau2 = Mbar phi2dd + F_q^T (M F_qq phi2d^2 + h)",
             answer=lambda *s: inverse(*s)[0], cases=_state, angles=(0,),
             mistakes=(Mistake(_QUADRATIC, lambda p, pd, pdd: inverse(p, 0.0, pdd)[0]),)),
        dict(function="constraint_stresses", arguments="phi2, phi2d, phi2dd",
             returns="sigma(o) (4,) [N, N m]: the rigid deformations' stresses",
             hint="D_c^T sigma = -(M xdd + h) on the dependent rows",
             answer=lambda *s: inverse(*s)[1], cases=_state, angles=(0,)),
        dict(function="reactions", arguments="phi2, phi2d, phi2dd",
             returns="f(o) (3,) [N]: the support reactions at O (x, y) and the slider's y",
             hint="f(o) = D_x^T sigma + M xdd + h on the fixed rows x1, y1, y5",
             answer=lambda *s: inverse(*s)[2], cases=_state, angles=(0,)),
        dict(function="crank_acceleration", arguments="phi2, phi2d, tau2",
             returns="phi2dd [rad/s^2] under the crank torque tau2 (forward dynamics; the "
                     "given PD-controlled simulation integrates it)",
             hint="Mbar phi2dd = tau2 - F_q^T (M F_qq phi2d^2 + h)",
             answer=crank_acceleration, cases=lambda rng: _state(rng, True), angles=(0,),
             mistakes=(Mistake(_QUADRATIC, functools.partial(crank_acceleration,
                                                             quadratic=False)),)),
    ), module="slider_crank_dynamics")

M2 = 0.06676  #: rod mass [kg]
