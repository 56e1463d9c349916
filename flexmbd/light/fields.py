"""The fields of SPACAR Light's input structures, checked at the door.

``nprops``, ``eprops`` and ``opt`` arrive as Python dicts with SPACAR Light's field names.
Each is checked here for what SPACAR Light checks (names, types, combinations that cannot
work) and turned into plain values, so that building the model never meets a bad one.
An unknown field is refused with the closest known names and the whole list.
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ArgumentError
from .plausible import check_material, check_rotation

#: node fields, as SPACAR Light names them
NODE_FIELDS = (
    "fix", "fix_x", "fix_y", "fix_z", "fix_pos", "fix_orien", "fix_warp",
    "displ_x", "displ_y", "displ_z", "displ_initial_x", "displ_initial_y", "displ_initial_z",
    "rot", "rot_x", "rot_y", "rot_z", "rot_initial", "rot_initial_x", "rot_initial_y",
    "rot_initial_z", "force", "moment", "force_initial", "moment_initial", "mass",
    "mominertia", "transfer_in", "transfer_out")

#: element-set fields (``cw`` is SPACAR Light's deprecated name of ``warping``)
ELEMENT_FIELDS = ("elems", "emod", "smod", "dens", "cshape", "dim", "orien", "nbeams", "flex",
                  "warping", "color", "hide", "opacity", "cw")

#: options; ``spavisual`` true draws the result (``res.fighandle``), ``showinputonly`` the
#: numbered input instead of a run; ``filename`` writes the model's .dat and the run's
#: .sbd and .sbm
OPTION_FIELDS = ("gravity", "loadsteps", "rls", "mode", "transfer", "calcbuck", "calccompl",
                 "rigidstress", "stressperelement", "silent", "filename", "spavisual",
                 "nmodes", "meshcheck", "customkin", "customdyn", "showinputonly")

#: SPACAR Light options flexmbd does not take, with what to use instead
UNSUPPORTED_OPTIONS = {
    "customvis": "SPACAR's visualization lines: draw with flexmbd.plot",
}

TRANSFER_INPUTS = ("force_x", "force_y", "force_z")
TRANSFER_OUTPUTS = ("displ_x", "displ_y", "displ_z", "veloc_x", "veloc_y", "veloc_z")
SHAPES = ("rect", "circ")
#: SPACAR Light refuses elements whose lengths differ more than this; flexmbd notes it
LENGTH_RATIO = 1000.0
#: SPACAR Light's default number of load steps (ITERSTEP with 9 increments)
DEFAULT_LOADSTEPS = 10


def unknown(where: str, name: str, allowed: Sequence[str]) -> ArgumentError:
    """An unknown field, with the closest known names and all of them."""
    close = difflib.get_close_matches(name, allowed, n=3)
    hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
    return ArgumentError(where, f"unknown field {name!r}{hint} The fields are: "
                                f"{', '.join(allowed)}")


def _given(props: Mapping[str, Any], name: str) -> bool:
    """SPACAR Light's test: the field is there and not empty (``[]``, ``None``)."""
    value = props.get(name)
    if value is None:
        return False
    return not (isinstance(value, (list, tuple, np.ndarray)) and len(value) == 0)


def flag(props: Mapping[str, Any], name: str, where: str) -> bool:
    if not _given(props, name):
        return False
    value = props[name]
    if np.ndim(value) == 0 and (isinstance(value, (bool, np.bool_)) or value in (0, 1)):
        return bool(value)
    raise ArgumentError(f"{where}.{name}", f"must be true or false, got {value!r}")


def _numbers(props: Mapping[str, Any], name: str, where: str, count: int | None
             ) -> np.ndarray | None:
    """The field as finite floats, ``count`` of them (any number if None); None if absent."""
    if not _given(props, name):
        return None
    try:
        values = np.atleast_1d(np.asarray(props[name], dtype=float)).ravel()
    except (TypeError, ValueError):
        values = np.array([np.nan])
    if not np.all(np.isfinite(values)) or (count is not None and values.size != count):
        size = f"{count} finite number{'s' if count != 1 else ''}" if count else \
            "finite numbers"
        raise ArgumentError(f"{where}.{name}", f"must be {size}, got {props[name]!r}")
    return values


