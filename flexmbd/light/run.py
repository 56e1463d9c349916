"""``light.run``: a SPACAR Light description built, solved over its load steps and
linearized at every step's equilibrium."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..analysis.eigen import FEW_MODES_FROM
from ..analysis.linearization import Linearization
from ..analysis.modes import NO_VALUE, buckling, in_frame, node_compliance, vibration_modes
from ..analysis.statespace import StateSpace, state_space
from ..analysis.statics import StaticResult, static_equilibrium
from ..analysis.stresses import beam_stresses
from ..errors import ArgumentError
from ..progress import progress_bar
from ..settings import RunSettings
from .build import LightModel, assemble, rotational, translational
from .custom import with_custom_lines
from .fields import (
    DEFAULT_LOADSTEPS,
    ElementSet,
    element_sets,
    flag,
    geometry,
    node_props,
    options,
)
from .picture import show_input
from .plausible import check_displacements, check_stress
from .results import ElementResult, LightResult, LightStateSpace, NodeResult, OneBased

#: eigenfrequencies per step of a model too large for the whole spectrum (opt.nmodes)
DEFAULT_MODES = 12


def _older(opt, more: tuple):
    """``opt`` of a call in the form of SPACAR Light before its 2019 versions,
    ``spacarlight(nodes, elements, nprops, eprops, rls, opt)``: the releases as a fifth
    argument (empty for automatic ones), the options sixth."""
    if not more:
        return opt
    if len(more) > 1:
        raise ArgumentError("run", f"takes nodes, elements, nprops, eprops, opt (or, as SPACAR "
                                   f"Light before 2019, rls then opt); got {5 + len(more)} "
                                   f"arguments")
    rls, opt = opt, more[0]
    if opt is not None and not isinstance(opt, dict):
        raise ArgumentError("opt", f"must be a dict of options, got {type(opt).__name__}")
    if opt is not None and "rls" in opt and rls not in (None, [], ()):
        raise ArgumentError("rls", "given twice: as the fifth argument and as opt['rls']")
    merged = dict(opt or {})
    if rls not in (None, [], ()):
        merged["rls"] = rls
    return merged


def build(nodes, elements, nprops=None, eprops=None, opt=None, *more) -> LightModel:
    """The flexmbd model of a SPACAR Light description, without running it (SPACAR
    Light's ``opt.showinputonly``). Arguments as :func:`run`.

    Returns:
        :class:`~flexmbd.light.build.LightModel`: ``.model`` and the numbering.

    Raises:
        ArgumentError: a field, value or combination SPACAR Light refuses, named.
        ModelError: the model cannot be built (e.g. a mechanism), with every problem.
    """
    opt = _older(opt, more)
    notes: list[str] = []
    positions, pairs = geometry(nodes, elements, notes)
    props = node_props(nprops, len(positions))
    check_displacements(props, positions, notes)
    sets = element_sets(eprops, len(pairs), notes)
    opt = options(opt, len(pairs), notes)
    constraints = sum(p.constraints for p in props.values())
    if constraints < 6:
        raise ArgumentError("nprops", f"the nodes have too few constraints ({constraints} < 6; "
                                      f"fix, fix_*, displ_* or rot*): the model can move freely")
    bare = sorted(set(range(1, len(pairs) + 1)) - {e for s in sets for e in s.elems})
    if bare:
        notes.append(f"element{'s' if len(bare) > 1 else ''} {', '.join(map(str, bare))} "
                     f"{'have' if len(bare) > 1 else 'has'} no properties: rigid and massless")
    if not any(s.flex for s in sets):
        notes.append("no element has the flex property: nothing deforms")
    lm = assemble(positions, pairs, props, sets, opt, notes)
    if opt.customkin or opt.customdyn:
        lm = with_custom_lines(lm, file_settings(lm, load_steps(lm)))
    return lm


def load_steps(lm: LightModel) -> int:
    """The load increments of a run of ``lm``: ``opt.loadsteps - 1`` (SPACAR Light's first
    step carries only the ``*_initial`` loads), none when nothing is added over the steps."""
    given = bool(lm.load_increment or lm.input_increment)
    return (lm.options.loadsteps or DEFAULT_LOADSTEPS) - 1 if given else 0


def file_settings(lm: LightModel, steps: int) -> RunSettings:
    """The run settings of ``lm``'s SPACAR file: its increments over ``steps`` load steps."""
    return RunSettings(load_increment=dict(lm.load_increment),
                       input_increment=dict(lm.input_increment), load_steps=steps)


def run(nodes, elements, nprops=None, eprops=None, opt=None, *more) -> LightResult | Any:
    """Run a SPACAR Light model: static equilibrium over the load steps and, at every
    step's equilibrium, the eigenfrequencies, buckling load factors, compliance of every
    node and largest stresses.

    Args:
        nodes: ``(n, 3)`` node positions [m]; user node ``j`` is row ``j`` (1-based).
        elements: ``(m, 2)`` pairs ``[p, q]`` of user node numbers.
        nprops: node properties: a list of dicts (entry ``j - 1`` for node ``j``) or a
            dict ``{j: {...}}``, with SPACAR Light's fields (``fix``, ``force``, ...).
        eprops: element property sets: a list of dicts with SPACAR Light's fields
            (``elems``, ``emod``, ``smod``, ``dens``, ``cshape``, ``dim``, ``orien``,
            ``nbeams``, ``flex``, ...).
        opt: options, a dict with SPACAR Light's fields (``gravity``, ``loadsteps``,
            ``rls``, ``transfer``, ``calcbuck``, ``calccompl``, ``silent``, ...;
            ``customkin`` and ``customdyn``, SPACAR lines added to the model's file as
            SPACAR Light adds them, :mod:`flexmbd.light.custom`; ``spavisual`` true draws
            the last step into ``res.fighandle``). Without
            ``rls`` the over-constraints are released automatically and printed.
            ``loadsteps`` keeps SPACAR Light's meaning: ``n`` steps (default 10), the first
            under the ``*_initial`` loads alone and the last with the whole ``force``,
            ``moment``, ``displ`` and ``rot`` (so ``loadsteps`` 1 applies none of them, a
            note says so); :func:`~flexmbd.static_equilibrium`'s ``steps=n`` gives ``n +
            1`` rows instead.
        more: SPACAR Light before 2019 took the releases fifth and the options sixth,
            ``spacarlight(nodes, elements, nprops, eprops, rls, opt)``; that call is read
            too (``rls = []``: automatic releases).

    Returns:
        :class:`~flexmbd.light.results.LightResult`, read as SPACAR Light's output:
        ``res.node[j].p`` ``(3, nsteps)``, ``res.step[i].freq``, ``res.stressmax``, ...;
        with ``opt.showinputonly`` true, instead, the numbered picture of the input (a
        matplotlib figure, :func:`~flexmbd.light.show_input`), as SPACAR Light shows only
        that.

    Raises:
        ArgumentError: a field, value or combination SPACAR Light refuses, named.
        ModelError: the model cannot be built, with every problem.
        ConvergenceError: a load step did not converge; ``error.partial_result`` keeps the
            converged steps.

    Example:
        >>> import numpy as np
        >>> from flexmbd import light
        >>> nodes = np.array([[0, 0, 0], [0.1, 0, 0]])
        >>> res = light.run(nodes, [[1, 2]], {1: {"fix": True}, 2: {"force": [0, 0, -1]}},
        ...                 [{"elems": 1, "emod": 210e9, "smod": 80e9, "dens": 7800,
        ...                   "cshape": "rect", "dim": [20e-3, 1e-3], "orien": [0, 1, 0],
        ...                   "nbeams": 4, "flex": [1, 2, 3, 4, 5, 6]}],
        ...                 {"loadsteps": 3, "silent": True})
        >>> res.node[2].p.shape
        (3, 3)
    """
    opt = _older(opt, more)
    if isinstance(opt, Mapping) and flag(opt, "showinputonly", "opt"):
        return show_input(nodes, elements, nprops, eprops, opt, window=True)
    lm = build(nodes, elements, nprops, eprops, opt)
    opt_ = lm.options
    show = not opt_.silent
    given = bool(lm.load_increment or lm.input_increment)
    steps = load_steps(lm)
    if opt_.loadsteps and opt_.loadsteps > 1 and not given and not opt_.transfer:
        lm.notes.append("opt.loadsteps: no force, moment, displ or rot is added over the "
                        "steps, so there is one step")
    if given and opt_.loadsteps == 1:
        lm.notes.append("opt.loadsteps is 1: the one step is the state before the "
                        "increments (as in SPACAR Light, step 1 carries only the *_initial "
                        "loads), so force, moment, displ and rot are never applied; give "
                        "loadsteps 2 or more")
    if show:
        for note in lm.notes:
            print(f"flexmbd.light: {note}")
    told = len(lm.notes)
    statics = static_equilibrium(lm.model, load_increment=lm.load_increment or None,
                                 input_increment=lm.input_increment or None, steps=steps,
                                 progress=None if show else False)
    result = _results(lm, statics, show)
    lm.notes[told:] = merged_step_notes(lm.notes[told:])
    if opt_.filename:
        _write_files(lm, statics, steps, result)
    if opt_.meshcheck:
        result.meshcheck = _mesh_check(result, nodes, elements, nprops, eprops, opt)
    if show:   # what the linearized steps and the mesh check noticed
        for note in lm.notes[told:]:
            print(f"flexmbd.light: {note}")
    if opt_.spavisual:
        result.fighandle = result.plot(window=True)
    return result


def _write_files(lm: LightModel, statics: StaticResult, steps: int, result: LightResult
                 ) -> None:
    """``opt.filename``: the model as a SPACAR input file ``filename.dat`` (as SPACAR Light
    writes one; ``flexmbd run`` and ``flexmbd spacar 10`` run it again) and this run's
    result files ``filename.sbd`` and ``.sbm`` (as SPACAR writes them), beside the
    working directory's other files."""
    from ..io.dat import write_dat
    from ..io.sbd import write_sbd, write_sbm

    assert lm.options.filename is not None
    base = Path(lm.options.filename)
    written = [write_dat(lm.model, base.with_name(base.name + ".dat"),
                         file_settings(lm, steps))]
    if len(statics.t):
        written.append(write_sbd(base.with_name(base.name + ".sbd"), statics, 10))
        written.append(write_sbm(base.with_name(base.name + ".sbm"),
                                 [statics.linearization(k) for k in range(len(statics.t))]))
    lm.notes.append("opt.filename: wrote " + ", ".join(str(path) for path in written))


#: the lowest frequencies the mesh check compares (a coarse mesh's higher modes are its own)
MESH_MODES = 6


def _mesh_check(coarse: LightResult, nodes, elements, nprops, eprops, opt) -> dict:
    """``opt.meshcheck``: the same model with every set's ``nbeams`` doubled, and the
    largest change of each output relative to its size: the :data:`MESH_MODES` lowest
    frequencies, the largest stress, the nodes' displacements (relative to the largest
    displacement)."""
    finer_sets = [dict(props, nbeams=2 * int(props.get("nbeams") or 1))
                  if isinstance(props, Mapping) and props.get("elems") is not None else props
                  for props in (eprops or [])]
    finer_opt = {k: v for k, v in dict(opt or {}).items() if k != "meshcheck"}
    fine = run(nodes, elements, nprops, finer_sets, dict(finer_opt, silent=True))
    changes: dict[str, float] = {}
    k = min(MESH_MODES, len(coarse.freq), len(fine.freq))   # the higher ones are the mesh's
    if k:
        changes["freq"] = float(np.nanmax(np.abs(fine.freq[:k] - coarse.freq[:k]) /
                                          np.abs(fine.freq[:k])))
    if np.any(np.isfinite(fine.stressmax)) and np.nanmax(fine.stressmax) > 0:
        changes["stressmax"] = float(np.nanmax(np.abs(fine.stressmax - coarse.stressmax)) /
                                     np.nanmax(fine.stressmax))
    moved = [np.abs(f.p - f.p[:, :1]).max() for f in fine.node]
    if moved and max(moved) > 0:
        changes["displacement"] = float(max(np.abs(f.p - c.p).max() for f, c in
                                            zip(fine.node, coarse.node, strict=True))
                                        / max(moved))
    coarse.notes.append("meshcheck: with every set's nbeams doubled, " + ", ".join(
        f"{name} changes by {value:.2g}" for name, value in changes.items()) +
        " (relative, over all steps): refine nbeams until the changes are below what you "
        "accept")
    return changes


def _results(lm: LightModel, statics: StaticResult, show: bool) -> LightResult:
    model, opt = lm.model, lm.options
    rows = len(statics.t)
    lins = [statics.linearization(row) for row in range(rows)]   # each formed on use
    ndof = len(lins[0].dynamic) if lins else 0
    count = _mode_count(opt.nmodes, ndof, lm.notes)
    freq = np.full((count, rows), np.nan)
    buck = np.full((ndof, rows), np.nan) if opt.calcbuck else None
    loaded = bool(lm.load_increment or model.nodal_forces or any(model.gravity))
    driven = bool(lm.input_increment or len(model.input_coordinates))
    if opt.calcbuck and driven:
        lm.notes.append("opt.calcbuck: a displacement is prescribed, so the buckling load "
                        "factors also multiply the loads of the supports that drive it "
                        "(as SPACAR Light says)")
    elif opt.calcbuck and not loaded:
        lm.notes.append("opt.calcbuck: no loads are applied, so there are no buckling load "
                        "factors")
    shapes: list[dict] = [{} for _ in lins]
    if not ndof:
        lm.notes.append("the model has no degrees of freedom (no flexible deformation is "
                        "left free): no eigenfrequencies or buckling load factors; give the "
                        "flexures' sets flex")
    with progress_bar(statics.t, "linearized load steps", None if show else False) as advance:
        for row, lin in enumerate(lins if ndof else ()):
            _fill(freq, row, lambda lin=lin, row=row: _kept(
                shapes[row], "freqmodes", vibration_modes(lin, count)),
                lm.notes, "eigenfrequencies")
            if buck is not None:
                _fill(buck, row, lambda lin=lin, row=row: _kept(shapes[row], "buckmodes",
                                                                buckling(lin)),
                      lm.notes, "buckling")
            if advance is not None:
                advance(statics.t[row])
    unstable = [row + 1 for row in range(rows) if np.nanmin(freq[:, row], initial=0.0) < 0]
    if unstable:   # SPACAR Light warns here; a negative frequency is no vibration
        lowest = np.nanmin(freq[:, unstable[0] - 1])
        lm.notes.append(f"step{'s' if len(unstable) > 1 else ''} "
                        f"{', '.join(map(str, unstable))} "
                        f"{'lie' if len(unstable) > 1 else 'lies'} past a buckling point: the "
                        f"equilibrium is unstable there, and a mode with omega^2 < 0 grows "
                        f"instead of vibrating; it is listed as a negative frequency, "
                        f"-sqrt(-omega^2)/2pi ({lowest:.4g} Hz at step {unstable[0]})")
    stress, per_beam = _stresses(lm, lins)
    if stress is not None:
        check_stress(stress, lm.notes)
    nodes = [_node(lm, j, statics, lins) for j in range(1, len(lm.positions) + 1)]
    elements = []
    for i, beams in lm.beams.items():
        assert statics.e is not None
        e = np.stack([statics.e[:, list(model.elements[b].deformations)].T for b in beams])
        top = None
        if opt.stressperelement and per_beam:
            top = np.max([per_beam.get(b, np.full(rows, np.nan)) for b in beams], axis=0)
        p, q = lm.elements[i - 1]
        length = float(np.linalg.norm(lm.positions[q - 1] - lm.positions[p - 1]))
        frame = np.array(model.elements[beams[0]].reference[1:10]).reshape(3, 3).T
        elements.append(ElementResult(beams, np.full(len(beams), length / len(beams)), e, top,
                                      frame))
    space = _state_space(lm, lins[0]) if opt.transfer and lins else None
    if show and not statics.success:
        print(f"flexmbd.light: {statics.message}")
    return LightResult(OneBased(nodes, "node"), OneBased(elements, "element"), freq, buck,
                       stress, np.asarray(statics.t, dtype=float), ndof, lm.releases,
                       lm.notes, model, statics, space, lm.styles, shapes)


def _mode_count(nmodes: int | str | None, ndof: int, notes: list[str]) -> int:
    """Eigenfrequencies per step: ``opt.nmodes``, else SPACAR Light's whole spectrum of a
    model below :data:`~flexmbd.analysis.eigen.FEW_MODES_FROM` degrees of freedom and the
    :data:`DEFAULT_MODES` lowest of a larger one (noted: the whole spectrum's cost grows
    with the cube of the degrees of freedom, the lowest few's linearly)."""
    if nmodes == "all":
        return ndof
    if nmodes is not None:
        return min(int(nmodes), ndof)
    if ndof < FEW_MODES_FROM or ndof <= DEFAULT_MODES:
        return ndof
    notes.append(f"eigenfrequencies: the {DEFAULT_MODES} lowest of {ndof} per step "
                 f"(opt.nmodes: another count, or 'all' for the whole spectrum, whose cost "
                 f"grows with the cube of the degrees of freedom)")
    return DEFAULT_MODES


def _kept(shapes: dict, name: str, found) -> np.ndarray:
    """Keep the shapes (over the degrees of freedom) of modes or buckling under ``name``;
    return their frequencies or factors."""
    shapes[name] = found.shapes
    return found.frequencies if name == "freqmodes" else found.factors


_STEP_NOTE = re.compile(r"^(?P<what>.+?) at step (?P<step>\d+): (?P<why>.*)$", re.DOTALL)


def merged_step_notes(notes: list[str]) -> list[str]:
    """``notes`` with the same note of several load steps said once, naming the steps
    ("eigenfrequencies at steps 1 to 10: ..."), where the first of them stood."""
    steps: dict[tuple[str, str], list[int]] = {}
    for note in notes:
        found = _STEP_NOTE.match(note)
        if found:
            steps.setdefault((found["what"], found["why"]), []).append(int(found["step"]))
    out, said = [], set()
    for note in notes:
        found = _STEP_NOTE.match(note)
        if not found:
            out.append(note)
            continue
        key = (found["what"], found["why"])
        if key in said:
            continue
        said.add(key)
        numbers = steps[key]
        if len(numbers) == 1:
            out.append(note)
            continue
        run = numbers == list(range(numbers[0], numbers[-1] + 1))
        which = (f"{numbers[0]} to {numbers[-1]}" if run else ", ".join(map(str, numbers)))
        out.append(f"{key[0]} at steps {which}: {key[1]}")
    return out


def _fill(table: np.ndarray, row: int, values, notes: list[str], what: str) -> None:
    """Put ``values()`` into column ``row``; a step whose analysis has no value (a
    singular tangent, a state without stresses) keeps NaN, noted with the reason."""
    try:
        found = np.asarray(values(), dtype=float)
    except NO_VALUE as error:
        notes.append(f"{what} at step {row + 1}: {error}")
        return
    table[:len(found), row] = found[:table.shape[0]]


def _stresses(lm: LightModel, lins: list[Linearization]
              ) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """The largest von Mises stress per step over the flexible beams (all beams with a
    section with ``rigidstress``), and per beam."""
    rows = len(lins)
    per_beam: dict[int, np.ndarray] = {}
    counted = {b for i, beams in lm.beams.items() for b in beams
               if lm.options.rigidstress or _flexible(lm.sets[i])}
    for row, lin in enumerate(lins):
        try:
            found = beam_stresses(lm.model, lin.x, lin.sigma)
        except ArgumentError:   # no beam has a section
            break
        for b, s in found.items():
            per_beam.setdefault(b, np.full(rows, np.nan))[row] = s.von_mises
    top = np.zeros(rows)
    for b in counted & set(per_beam):
        top = np.fmax(top, per_beam[b])
    return top, per_beam


def _flexible(s: ElementSet | None) -> bool:
    return s is not None and bool(s.flex)


def _node(lm: LightModel, j: int, statics: StaticResult, lins: list[Linearization]
          ) -> NodeResult:
    rows = len(statics.t)
    model = lm.model
    t, r = translational(j), rotational(j)
    if j not in lm.connected:
        return NodeResult(np.tile(lm.positions[j - 1][:, None], (1, rows)), spa_nrs=(t, r),
                          attached=False)
    ct, cr = list(model.nodes[t].coordinates), list(model.nodes[r].coordinates)
    p = statics.x[:, ct].T
    quat = statics.x[:, cr].T
    axang = np.array([_axis_angle(q) for q in quat.T]).T
    euler = np.array([_euler_zyx(q) for q in quat.T]).T
    force = np.array([lin.reactions[ct] for lin in lins]).T
    moment = np.array([lin.reactions[cr[1:]] for lin in lins]).T
    glob = loc = None
    if lm.options.calccompl:
        glob, loc = np.full((6, 6, rows), np.nan), np.full((6, 6, rows), np.nan)
        for row, lin in enumerate(lins):
            try:
                glob[:, :, row] = node_compliance(lin, t, r, frame="global")
            except NO_VALUE as error:
                lm.notes.append(f"compliance of node {j} at step {row + 1}: {error}")
                continue
            loc[:, :, row] = in_frame(model, lin.x, r, glob[:, :, row], "body")
    return NodeResult(p, quat, axang, euler, force, moment, glob, loc, (t, r))


def _axis_angle(lam: np.ndarray) -> np.ndarray:
    """``[angle, ax, ay, az]`` of Euler parameters, as SPACAR Light gives it (axis x for a
    rotation too small to have one)."""
    c = min(max(float(lam[0]), -1.0), 1.0)
    angle = 2.0 * math.acos(c)
    s = math.sqrt(max(0.0, 1.0 - c * c))
    axis = np.array([1.0, 0.0, 0.0]) if s < 1e-3 else lam[1:4] / s
    return np.concatenate([[angle], axis])


def _euler_zyx(lam: np.ndarray) -> np.ndarray:
    """ZYX Euler angles ``[z, y, x]`` [rad] of Euler parameters."""
    q0, q1, q2, q3 = lam / np.linalg.norm(lam)
    sine = min(1.0, max(-1.0, -2.0 * (q1 * q3 - q0 * q2)))
    return np.array([math.atan2(2 * (q1 * q2 + q0 * q3), q0**2 + q1**2 - q2**2 - q3**2),
                     math.asin(sine),
                     math.atan2(2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2)])


def _state_space(lm: LightModel, lin: Linearization) -> StateSpace:
    """The state-space model with inputs and outputs in SPACAR Light's order."""
    inputs = [label for label, _ in lm.transfer_inputs]
    outputs = [label for label, _ in lm.transfer_outputs if not label.startswith("xd")]
    rates = ["x" + label[2:] for label, _ in lm.transfer_outputs if label.startswith("xd")]
    space = state_space(lin, inputs, outputs, rates, damping_ratio=lm.options.damping)
    order = [space.outputs.index(label) for label, _ in lm.transfer_outputs]
    return LightStateSpace(space.A, space.B, space.C[order], space.D[order], space.inputs,
                           tuple(space.outputs[k] for k in order), space.states,
                           InputName=tuple(name for _, name in lm.transfer_inputs),
                           OutputName=tuple(name for _, name in lm.transfer_outputs))
