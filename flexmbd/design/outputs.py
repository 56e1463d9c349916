"""The outputs a design is judged by, each with its value and its exact derivative.

Every output is a function of the converged state ``(x, mu)`` at the last load step and
of the design's data; its total derivative to a parameter follows from the state's
change (:meth:`Design.sensitivities`) and the data's:

* a result column (``x10.3``, ``e4.2``, ``sig4.2``, the reaction ``f1.2``): the
  coordinates' change, the deformations' ``D_x dx + de/dp dp``, the stresses' ``S de +
  dS e`` (or ``dmu``), the reactions' ``d(D_x^T sigma - f)``;
* ``f<k>``, the k-th frequency [Hz]: ``d omega^2 = w^T dA w - omega^2 phi^T dM phi``
  with ``w = (phi, nu)`` the mode on the bordered tangent (``nu`` its constraint
  stresses) and ``dA`` the tangent's change, third derivatives of the deformations
  included; a repeated frequency has no derivative and is refused;
* ``C[node,rot][i,j]``, an entry of :func:`~flexmbd.node_compliance` in the global frame:
  ``dC = dt_i^T W_j + V_i^T dt_j - V_i^T dA W_j`` with ``W = A^-1 t``, ``V = A^-T t``
  (``t`` the unit loads, whose moments turn with the node);
* ``stress_max``, the largest von Mises stress over the beams with a section [Pa]: the
  derivative of the maximising point (where another point lies within
  :data:`COMPETING` of it, the result says so), by central differences of the stress
  evaluation along the exact change of the state and data;
* ``buckling<k>``, the k-th load factor of :func:`~flexmbd.buckling`: its eigenvalue's
  derivative with the elastic and geometric stiffness apart;
* ``stress_ks``, the Kreisselmeier-Steinhauser aggregate (:func:`ks`) of every beam
  end's largest stress, smooth where the maximum is not, likewise.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..analysis.modes import buckling, node_compliance, vibration_modes
from ..analysis.stresses import beam_stresses
from ..errors import ArgumentError
from ..orientation import euler_forces
from .data import STENCIL, rate
from .state import DataChange

__all__ = ["COMPETING", "KS_RHO", "REPEATED", "parse"]

#: frequencies closer than this share are one repeated frequency, which has no derivative
REPEATED = 1e-8
#: a stress point within this share of the largest competes with it (the maximum's
#: derivative then depends on the direction of the change)
COMPETING = 1e-6
#: the Kreisselmeier-Steinhauser parameter of ``stress_ks`` (:func:`ks`), per largest stress
KS_RHO = 50.0

_FREQUENCY = re.compile(r"f(\d+)$")
_BUCKLING = re.compile(r"buckling(\d+)$")
_COMPLIANCE = re.compile(r"C\[\s*(\d+)\s*(?:,\s*(\d+)\s*)?\]\[\s*(\d+)\s*,\s*(\d+)\s*\]$")
_COLUMN = re.compile(r"(x|e|sig|f)(\d+)\.(\d+)$")
NAMES = ("a result column (x10.3, e4.2, sig4.2, the reaction f1.2)", "f<k>", "buckling<k>",
         "C[<node>,<rot>][i,j]", "stress_max", "stress_ks")


@dataclass(frozen=True)
class Output:
    """One output by name, parsed: ``kind`` and its arguments."""
    name: str
    kind: str
    args: tuple = field(default=())


def parse(name) -> Output:
    """An output name as :class:`Output`.

    Raises:
        ArgumentError: a name that is none of :data:`NAMES`.
    """
    if not isinstance(name, str):
        raise ArgumentError("outputs", f"an output is named by a string, got "
                                       f"{type(name).__name__}")
    text = name.strip()
    if text in ("stress_max", "stress_ks"):
        return Output(text, text)
    for kind, pattern in (("frequency", _FREQUENCY), ("buckling", _BUCKLING)):
        match = pattern.match(text)
        if match:
            if int(match.group(1)) < 1:
                raise ArgumentError("outputs", f"{name!r}: modes count from 1")
            return Output(text, kind, (int(match.group(1)),))
    match = _COMPLIANCE.match(text)
    if match:
        node, rot, i, j = match.groups()
        return Output(text, "compliance", (int(node), None if rot is None else int(rot),
                                           int(i), int(j)))
    match = _COLUMN.match(text)
    if match:
        return Output(text, "column", (match.group(1), f"{match.group(2)}.{match.group(3)}"))
    raise ArgumentError("outputs", f"{name!r} is not an output flexmbd.design knows: name "
                                   f"{', '.join(NAMES)}")


@dataclass
class Sensitivity:
    """The state's change per unit of one parameter: all coordinates ``dx`` ``(nx,)``, the
    constraint stresses ``dmu`` ``(nc,)``, the data's change (its step ``h``) and the
    workspaces of the designs around (at the points of
    :data:`~flexmbd.design.data.STENCIL`)."""
    name: str
    h: float
    data: DataChange
    dx: np.ndarray
    dmu: np.ndarray
    engines: Sequence


@dataclass(frozen=True)
class _Pair:
    """What an eigenvalue's or a compliance's derivative needs of the tangent's change,
    ``[l; nu_l]^T dA [r; nu_r]`` with the geometric stiffness weighted by ``weight`` (and,
    when ``weighed``, ``l^T dM r``), and how it ``finish``es: ``(dA, dM)`` ``(k,)`` each
    to the output's derivative ``(k,)``."""
    left: np.ndarray
    right: np.ndarray
    nu_left: np.ndarray
    nu_right: np.ndarray
    weight: float
    finish: Callable[[np.ndarray, np.ndarray], np.ndarray]
    weighed: bool = False