def _scalar(props: Mapping[str, Any], name: str, where: str) -> float | None:
    values = _numbers(props, name, where, 1)
    return None if values is None else float(values[0])


@dataclass
class NodeProps:
    """One user node's properties, checked (SPACAR Light's ``nprops(i)``)."""

    fix: bool = False
    fix_pos: bool = False
    fix_orien: bool = False
    fix_warp: bool = False
    fix_dirs: tuple[int, ...] = ()                   # fix_x/y/z as directions 1..3
    displ: dict[int, float] = field(default_factory=dict)          # direction -> increment
    displ_initial: dict[int, float] = field(default_factory=dict)  # direction -> offset
    rot: np.ndarray | None = None                    # Euler parameters of ``rot``
    rot_initial: np.ndarray | None = None            # and of ``rot_initial``
    rot_dirs: tuple[int, ...] = ()                   # lam directions (2, 3, 4) prescribed
    force: np.ndarray | None = None
    moment: np.ndarray | None = None
    force_initial: np.ndarray | None = None
    moment_initial: np.ndarray | None = None
    mass: float | None = None
    mominertia: np.ndarray | None = None
    transfer_in: tuple[str, ...] = ()
    transfer_out: tuple[str, ...] = ()

    @property
    def prescribed(self) -> bool:
        return bool(self.displ or self.displ_initial or self.rot_dirs)

    @property
    def constraints(self) -> int:
        """The constraints SPACAR Light counts on this node (fixes and inputs)."""
        count = 6 if self.fix else 0
        count += 3 * self.fix_pos + 3 * self.fix_orien + len(self.fix_dirs)
        count += len(set(self.displ) | set(self.displ_initial)) + len(self.rot_dirs)
        return count


def axis_angle_to_euler(values: np.ndarray) -> np.ndarray:
    """Euler parameters ``(lam0..lam3)`` of SPACAR Light's axis-angle ``[angle ax ay az]``."""
    axis = values[1:4]
    norm = float(np.linalg.norm(axis))
    if norm == 0.0:
        raise ArgumentError("rot", "the axis of [angle ax ay az] is zero")
    half = values[0] / 2.0
    return np.concatenate([[math.cos(half)], math.sin(half) * axis / norm])


def node_props(nprops, n_nodes: int) -> dict[int, NodeProps]:
    """Check ``nprops``: a list whose entry ``i - 1`` holds node ``i``'s fields (None or
    ``{}`` for none), or a dict ``{node: fields}``. Returns ``{node: NodeProps}``."""
    if nprops is None:
        entries: dict[int, Any] = {}
    elif isinstance(nprops, Mapping):
        entries = dict(nprops)
    elif isinstance(nprops, Sequence) and not isinstance(nprops, str):
        entries = {i + 1: props for i, props in enumerate(nprops)}
    else:
        raise ArgumentError("nprops", f"must be a list of dicts (entry i - 1 for node i) or a "
                                      f"dict {{node: dict}}, got {type(nprops).__name__}")
    out = {}
    for node, props in entries.items():
        if isinstance(node, bool) or not isinstance(node, (int, np.integer)) or \
                not 1 <= node <= n_nodes:
            raise ArgumentError("nprops", f"node {node!r} does not exist: the nodes are 1 to "
                                          f"{n_nodes} (the rows of nodes)")
        if props is None:
            continue
        if not isinstance(props, Mapping):
            raise ArgumentError(f"nprops({node})", f"must be a dict of fields, got "
                                                   f"{type(props).__name__}")
        out[int(node)] = _node(props, f"nprops({node})")
    return out


