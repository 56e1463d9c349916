"""A SPACAR Light model made an ordinary flexmbd model, numbered as SPACAR Light numbers it.

User node ``j`` becomes translational node ``3j - 2``, rotational node ``3j - 1`` and,
where an element with ``warping`` uses it, warping node ``3j``. User element ``i``
becomes ``nbeams`` spatial (or warping) beams, numbered on from 1 over the elements in
order; the nodes between them are numbered on from
``3n + 1``, three numbers each. The flexible deformations (``flex``) of every beam are
dynamic degrees of freedom; releases (``rls``) go on the last beam of an element, as
SPACAR Light puts them.

Loads and inputs follow SPACAR Light's static mode: ``force_initial``, ``moment_initial``
and ``displ_initial_*``, ``rot_initial*`` act from the first load step; ``force``,
``moment``, ``displ_*`` and ``rot*`` are added over the load steps (SPACAR's ``DELXF`` and
``DELINPX``). An input rotation prescribes Euler parameters, as SPACAR does: ``rot``
``lam1..lam3``, ``rot_x`` only ``lam1`` (and so on), moved linearly over the steps.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..builder import ModelBuilder
from ..elements.spatial_beam import default_orientation
from ..errors import ArgumentError, ModelError
from ..model import Model
from ..motion import Polynomial
from ..sections import Circle, Material, Rectangle, Section
from .fields import ElementSet, NodeProps, Options
from .plausible import check_section


@dataclass
class LightModel:
    """The flexmbd model of a SPACAR Light description and what a run needs besides.

    Attributes:
        model: the mechanism.
        positions: the user nodes ``(n, 3)`` [m].
        elements: the user elements ``(m, 2)``, pairs of user node numbers.
        beams: per user element (1-based), its beams' element numbers in order.
        sets: per user element, its property set (None: rigid and massless).
        connected: the user nodes an element uses.
        load_increment: loads added over the load steps by coordinate label [N, N m].
        input_increment: input increments over the load steps by label [m, -].
        transfer_inputs, transfer_outputs: the state-space inputs (``"x4.1"``) and outputs
            (``"x4.1"``, rates ``"xd4.1"``) in SPACAR Light's order, with its names.
        releases: the released deformations ``(beam, k)``.
        options: the checked ``opt``.
        notes: what was read in a way worth saying.
        styles: per beam its set's ``color``, ``opacity`` and ``hide`` for pictures
            (:func:`flexmbd.plot.plot_sections`).
    """

    model: Model
    positions: np.ndarray
    elements: np.ndarray
    beams: dict[int, tuple[int, ...]]
    sets: dict[int, ElementSet | None]
    connected: frozenset[int]
    load_increment: dict[str, float]
    input_increment: dict[str, float]
    transfer_inputs: list[tuple[str, str]]
    transfer_outputs: list[tuple[str, str]]
    releases: list[tuple[int, int]]
    options: Options
    notes: list[str] = field(default_factory=list)
    styles: dict[int, dict] = field(default_factory=dict)


def translational(node: int) -> int:
    """SPACAR Light's translational node of user node ``node``."""
    return 3 * node - 2


def rotational(node: int) -> int:
    """SPACAR Light's rotational node of user node ``node``."""
    return 3 * node - 1


def section_of(s: ElementSet) -> Section | None:
    if s.cshape == "rect":
        return Rectangle(s.dim[0], s.dim[1])
    if s.cshape == "circ":
        return Circle(s.dim[0])
    return None