class Evaluator:
    """The values and derivatives of outputs at one design (``Design`` holds the state)."""

    def __init__(self, design):
        self.design = design
        self._modes: dict[int, object] = {}

    # --- values ---------------------------------------------------------------------------
    def value(self, out: Output) -> float:
        d = self.design
        if out.kind == "column":
            return float(d.statics[out.name][-1])
        if out.kind == "frequency":
            return float(self.modes(out.args[0]).frequencies[out.args[0] - 1])
        if out.kind == "buckling":
            k = out.args[0]
            factors = buckling(d.lin, k).factors
            if len(factors) < k:
                raise ArgumentError("outputs", f"{out.name}: the state has "
                                               f"{len(factors)} buckling factors")
            return float(factors[k - 1])
        if out.kind == "compliance":
            node, rot, i, j = out.args
            C = node_compliance(d.lin, node, rot)
            if not (i < C.shape[0] and j < C.shape[1]):
                raise ArgumentError("outputs", f"{out.name}: the compliance is "
                                               f"{C.shape[0]}x{C.shape[1]}")
            return float(C[i, j])
        stresses = self.stress_points(d.x, d.sigma, d.model)
        if out.kind == "stress_max":
            return float(stresses.max())
        return ks(stresses)

    def modes(self, k: int):
        if k not in self._modes:
            available = len(self.design.model.dynamic_q_labels)
            if k > available:
                raise ArgumentError("outputs", f"f{k}: the model has {available} degrees "
                                               f"of freedom")
            # one more than asked: a repeated k-th frequency shows in its neighbour
            self._modes[k] = vibration_modes(self.design.lin, min(k + 1, available))
        return self._modes[k]

    @staticmethod
    def stress_points(x: np.ndarray, sigma: np.ndarray, model, elements=None) -> np.ndarray:
        """Every beam's (or those numbered in ``elements``) largest von Mises stress at
        both ends ``(2 n_beams,)`` [Pa]."""
        return np.array([s for beam in beam_stresses(model, x, sigma, elements).values()
                         for s in beam.ends])

    # --- derivatives ----------------------------------------------------------------------
    def gradients(self, outs: list[Output], sens: list[Sensitivity]
                  ) -> tuple[dict[str, np.ndarray], list[str]]:
        """Each output's derivative to each parameter ``(k,)`` by name, and the notes.
        The frequencies', compliances' and buckling factors' tangent changes are one
        evaluation of the elements for all of them."""
        found: dict[str, np.ndarray] = {}
        notes: list[str] = []
        pairs: dict[str, _Pair] = {}
        for out in outs:
            if out.kind == "column":
                found[out.name] = self._column(out)
            elif out.kind in ("stress_max", "stress_ks"):
                found[out.name], note = self._stress(out, sens)
                notes += [note] if note else []
            else:
                pairs[out.name] = {"frequency": self._frequency, "compliance":
                                   self._compliance, "buckling": self._buckling}[out.kind](out)
        if pairs:
            d, batch = self.design, list(pairs.values())
            columns = [np.column_stack(v) for v in zip(*((p.left, p.right, p.nu_left,
                                                          p.nu_right) for p in batch), strict=True)]
            dA = d.tangent_changes(*columns, np.array([p.weight for p in batch]))
            weighed = [q for q, p in enumerate(batch) if p.weighed]
            dM = np.zeros_like(dA)
            if weighed:
                dM[weighed] = d.mass_changes(columns[0][:, weighed], columns[1][:, weighed])
            for q, (name, pair) in enumerate(pairs.items()):
                found[name] = pair.finish(dA[q], dM[q])
        return {out.name: found[out.name] for out in outs}, notes

    def _column(self, out: Output) -> np.ndarray:
        d = self.design
        prefix, label = out.args
        model = d.model
        if prefix == "x":
            return d.dx[:, model._coordinate_index(f"x{label}")]
        if prefix == "f":
            index = model._coordinate_index(f"x{label}")
            return d.reaction_changes()[:, index]
        index = model._deformation_index(f"e{label}")
        return (d.de if prefix == "e" else d.dsigma)[:, index]

    def _frequency(self, out: Output) -> _Pair:
        d, k = self.design, out.args[0]
        modes = self.modes(k)
        omega2 = modes.omega2
        near = [omega2[j] for j in (k - 2, k) if 0 <= j < len(omega2)]
        if any(abs(o - omega2[k - 1]) <= REPEATED * abs(omega2[k - 1]) for o in near):
            raise ArgumentError("outputs", f"{out.name} is a repeated frequency (its "
                                           f"neighbour within {REPEATED:g}): it has no "
                                           f"derivative; break the symmetry, or ask for "
                                           f"another output")
        value = omega2[k - 1]
        transfer = modes.linearization.F_q[:, modes.linearization.dynamic]
        shape = modes.shapes[:, k - 1]
        phi = transfer @ shape
        psi = transfer @ d.left_mode(shape, value)
        nu, eta = d.bordered_mode(phi, value), d.bordered_mode(psi, value, transposed=True)
        mass = psi @ d.state.engine.mass(d.x)[0] @ phi
        hz = 8.0 * np.pi**2 * modes.frequencies[k - 1]
        return _Pair(psi, phi, eta, nu, 1.0, weighed=True,
                     finish=lambda dA, dM: (dA - value * dM) / mass / hz)

    def _compliance(self, out: Output) -> _Pair:
        d = self.design
        node, rot, i, j = out.args
        T = d.unit_loads(node, rot)                   # (nx, m)
        W, nu_w = d.bordered_solve(T, transposed=False)
        V, nu_v = d.bordered_solve(T, transposed=True)
        dT = d.unit_load_changes(node, rot)           # (k_params, nx, m)
        turned = dT[:, :, i] @ W[:, j] + dT[:, :, j] @ V[:, i]
        return _Pair(V[:, i], W[:, j], nu_v[:, i], nu_w[:, j], 1.0,
                     finish=lambda dA, dM: turned - dA)

    def _buckling(self, out: Output) -> _Pair:
        """``d lambda = -(psi^T (dK0 + lambda dG0) phi + 2 nu^T dD_c phi) / phi^T G0 phi`` on
        the symmetric problem :func:`~flexmbd.buckling` solves (its matrices'
        symmetric parts: a quadratic form sees only those)."""
        d, k = self.design, out.args[0]
        found = buckling(d.lin, k + 1 if k < len(d.model.dynamic_q_labels) else k)
        factors = found.factors
        if len(factors) < k:
            raise ArgumentError("outputs", f"{out.name}: the state has {len(factors)} "
                                           f"buckling factors")
        factor = factors[k - 1]
        if any(abs(f - factor) <= REPEATED * abs(factor) for j, f in enumerate(factors)
               if j != k - 1):
            raise ArgumentError("outputs", f"{out.name} is a repeated buckling factor: it has "
                                           f"no derivative; break the symmetry, or ask for "
                                           f"another output")
        phi = found.linearization.F_q[:, found.linearization.dynamic] @ found.shapes[:, k - 1]
        nu = d.buckling_border(phi, factor)
        G = found.linearization.block("G0")
        shape = found.shapes[:, k - 1]
        curvature = shape @ G @ shape
        return _Pair(phi, phi, nu, nu, factor, finish=lambda dA, dM: -dA / curvature)

    def _stress(self, out: Output, sens: list[Sensitivity]) -> tuple[np.ndarray, str]:
        """``stress_max`` (the maximising point's derivative) or ``stress_ks``: central
        differences of the stress evaluation along the exact change of state and data."""
        d = self.design
        points = self.stress_points(d.x, d.sigma, d.model)
        top = int(np.argmax(points))
        rivals = np.flatnonzero(points >= (1.0 - COMPETING) * points[top])
        note = ("" if len(rivals) == 1 or out.kind != "stress_max" else
                f"stress_max: {len(rivals)} points lie within {COMPETING:g} of the largest; "
                f"its derivative is the first's (the maximum is not smooth here)")

        # stress_max follows its point alone: its beam is the only one evaluated
        beams = list(beam_stresses(d.model, d.x, d.sigma))   # in stress_points' order
        only = [beams[top // 2]] if out.kind == "stress_max" else None

        def measure(values: np.ndarray) -> float:
            return float(values[top % 2]) if only else ks(values)

        gradient = np.empty(len(sens))
        for n, s in enumerate(sens):
            values = [measure(self.stress_points(d.x + k * s.h * d.dx[n], d.sigma + k * s.h *
                                                 d.dsigma[n], built.model, only))
                      for (k, _), built in zip(STENCIL, d.sides[n], strict=True)]
            gradient[n] = rate(values, s.h)
        return gradient, note


def ks(stresses: np.ndarray) -> float:
    """The Kreisselmeier-Steinhauser aggregate ``s_max (1 + ln(sum exp(rho (s_i / s_max -
    1))) / rho)`` of ``stresses`` [Pa], ``rho`` :data:`KS_RHO`: the stresses relative to the
    largest, so it is the same for any unit and stress level; above the largest by at
    most ``ln(n) / rho`` of it, and it follows every point's stress, where the largest
    alone jumps from point to point (its slope changes there by about ``1 / rho``)."""
    top = float(stresses.max())
    if top <= 0.0:
        return top
    return top * (1.0 + float(np.log(np.sum(np.exp(KS_RHO * (stresses / top - 1.0)))))
                  / KS_RHO)


def moment_loads(lam: np.ndarray) -> np.ndarray:
    """The generalized forces ``(4, 3)`` on Euler parameters ``lam`` of unit global moments
    about x, y and z."""
    return np.stack([euler_forces(lam, axis) for axis in np.eye(3)], axis=1)