def _node(props: Mapping[str, Any], where: str) -> NodeProps:
    for name in props:
        if name not in NODE_FIELDS:
            raise unknown(where, str(name), NODE_FIELDS)
    p = NodeProps()
    p.fix, p.fix_pos = flag(props, "fix", where), flag(props, "fix_pos", where)
    p.fix_orien, p.fix_warp = flag(props, "fix_orien", where), flag(props, "fix_warp", where)
    p.fix_dirs = tuple(k for k, axis in enumerate("xyz", 1)
                       if flag(props, f"fix_{axis}", where))
    if p.fix and (p.fix_pos or p.fix_orien or p.fix_warp or p.fix_dirs):
        raise ArgumentError(where, "fix is combined with fix_pos, fix_orien, fix_warp or "
                                   "fix_x/y/z; fix already fixes the whole node")
    for k, axis in enumerate("xyz", 1):
        if (value := _scalar(props, f"displ_{axis}", where)) is not None:
            p.displ[k] = value
        if (value := _scalar(props, f"displ_initial_{axis}", where)) is not None:
            p.displ_initial[k] = value
    rot, rot_initial = (_numbers(props, name, where, 4) for name in ("rot", "rot_initial"))
    p.rot = None if rot is None else axis_angle_to_euler(rot)
    p.rot_initial = None if rot_initial is None else axis_angle_to_euler(rot_initial)
    dirs: list[tuple[int, ...]] = [(2, 3, 4)] if rot is not None or rot_initial is not None \
        else []
    for name, given in (("rot", rot), ("rot_initial", rot_initial)):
        if given is not None:
            check_rotation(where, name, float(given[0]))
    for k, axis in enumerate("xyz", 2):
        increment = _scalar(props, f"rot_{axis}", where)
        initial = _scalar(props, f"rot_initial_{axis}", where)
        for name, value in ((f"rot_{axis}", increment), (f"rot_initial_{axis}", initial)):
            if value is not None:
                check_rotation(where, name, value)
        if increment is None and initial is None:
            continue
        dirs.append((k,))
        # a rotation about one axis: its Euler parameter sin(angle / 2)
        if increment is not None:
            p.rot = _euler_about(p.rot, k, increment)
        if initial is not None:
            p.rot_initial = _euler_about(p.rot_initial, k, initial)
    if len(dirs) > 1:
        raise ArgumentError(where, "more than one input rotation (rot, rot_x, rot_y, rot_z and "
                                   "their rot_initial): give one per node")
    p.rot_dirs = dirs[0] if dirs else ()
    p.force, p.moment = (_numbers(props, n, where, 3) for n in ("force", "moment"))
    p.force_initial, p.moment_initial = (_numbers(props, n, where, 3)
                                         for n in ("force_initial", "moment_initial"))
    p.mass = _scalar(props, "mass", where)
    p.mominertia = _numbers(props, "mominertia", where, 6)
    p.transfer_in = _choices(props, "transfer_in", where, TRANSFER_INPUTS)
    p.transfer_out = _choices(props, "transfer_out", where, TRANSFER_OUTPUTS)
    _check_node(p, where)
    return p


def _euler_about(previous: np.ndarray | None, k: int, angle: float) -> np.ndarray:
    lam = np.zeros(4) if previous is None else previous.copy()
    lam[0], lam[k - 1] = math.cos(angle / 2.0), math.sin(angle / 2.0)
    return lam


def _choices(props, name: str, where: str, allowed: Sequence[str]) -> tuple[str, ...]:
    if not _given(props, name):
        return ()
    values = props[name]
    values = [values] if isinstance(values, str) else list(values)
    for value in values:
        if value not in allowed:
            raise ArgumentError(f"{where}.{name}", f"unknown value {value!r}; the values are: "
                                                   f"{', '.join(allowed)}")
    if len(set(values)) != len(values):
        raise ArgumentError(f"{where}.{name}", "should contain unique values")
    return tuple(values)


def _check_node(p: NodeProps, where: str) -> None:
    """SPACAR Light's combinations that cannot work on one node."""
    for k, axis in enumerate("xyz", 1):
        loaded = any(f is not None and f[k - 1] != 0 for f in (p.force, p.force_initial))
        given = [k in p.fix_dirs, loaded, k in p.displ or k in p.displ_initial]
        if sum(given) > 1:
            raise ArgumentError(where, f"fix_{axis}, force({k}) and displ_(initial_){axis} are "
                                       f"combined: one node direction takes one of them")
    moments = any(m is not None and np.any(m != 0) for m in (p.moment, p.moment_initial))
    if sum([p.fix_orien, moments, bool(p.rot_dirs)]) > 1:
        raise ArgumentError(where, "fix_orien, a moment and an input rotation are combined: the "
                                   "node's orientation takes one of them")
    if (p.transfer_in or p.transfer_out) and (p.fix or p.fix_pos):
        raise ArgumentError(where, "a fixed node cannot be a transfer-function input or output")
    for name in (*p.transfer_in, *p.transfer_out):
        k = "xyz".index(name[-1]) + 1
        if k in p.fix_dirs:
            raise ArgumentError(where, f"{name} on a node whose {name[-1]} is fixed")