def assemble(positions: np.ndarray, elements: np.ndarray, props: dict[int, NodeProps],
             sets: list[ElementSet], opt: Options, notes: list[str]) -> LightModel:
    """Build the model (releases made, automatic ones when ``opt.rls`` is not given)."""
    n = len(positions)
    builder = ModelBuilder(opt.filename or "spacar light model")
    # SPACAR Light's conventions release deformations on purpose (a warping node left
    # free): not the forgotten properties the builder warns a Python user about
    builder.missing_properties = "note"
    builder.unit_doubts = "off"      # said by the set's fields (plausible.check_material)
    connected = frozenset(int(v) for v in elements.ravel())
    for j in sorted(connected):
        builder.add_node(translational(j), *positions[j - 1])
    owner = {e: s for s in sets for e in s.elems}
    unused = sorted(set(range(1, n + 1)) - connected)
    if unused:
        notes.append(f"node{'s' if len(unused) > 1 else ''} "
                     f"{', '.join(map(str, unused))} not attached to an element")
    beams: dict[int, tuple[int, ...]] = {}
    warped: set[int] = set()         # warping nodes in the model
    held: set[int] = set()           # those of rigid warping elements, fixed
    next_beam, next_node = 1, 3 * n + 1
    checked: set[int] = set()   # the sets whose section was held to their elements
    for i, (p, q) in enumerate(elements, 1):
        s = owner.get(i)
        if s is not None and s.dim and s.number not in checked:
            length = float(np.linalg.norm(positions[q - 1] - positions[p - 1]))
            before = len(notes)
            check_section(f"eprops({s.number})", s.dim, length, i, notes)
            if len(notes) > before:
                checked.add(s.number)
        orien = _orientation(i, positions[p - 1], positions[q - 1], s, notes)
        count = s.nbeams if s else 1
        section = section_of(s) if s else None
        ends = _warping_ends(s, int(p), int(q), notes)
        builder.add_spatial_beams(next_beam, translational(p), rotational(p), translational(q),
                                  rotational(q), count, orien,
                                  new_nodes=next_node, dynamic=(), node_step=3, warping=ends)
        if ends:
            nodes = {*ends, *(next_node + 3 * k + 2 for k in range(count - 1))}
            warped |= nodes
            if s is not None and not s.flex:   # SPACAR Light fixes a rigid one's warping
                held |= nodes
        beams[i] = tuple(range(next_beam, next_beam + count))
        if s is not None and section is not None:
            for beam in beams[i]:
                builder.set_section(beam, section, _material(s))
        next_beam += count
        next_node += 3 * (count - 1)
    _classify(builder, beams, owner, opt)
    increments = _nodes(builder, positions, props, connected, opt)
    _fix_warping(builder, props, warped, held, notes)
    if opt.gravity is not None:
        builder.set_gravity(*opt.gravity)
    releases = [(e, k) for e, ks in sorted(_user_releases(beams, opt).items()) for k in ks]
    try:
        if opt.rls is None:
            releases = builder.release_overconstraints()   # names an under-constrained one
            if releases:
                notes.append("over-constraints released: " +
                             ", ".join(f"element {_user_element(beams, e)} (beam {e}) "
                                       f"deformation {k}" for e, k in releases))
        model = builder.build()
    except ModelError as error:
        flexible = any(s is not None and s.flex for s in owner.values())
        if flexible and opt.rls is not None:
            raise ArgumentError("opt.rls", "with the releases given the model does not close "
                                           "(" + str(error).removeprefix("invalid model: ") +
                                           "); leave rls out, and flexmbd releases the "
                                           "over-constraints itself, as SPACAR Light "
                                           "does") from None
        if flexible:
            raise
        raise ArgumentError("eprops", "no element set has flex, so every element is rigid, "
                                      "and the rigid elements constrain each other (" +
                                      str(error).removeprefix("invalid model: ")[:200] +
                                      "...): give the sets of the flexures flex, the "
                                      "deformations that bend (1 to 6)") from None
    inputs, outputs = _transfer(props, opt)
    return LightModel(model, positions, elements, beams, {i: owner.get(i) for i in beams},
                      connected, increments[0], increments[1], inputs, outputs, releases, opt,
                      notes, _styles(beams, owner, notes))


#: the sine between an element and its orientation vector below which SPACAR Light refuses
#: the vector as (almost) along the element
ALONG = 1e-5


def _orientation(element: int, p: np.ndarray, q: np.ndarray, s: ElementSet | None,
                 notes: list[str]) -> tuple[float, float, float]:
    """The orientation vector of user element ``element`` from ``p`` to ``q`` [m]: its
    set's ``orien`` (default ``[0 1 0]``). One along the element is refused, naming the
    field, where it matters (a rectangular section's width direction, as SPACAR Light
    refuses it); for a round or no section SPACAR's own choice replaces it, noted."""
    orien = s.orien if s else (0.0, 1.0, 0.0)
    along = (q - p) / np.linalg.norm(q - p)
    vector = np.array(orien) / np.linalg.norm(orien)
    if np.sqrt(max(1.0 - float(np.dot(along, vector)) ** 2, 0.0)) >= ALONG:
        return orien
    direction = ", ".join(f"{v:.4g}" for v in along)
    if s is not None and s.cshape == "rect":   # (a rectangle is given its orien)
        raise ArgumentError(f"eprops({s.number}).orien",
                            f"orien lies along element {element} ({direction}): give a "
                            f"vector across the set's elements (the rectangle's width "
                            f"direction)")
    chosen = tuple(float(v) for v in default_orientation(along)[0])
    notes.append(f"element {element} lies along its orientation vector "
                 f"[{' '.join(f'{v:g}' for v in orien)}], which "
                 f"{'a round section' if s is not None else 'an element without a set'} "
                 f"does not need: SPACAR's choice [{' '.join(f'{v:g}' for v in chosen)}] is "
                 f"taken instead")
    return chosen  # type: ignore[return-value]