@dataclass
class ElementSet:
    """One element property set, checked (SPACAR Light's ``eprops(j)``)."""

    number: int
    elems: tuple[int, ...]
    emod: float | None = None
    smod: float | None = None
    dens: float | None = None
    cshape: str | None = None
    dim: tuple[float, ...] = ()
    orien: tuple[float, float, float] = (0.0, 1.0, 0.0)
    nbeams: int = 1
    flex: tuple[int, ...] = ()
    warping: bool = False
    color: Any = None
    hide: bool = False
    opacity: float | None = None


def element_sets(eprops, n_elements: int, notes: list[str]) -> list[ElementSet]:
    """Check ``eprops``: a list of property sets (dicts). An element in two sets, an
    unknown element, a flexible set without its section and material are refused."""
    if eprops is None:
        eprops = []
    if isinstance(eprops, Mapping) or not isinstance(eprops, Sequence) or \
            isinstance(eprops, str):
        raise ArgumentError("eprops", f"must be a list of property sets (dicts), got "
                                      f"{type(eprops).__name__}")
    owner: dict[int, int] = {}
    out = []
    for j, props in enumerate(eprops, 1):
        where = f"eprops({j})"
        if props is None:
            continue
        if not isinstance(props, Mapping):
            raise ArgumentError(where, f"must be a dict of fields, got {type(props).__name__}")
        for name in props:
            if name not in ELEMENT_FIELDS:
                raise unknown(where, str(name), ELEMENT_FIELDS)
        if not _given(props, "elems"):
            others = [str(name) for name in props if _given(props, name)]
            if others:   # its properties would reach no element
                raise ArgumentError(f"{where}.elems", f"is missing: the set gives "
                                                      f"{', '.join(others)} but names no "
                                                      f"element; give elems, the rows of "
                                                      f"elements it applies to")
            notes.append(f"{where} is empty; it is ignored")
            continue
        elems = _numbers(props, "elems", where, None)
        assert elems is not None
        if np.any(elems != np.round(elems)) or np.any(elems < 1) or \
                np.any(elems > n_elements):
            raise ArgumentError(f"{where}.elems", f"must be element numbers 1 to {n_elements} "
                                                  f"(the rows of elements), got {props['elems']!r}")
        numbers = tuple(int(e) for e in elems)
        if len(set(numbers)) != len(numbers):
            raise ArgumentError(f"{where}.elems", "contains an element twice")
        for e in numbers:
            if e in owner:
                raise ArgumentError(f"{where}.elems", f"element {e} is already in "
                                                      f"eprops({owner[e]})")
            owner[e] = j
        out.append(_element_set(props, where, j, numbers, notes))
    return out


def _element_set(props, where: str, j: int, elems: tuple[int, ...], notes: list[str]
                 ) -> ElementSet:
    s = ElementSet(j, elems)
    s.emod, s.smod, s.dens = (_scalar(props, n, where) for n in ("emod", "smod", "dens"))
    for name, unit in (("emod", "Pa"), ("smod", "Pa")):
        value = getattr(s, name)
        if value is not None and value <= 0.0:
            raise ArgumentError(f"{where}.{name}", f"must be a positive modulus [{unit}], got "
                                                   f"{value:g}")
    if s.dens is not None and s.dens < 0.0:
        raise ArgumentError(f"{where}.dens", f"must be a density >= 0 [kg/m^3], got "
                                             f"{s.dens:g}")
    check_material(where, s.emod, s.smod, s.dens, notes)
    if _given(props, "cshape"):
        if props["cshape"] not in SHAPES:
            raise ArgumentError(f"{where}.cshape", f"must be 'rect' or 'circ', got "
                                                   f"{props['cshape']!r}")
        s.cshape = props["cshape"]
        dim = _numbers(props, "dim", where, 2 if s.cshape == "rect" else 1)
        if dim is None:
            wanted = "[width thickness]" if s.cshape == "rect" else "[diameter]"
            raise ArgumentError(where, f"cshape {s.cshape!r} needs dim ({wanted} in m)")
        s.dim = tuple(float(d) for d in dim)
        if min(s.dim) <= 0.0:
            wanted = "[width thickness]" if s.cshape == "rect" else "[diameter]"
            raise ArgumentError(f"{where}.dim", f"must be positive lengths [m] ({wanted}), "
                                                f"got {list(s.dim)}")
    elif _given(props, "dim"):
        notes.append(f"{where}.dim is not used without cshape")
    orien = _numbers(props, "orien", where, 3)
    if orien is not None:
        if not np.any(orien):
            raise ArgumentError(f"{where}.orien", "must not be the zero vector")
        s.orien = (float(orien[0]), float(orien[1]), float(orien[2]))
    elif s.cshape == "rect":
        raise ArgumentError(where, "a rectangular section needs orien (the vector along its "
                                   "width)")
    nbeams = _scalar(props, "nbeams", where)
    if nbeams is not None:
        if nbeams != round(nbeams) or nbeams < 1:
            raise ArgumentError(f"{where}.nbeams", f"must be a whole number >= 1, got {nbeams:g}")
        s.nbeams = int(nbeams)
    flex = _numbers(props, "flex", where, None)
    if flex is not None:
        if np.any(flex != np.round(flex)) or np.any((flex < 1) | (flex > 6)):
            raise ArgumentError(f"{where}.flex", f"deformation modes are 1 to 6, got "
                                                 f"{props['flex']!r}")
        s.flex = tuple(sorted({int(k) for k in flex}))
    s.warping = flag(props, "warping", where)
    if _given(props, "cw"):
        notes.append(f"{where}.cw is ignored, as SPACAR Light 1.38 ignores it: before 2019 "
                     f"cw = true multiplied a rectangular flexure's torsion stiffness GIt by "
                     f"a constrained-warping factor of its length and aspect, so a 2018 "
                     f"script gives other torsion frequencies here; warping = true models "
                     f"the constrained warping itself (warping beams)")
    s.hide = flag(props, "hide", where)
    s.opacity = _scalar(props, "opacity", where)
    if s.opacity is not None and not 0.0 < s.opacity < 1.0:
        raise ArgumentError(f"{where}.opacity", f"must lie in (0, 1), got {s.opacity:g}")
    s.color = props.get("color")
    if s.flex:
        for name in ("cshape", "emod", "smod", "dens"):
            if getattr(s, name) is None:
                raise ArgumentError(where, f"flexible elements (flex) need {name}")
    else:
        for name in ("emod", "smod"):
            if getattr(s, name) is not None:
                notes.append(f"{where}.{name} is not used without flex (rigid elements)")
        if s.dens and s.cshape is None:
            raise ArgumentError(where, "dens needs cshape and dim (the mass comes from the "
                                       "section)")
    return s


@dataclass
class Options:
    """The checked ``opt``."""

    gravity: tuple[float, float, float] | None = None
    loadsteps: int | None = None
    rls: dict[int, tuple[int, ...]] | None = None
    mode: int = 10
    transfer: bool = False
    damping: float | None = None
    calcbuck: bool = False
    calccompl: bool = True
    rigidstress: bool = False
    stressperelement: bool = False
    silent: bool = False
    filename: str | None = None
    #: eigenfrequencies per step, flexmbd's option: a count, "all", or None (SPACAR
    #: Light's whole spectrum for a small model, the lowest few of a large one)
    nmodes: int | str | None = None
    #: flexmbd's option: rerun with every set's nbeams doubled and report the changes
    meshcheck: bool = False
    #: SPACAR Light's pictures: the result drawn after the run, the input instead of it
    spavisual: bool = False
    showinputonly: bool = False
    #: SPACAR lines added to the kinematics and dynamics blocks of the model's file
    customkin: tuple[str, ...] = ()
    customdyn: tuple[str, ...] = ()