def _styles(beams: dict[int, tuple[int, ...]], owner: dict[int, ElementSet],
            notes: list[str]) -> dict[int, dict]:
    """The sets' ``color`` (a colour name, RGB in 0..1 or 0..255), ``opacity`` and
    ``hide`` by beam; SPACAR Light's numbered palette is not flexmbd's, so a number is
    noted and drawn grey, as is a name matplotlib does not know or RGB out of range."""
    from matplotlib.colors import is_color_like

    styles = {}
    for i, numbers in beams.items():
        s = owner.get(i)
        if s is None:
            continue
        style: dict = {"hide": s.hide}
        if s.opacity is not None:
            style["alpha"] = s.opacity
        color = s.color
        rgb = _rgb(color)
        if rgb is not None:
            style["color"] = tuple(rgb / 255.0) if np.any(rgb > 1) else tuple(rgb)
        elif isinstance(color, str) and is_color_like(color):
            style["color"] = color
        elif color is not None:
            note = f"eprops({s.number}).color {color!r} is drawn grey (give a colour name " \
                   f"or RGB)"
            if note not in notes:
                notes.append(note)
        for beam in numbers:
            styles[beam] = style
    return styles


def _rgb(color) -> np.ndarray | None:
    """``color`` as three numbers from 0 to 255, or None."""
    if not isinstance(color, (list, tuple, np.ndarray)) or len(color) != 3:
        return None
    try:
        rgb = np.asarray(color, dtype=float)
    except (TypeError, ValueError):
        return None
    return rgb if np.all(np.isfinite(rgb)) and np.all((rgb >= 0) & (rgb <= 255)) else None


def warping_node(node: int) -> int:
    """SPACAR Light's warping node of user node ``node``."""
    return 3 * node


def _warping_ends(s: ElementSet | None, p: int, q: int, notes: list[str]
                  ) -> tuple[int, int] | None:
    """The warping nodes of an element with ``warping`` (None: a beam without warping);
    a circular section has no warping, so it stays a beam (SPACAR Light warns too)."""
    if s is None or not s.warping:
        return None
    if s.cshape != "rect":
        note = f"eprops({s.number}).warping: a circular section does not warp; its " \
               f"elements are beams without warping"
        if note not in notes:
            notes.append(note)
        return None
    return warping_node(p), warping_node(q)


def _fix_warping(builder: ModelBuilder, props: dict[int, NodeProps], warped: set[int],
                 held: set[int], notes: list[str]) -> None:
    """Restrain warping where SPACAR Light does: at nodes with ``fix`` or ``fix_warp``,
    and on rigid warping elements (their warping would have no stiffness)."""
    fixed = set(held)
    for j, p in props.items():
        if p.fix_warp and warping_node(j) not in warped:
            notes.append(f"nprops({j}).fix_warp: no element with warping uses node {j}")
        if (p.fix or p.fix_warp) and warping_node(j) in warped:
            fixed.add(warping_node(j))
    for node in sorted(fixed):
        builder.fix(node)


def _material(s: ElementSet) -> Material:
    """The set's material; a rigid set's is rigid (SPACAR Light needs no moduli for it)."""
    if not s.flex:
        return Material.rigid(s.dens or 0.0)
    assert s.emod is not None and s.smod is not None
    return Material(s.emod, s.smod, s.dens or 0.0)


def _user_element(beams: dict[int, tuple[int, ...]], beam: int) -> int:
    return next(i for i, numbers in beams.items() if beam in numbers)


def _user_releases(beams, opt: Options) -> dict[int, tuple[int, ...]]:
    """``opt.rls`` by beam: the last beam of each element."""
    return {beams[i][-1]: ks for i, ks in (opt.rls or {}).items() if ks}


def _classify(builder: ModelBuilder, beams, owner, opt: Options) -> None:
    for i, ks in sorted((opt.rls or {}).items()):
        s = owner.get(i)
        if ks and not (s is not None and s.flex):
            what = (f"belongs to a set without flex (eprops({s.number}))" if s is not None
                    else "is in no element set")
            raise ArgumentError(f"opt.rls({i})", f"element {i} {what}: its deformations are "
                                                 f"rigid, and releasing them would leave the "
                                                 f"body free to bend there, a hinge without "
                                                 f"stiffness; release only deformations of "
                                                 f"flexible elements (a set with flex), or "
                                                 f"leave rls out to release over-constraints "
                                                 f"automatically")
    released = _user_releases(beams, opt)
    for i, numbers in beams.items():
        s = owner.get(i)
        flex = s.flex if s else ()
        for beam in numbers:
            dynamic = [k for k in flex if k not in released.get(beam, ())]
            if dynamic:
                builder.dynamic_deformation(beam, *dynamic)
            if beam in released:
                builder.release(beam, *released[beam])