def options(opt, n_elements: int, notes: list[str]) -> Options:
    """Check ``opt`` (a dict, or None for the defaults)."""
    if opt is None:
        return Options()
    if not isinstance(opt, Mapping):
        raise ArgumentError("opt", f"must be a dict of options, got {type(opt).__name__}")
    for name in opt:
        if name in UNSUPPORTED_OPTIONS:
            raise ArgumentError(f"opt.{name}", f"is not supported by flexmbd; "
                                               f"{UNSUPPORTED_OPTIONS[name]}")
        if name not in OPTION_FIELDS:
            raise unknown("opt", str(name), OPTION_FIELDS)
    o = Options()
    gravity = _numbers(opt, "gravity", "opt", 3)
    o.gravity = None if gravity is None else (float(gravity[0]), float(gravity[1]),
                                             float(gravity[2]))
    steps = _scalar(opt, "loadsteps", "opt")
    if steps is not None:
        if steps != round(steps) or steps < 1:
            raise ArgumentError("opt.loadsteps", f"must be a whole number >= 1, got {steps:g}")
        o.loadsteps = int(steps)
    mode = _scalar(opt, "mode", "opt")
    if mode is not None:
        if mode not in (3, 10):
            raise ArgumentError("opt.mode", f"must be 10 (static) or 3 (inputs free), got "
                                            f"{mode:g}")
        o.mode = int(mode)
    for name in ("calcbuck", "rigidstress", "stressperelement", "silent", "meshcheck",
                 "spavisual", "showinputonly"):
        setattr(o, name, flag(opt, name, "opt"))
    if _given(opt, "calccompl"):
        o.calccompl = flag(opt, "calccompl", "opt")
    if _given(opt, "nmodes"):
        o.nmodes = _mode_count(opt["nmodes"])
    if _given(opt, "filename"):
        if not isinstance(opt["filename"], (str, os.PathLike)):
            raise ArgumentError("opt.filename", f"must be a file name (str or path), got "
                                                f"{opt['filename']!r}")
        o.filename = os.fspath(opt["filename"])
    for name in ("customkin", "customdyn"):
        if _given(opt, name):
            setattr(o, name, custom_lines(opt[name], name))
    _transfer(opt, o, notes)
    o.rls = _releases(opt.get("rls"), n_elements)
    return o


def custom_lines(value, name: str) -> tuple[str, ...]:
    """``opt.customkin`` or ``opt.customdyn`` (``name``) as lines: a list of strings (SPACAR
    Light's cell array), or one string (lines split at newlines)."""
    if isinstance(value, str):
        return tuple(value.splitlines())
    if not isinstance(value, Sequence) or not all(isinstance(v, str) for v in value):
        raise ArgumentError(f"opt.{name}", f"must be a list of SPACAR input lines (str), as "
                                           f"SPACAR Light's cell array {{'XM 4 0.5'}}; got "
                                           f"{value!r}")
    lines: list[str] = []
    for text in value:
        lines.extend(text.splitlines() or [""])
    return tuple(lines)


def _mode_count(value) -> int | str:
    """``nmodes``: a whole number >= 1, or ``"all"``."""
    if value == "all":
        return "all"
    if isinstance(value, bool) or not isinstance(value, int | np.integer | float) or \
            not value == round(value) or value < 1:
        raise ArgumentError("opt.nmodes", f"must be a whole number >= 1 (the lowest "
                                          f"eigenfrequencies per step) or 'all', got {value!r}")
    return int(value)


def _transfer(opt, o: Options, notes: list[str]) -> None:
    """``transfer``: ``True`` or ``[True, damping_ratio]`` (SPACAR's mode 9)."""
    if not _given(opt, "transfer"):
        return
    value = opt["transfer"]
    items = list(value) if isinstance(value, (list, tuple)) else [value]
    if len(items) not in (1, 2):
        raise ArgumentError("opt.transfer", f"must be true/false or [true, damping_ratio], got "
                                            f"{value!r}")
    o.transfer = flag({"transfer": items[0]}, "transfer", "opt")
    if len(items) == 2:
        ratio = _scalar({"transfer": items[1]}, "transfer", "opt")
        if ratio is None or ratio < 0:
            raise ArgumentError("opt.transfer", f"the relative damping must be >= 0, got "
                                                f"{items[1]!r}")
        o.damping = ratio
    if o.transfer:
        if o.calcbuck:
            raise ArgumentError("opt.transfer", "cannot be combined with calcbuck")
        if o.loadsteps is not None:
            notes.append("opt.loadsteps is not used with opt.transfer (one step, as SPACAR "
                         "Light)")
        o.loadsteps = 1


def _releases(rls, n_elements: int) -> dict[int, tuple[int, ...]] | None:
    """``rls``: a list with entry ``i - 1`` for element ``i`` (``{'def': [..]}`` as SPACAR
    Light's ``rls(i).def``, or the list itself), or a dict ``{element: [..]}``; None or
    empty for automatic releases."""
    if rls is None or (isinstance(rls, (list, tuple, dict)) and len(rls) == 0):
        return None
    entries = dict(rls) if isinstance(rls, Mapping) else \
        {i + 1: v for i, v in enumerate(rls)}
    out = {}
    for element, value in entries.items():
        where = f"opt.rls({element})"
        if not isinstance(element, (int, np.integer)) or not 1 <= element <= n_elements:
            raise ArgumentError("opt.rls", f"element {element!r} does not exist (1 to "
                                           f"{n_elements})")
        if isinstance(value, Mapping):
            extra = set(value) - {"def"}
            if extra:
                raise ArgumentError(where, f"unknown field {sorted(extra)[0]!r}; only 'def'")
            value = value.get("def")
        defs = _numbers({"def": value}, "def", where, None)
        if defs is None:
            continue
        if np.any(defs != np.round(defs)) or np.any((defs < 1) | (defs > 6)):
            raise ArgumentError(where, f"deformation modes are 1 to 6, got {value!r}")
        out[int(element)] = tuple(sorted({int(k) for k in defs}))
    return out


def geometry(nodes, elements, notes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Check ``nodes`` ``(n, 3)`` [m] and ``elements`` ``(m, 2)`` (user node numbers):
    the positions and the pairs as ints; lengths beyond SPACAR Light's ratio noted."""
    try:
        positions = np.asarray(nodes, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError("nodes", "must be an (n, 3) array of positions [m]") from None
    if positions.ndim != 2 or positions.shape[1] != 3 or not len(positions):
        raise ArgumentError("nodes", f"must be an (n, 3) array of positions [m], got shape "
                                     f"{positions.shape}")
    if not np.all(np.isfinite(positions)):
        raise ArgumentError("nodes", "holds a value that is not a finite number")
    try:
        raw = np.asarray(elements, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError("elements", "must be an (m, 2) array of node numbers") from None
    raw = raw.reshape(1, -1) if raw.ndim == 1 else raw
    if raw.ndim != 2 or raw.shape[1] != 2 or not len(raw):
        raise ArgumentError("elements", f"must be an (m, 2) array of node numbers [p q], got "
                                        f"shape {np.shape(elements)}")
    n = len(positions)
    if not np.all(np.isfinite(raw)) or np.any(raw != np.round(raw)) or \
            np.any((raw < 1) | (raw > n)):
        raise ArgumentError("elements", f"must hold node numbers 1 to {n} (the rows of nodes)")
    pairs = raw.astype(int)
    lengths = np.linalg.norm(positions[pairs[:, 1] - 1] - positions[pairs[:, 0] - 1], axis=1)
    for i, length in enumerate(lengths, 1):
        if pairs[i - 1, 0] == pairs[i - 1, 1]:
            raise ArgumentError("elements", f"element {i} connects node {pairs[i - 1, 0]} to "
                                            f"itself")
        if length == 0.0:
            raise ArgumentError("elements", f"element {i} has zero length (nodes "
                                            f"{pairs[i - 1, 0]} and {pairs[i - 1, 1]} coincide)")
    if lengths.max() / lengths.min() > LENGTH_RATIO:
        notes.append(f"element lengths differ by more than {LENGTH_RATIO:g} times (SPACAR "
                     f"Light refuses this)")
    return positions, pairs