def _nodes(builder: ModelBuilder, positions, props: dict[int, NodeProps], connected,
           opt: Options) -> tuple[dict[str, float], dict[str, float]]:
    """Fixes, inputs, loads and masses of the user nodes; returns the load and input
    increments over the load steps."""
    loads: dict[str, float] = {}
    inputs: dict[str, float] = {}
    static = opt.mode == 10 and not opt.transfer
    for j, p in sorted(props.items()):
        if j not in connected:
            given = _given_fields(p)
            if given:
                raise ArgumentError(f"nprops({j})", f"gives {', '.join(given)}, but node {j} "
                                                    f"is not attached to an element (no row "
                                                    f"of elements names it): attach it, or "
                                                    f"give these to a node that is")
            continue
        t, r = translational(j), rotational(j)
        if p.fix or p.fix_pos:
            builder.fix(t)
        if p.fix or p.fix_orien:
            builder.fix(r)
        if p.fix_dirs:
            builder.fix(t, *p.fix_dirs)
        for k in sorted(set(p.displ) | set(p.displ_initial)):
            if opt.mode == 3:
                builder.dynamic_coordinate(t, k)
                continue
            if opt.transfer:
                continue
            start = positions[j - 1][k - 1] + p.displ_initial.get(k, 0.0)
            builder.input_coordinate(t, k, law=Polynomial(start))
            if k in p.displ:
                inputs[f"x{t}.{k}"] = p.displ[k]
        for k in p.rot_dirs:
            if opt.mode == 3:
                builder.dynamic_coordinate(r, k)
                continue
            if opt.transfer:
                continue
            start = 0.0 if p.rot_initial is None else float(p.rot_initial[k - 1])
            builder.input_coordinate(r, k, law=Polynomial(start))
            if p.rot is not None:
                inputs[f"x{r}.{k}"] = float(p.rot[k - 1])
        if static or opt.mode == 3:
            if p.force_initial is not None:
                builder.add_force(t, *p.force_initial)
            if p.moment_initial is not None:
                builder.add_force(r, *p.moment_initial)
            for node, values in ((t, p.force), (r, p.moment)):
                first = 1 if node == t else 2   # a moment's slots are lam1..lam3
                for k, value in enumerate(values if values is not None else (), first):
                    loads[f"x{node}.{k}"] = loads.get(f"x{node}.{k}", 0.0) + float(value)
        if p.mass:
            builder.add_point_mass(t, p.mass)
        if p.mominertia is not None:
            builder.add_rotary_inertia(r, *p.mominertia)
    return loads, inputs


def _given_fields(p: NodeProps) -> list[str]:
    """The fields of a node's properties that differ from the defaults (arrays
    compared by value)."""
    default = NodeProps()
    given = []
    for f in dataclasses.fields(p):
        value, unset = getattr(p, f.name), getattr(default, f.name)
        if isinstance(value, np.ndarray) or isinstance(unset, np.ndarray):
            same = (value is None and unset is None) or (
                value is not None and unset is not None and np.array_equal(value, unset))
        else:
            same = value == unset
        if not same:
            given.append(f.name)
    return given


def _transfer(props: dict[int, NodeProps], opt: Options
              ) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """State-space inputs and outputs, numbered in node order as SPACAR Light numbers them,
    with its names (``"force-x n3"``)."""
    if not opt.transfer:
        return [], []
    inputs, outputs = [], []
    for j, p in sorted(props.items()):
        t = translational(j)
        for name in p.transfer_in:
            k = "xyz".index(name[-1]) + 1
            inputs.append((f"x{t}.{k}", f"force-{name[-1]} n{j}"))
        for name in p.transfer_out:
            k = "xyz".index(name[-1]) + 1
            rate = name.startswith("veloc")
            outputs.append((f"{'xd' if rate else 'x'}{t}.{k}",
                            f"{'veloc' if rate else 'displ'}-{name[-1]} n{j}"))
    if not inputs or not outputs:
        raise ArgumentError("opt.transfer", "needs transfer_in and transfer_out on nodes "
                                            "(nprops)")
    return inputs, outputs
