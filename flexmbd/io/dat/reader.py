"""Reading a SPACAR input file, planar or spatial, into a model and its run settings.

Readings chosen where the format leaves room (the user guide's page on SPACAR files
lists them with every keyword, its table made from :mod:`flexmbd.io.dat.syntax`):

* element lines name their nodes in the order of the element type's roles; the
  types come from :data:`flexmbd.elements.ELEMENT_TYPES` (SPACAR's ``PLBEAM``,
  ``PLTRUSS``, ``PLHINGE`` and flexmbd's own ``PLRBEAM``, ``PLSPRING``);
* ``EM e rhoA`` gives the consistent mass of THEORY 5; ``EMLUMP e rhoA``
  (flexmbd's own keyword) the lumped one. A non-zero ``rhoI`` is refused:
  planar flexmbd beams carry no rotary inertia of the cross-section.
* ``ESTIFF`` and ``EDAMP`` take the values the element type declares, in its
  order (:attr:`~flexmbd.elements.base.ElementType.stiffness_values`): a truss or
  rigid beam ``EA`` (``c_A``); a beam ``EA EI [GA_s]`` (``c_A c_I``); a hinge its
  rotational stiffness (damping); a spring-damper ``k`` (``c``).
* ``ESIG e s1 [s2 ...]`` gives the pre-stresses of element ``e``'s deformations in
  order, as SPACAR writes them (the ones left off are 0).
* ``XF n Fx Fy`` loads a translational node, ``XF n M`` a rotational one;
  ``XM`` is a mass on a translational node and a rotary inertia on a
  rotational one.
* Block 2 ``INPUTX n dir x0 [v0 [a0]]`` is the law ``x0 + v0 t + a0 t^2 / 2``
  of a coordinate block 1 declared an input (``INPUTE`` likewise);
  ``STARTDE e k e0 [edot0]`` and ``STARTDX`` set initial values of dynamic
  degrees of freedom.
* ``TIMESTEP t_end n`` asks for ``n + 1`` output times; ``ERROR atol rtol``
  sets the integrator tolerances; ``ITERSTEP nit [nsteps [tol [flags ...]]]``, in
  SPACAR's order, the iteration limit, the load steps of a static analysis and
  the tolerance [m, rad] of the Newton position solve (the flags are SPACAR
  solver options and are not used).
* A file with a spatial element (``BEAM e p rp q rq ox oy oz``, ``HINGE e rp rq ax ay
  az``, ``TRUSS e p q``) is spatial: ``X n x y z``, three load components (a global
  moment on a rotational node), ``XM n Ixx Ixy Ixz Iyy Iyz Izz`` on a rotational node,
  ``EM e rhoA Jxx Jyy Jzz Jyz``, ``ESTIFF e EA GIt EIy EIz [sy sz]``, ``GRAVITY gx gy
  gz``; ``FIX n`` on a rotational node fixes ``lam1..lam3`` (so do ``INPUTX``, ``DYNX``
  without directions). A file of planar and spatial elements is refused, naming a line
  of each. Values SPACAR accepts that flexmbd does not model (warping ``ECw`` and
  ``Jw``) and ``OUTLEVEL`` are read and reported once in ``settings.notes``.
* Static load steps and the linear model: ``DELXF n F..`` (the total load increment
  over the load steps, as ``XF``), ``DELINPX n k delta`` and ``DELINPE e k delta``
  (total increments of inputs) of ``flexmbd static``. The inputs and outputs of
  ``flexmbd statespace`` come, as in SPACAR's transfer-function files (mode 9), from a
  third block after ``END HALT``: ``INPUTF i n k`` (force input ``i``), ``OUTX i n k``
  and ``OUTXP i n k`` (output ``i``: a position or its rate), in the order of their
  numbers. flexmbd's own earlier form, ``INPUTF n k..``, ``OUTX n k..`` and ``OUTXP n
  k..`` in block 2 (without numbers), is still read.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Literal, NamedTuple

from ... import checks
from ...builder import ModelBuilder
from ...elements import ELEMENT_TYPES, ROTATIONAL, TRANSLATIONAL
from ...elements.base import (
    COORDINATES_PER_NODE,
    SPATIAL_ROTATIONAL,
    SPATIAL_TRANSLATIONAL,
    is_translational,
)
from ...engine import output_bytes
from ...errors import ArgumentError, InputFileError, ModelError
from ...frozen import FrozenMap
from ...model import CoordinateClass, DeformationClass, Model
from ...motion import Polynomial
from ...settings import RunSettings
from .spacar95 import is_spacar95, parse_spacar95
from .syntax import LINE_DATA, DatText, Statement, parse_text

#: the load components of a node of each kind, as XF and DELXF name them
LOAD_WORDS = {TRANSLATIONAL: ("Fx", "Fy"), ROTATIONAL: ("M",),
              SPATIAL_TRANSLATIONAL: ("Fx", "Fy", "Fz"), SPATIAL_ROTATIONAL: ("Mx", "My", "Mz")}

#: input files larger than this [bytes] are refused before they are read
LARGEST_FILE = 64 * 2**20


class DatFile(NamedTuple):
    """What a SPACAR input file describes: the mechanism and how it is meant to be run.
    Unpacks as ``model, settings = read_dat(path)``."""

    model: Model
    settings: RunSettings


def read_dat(path: str | Path, *, release: bool = False) -> DatFile:
    """Read a SPACAR input file (``.dat``), planar or spatial.

    Args:
        path: the file.
        release: release the model's over-constraints as SPACAR Light does
            (:meth:`~flexmbd.ModelBuilder.release_overconstraints`); the releases are
            listed in ``settings.notes``.

    Returns:
        :class:`DatFile` ``(model, settings)``: the model, and the file's run settings
        (``TIMESTEP``, ``STARTDE``, ``STARTDX``, ``ERROR``, ``ITERSTEP``).

    Raises:
        InputFileError: naming the file, the line and the reason.

    Examples:
        An installed example file (``flexmbd example --file`` writes them out):

        >>> from importlib.resources import files
        >>> import flexmbd as fm
        >>> dat = fm.read_dat(files("flexmbd.examples") / "slider_crank_flex.dat")
        >>> print(dat.model.n_dof, dat.settings.t_end)
        3 0.08377580409572781
    """
    return dat_from_text(read_text(path), path, release=release)


def read_unchecked(path: str | Path) -> tuple[DatFile, list[str]]:
    """:func:`read_dat` that lists the problems of the model's constraints (a
    degree-of-freedom count that does not close, a singular ``D_c``) instead of refusing
    them, as SPACAR's mode 0 does: it stores ``D_x`` so that they can be found.

    Raises:
        InputFileError: any other problem, naming the file and the line.
    """
    constraints: list[str] = []
    dat = _reader_of(read_text(path), path, False).read(constraints)
    return dat, constraints


def read_text(path: str | Path) -> str:
    """The text of a SPACAR input file, refused when it cannot be one (too large, binary).

    Raises:
        InputFileError: naming the file and the reason.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputFileError(f"the file name must be a str or a path, got {path!r}")
    path = Path(path)
    try:
        with open(path, "rb") as file:  # bounded: /dev/zero or a disk image is not read whole
            data = file.read(LARGEST_FILE + 1)
    except OSError as error:
        raise InputFileError(f"cannot read the file: {error.strerror or error}",
                             str(path)) from None
    if len(data) > LARGEST_FILE:
        raise InputFileError(f"the file is larger than {LARGEST_FILE // 2**20} MiB; a SPACAR "
                             f"input file is text of a few kB", str(path))
    if b"\0" in data:
        line = data[:data.index(b"\0")].count(b"\n") + 1
        raise InputFileError("this is not a text file (it holds NUL bytes); a SPACAR input "
                             "file is text", str(path), line)
    return data.decode("utf-8", errors="replace")


def dat_from_text(text: str, path: str | Path | None = None, *, release: bool = False
                  ) -> DatFile:
    """:func:`read_dat` for the text of a file (``path`` is used in messages and the name)."""
    return _reader_of(text, path, release).read()


def _reader_of(text: str, path: str | Path | None, release: bool) -> _Reader:
    """The reader of a UT SPACAR or a SPACAR95 (Delft) text (:mod:`.spacar95`)."""
    if not is_spacar95(text, path):
        return _Reader(parse_text(text, path), release)
    parsed, notes = parse_spacar95(text, path)
    reader = _Reader(parsed, release)
    reader.remarks += notes
    return reader


class _Reader:
    """Applies the statements to a :class:`ModelBuilder`, checking what needs a line number."""

    def __init__(self, text: DatText, release: bool = False):
        self.text, self.path = text, text.path
        self.release = release
        name = Path(self.path).stem if self.path else "SPACAR model"
        self.builder = ModelBuilder(name)
        self.builder.missing_properties = "note"   # SPACAR runs them; a file cannot say 0
        self.elements: dict[int, tuple[str, tuple[int, ...], int]] = {}  # keyword, nodes, line
        self.kinds: dict[int, str] = {}
        self.positions: dict[int, int] = {}  # node -> line of X
        self.inputs: set[tuple[str, int, int]] = set()  # ("x"|"e", number, k) of block 1
        self.settings: dict[str, Any] = {}
        #: static increments, force inputs and outputs of the linear analyses
        self.linear: dict[str, Any] = {}
        self.initial: dict[str, tuple[tuple[float, float], Statement]] = {}
        self.classified: dict[str, list[int]] = {}  # label -> lines that classified it
        self.setting_statements: dict[str, Statement] = {}
        self.nodal_masses: dict[int, int] = {}  # node -> line of its last XM
        self.family_line: dict[bool, Statement] = {}  # spatial? -> its first element line
        self.dimensions: dict[int, int] = {}  # node -> coordinates given by X
        #: what the file gives that flexmbd reads but does not model: reason -> lines
        self.ignored: dict[str, list[int]] = {}
        #: how lines were read where SPACAR's meaning is not the plain one, a note each
        self.remarks: list[str] = []
        #: lines of beams without an orientation vector (SPACAR's choice, noted once)
        self.unoriented: list[int] = []
        #: FIX, INPUTX and DYNX lines of nodes not known when they were read
        self.pending: list[Statement] = []
        self.by_line = {s.line: s for s in (*text.kinematics, *text.dynamics, *text.transfer)}
        #: block 3 (transfer functions): number -> (label, statement) of inputs and outputs
        self.numbered: dict[str, dict[int, tuple[str, Statement]]] = {"inputs": {},
                                                                       "outputs": {}}

    def fail(self, statement: Statement, message: str):
        raise InputFileError(f"{statement.keyword}: {message}", self.path, statement.line)

    def read(self, constraints: list[str] | None = None) -> DatFile:
        """The file's model and settings; with a ``constraints`` list, problems of the
        model's constraints (:meth:`~flexmbd.ModelBuilder.assemble`) are added to it
        instead of refused."""
        for statement in self.text.kinematics:
            self.kinematic(statement)
        self.check_positions()
        for statement in self.text.dynamics:
            self.dynamic(statement)
        for statement in self.text.transfer:
            self.transfer(statement)
        self.order_transfer()
        try:
            if self.release:
                released = self.builder.release_overconstraints()
                if released:
                    self.remarks.append("released over-constraints as SPACAR Light does: " +
                                        ", ".join(f"RLSE {e} {k}" for e, k in released))
            if constraints is None:
                model = self.builder.build()
            else:
                model, found = self.builder.assemble()
                constraints += found
        except ModelError as error:
            raise self.located(error.problems) from None
        if self.unoriented:
            lines = self.unoriented
            self.remarks.append(
                f"line{'s' if len(lines) > 1 else ''} {', '.join(map(str, lines))}: no "
                f"orientation vector; the local y axis is SPACAR's choice, the global axis "
                f"in which the element's direction is smallest (the last of equal ones) "
                f"made perpendicular to it")
        for note in self.builder.notes:   # e.g. a flexible beam without ESTIFF
            line = next((self.line_of(kind, key) for kind, key in getattr(note, "about", ())),
                        None)
            self.remarks.append(f"line {line}: {note}" if line else str(note))
        return DatFile(model, self.run_settings(model))

    def located(self, problems: list[str]) -> InputFileError:
        """The builder's problems, each at the line of the statement that made what it is
        about (the END of the kinematics block for the model as a whole)."""
        placed = []
        for problem in problems:
            lines = [self.line_of(kind, key) for kind, key in getattr(problem, "about", ())]
            line = next((n for n in lines if n is not None), self.text.kinematics_end)
            placed.append((line, f"{self.keyword_at(line)}: {problem}"))
        if len(placed) == 1:
            return InputFileError(placed[0][1], self.path, placed[0][0])
        text = "".join(f"\n  - line {line}: {message}" for line, message in placed)
        return InputFileError(f"{len(placed)} problems:{text}", self.path, placed[0][0])

    def line_of(self, kind: str, key) -> int | None:
        """The line of the statement that made node, element, coordinate or deformation
        ``key``; for a coordinate or deformation the last that classified it, for a
        nodal mass the last XM of the node."""
        if kind in ("coordinate", "deformation"):
            if self.classified.get(key):
                return self.classified[key][-1]
            number = int(key[1:].split(".")[0])
            return self.line_of("node" if kind == "coordinate" else "element", number)
        if kind == "nodal mass":
            return self.nodal_masses.get(key) or self.line_of("node", key)
        if kind == "element":
            return self.elements[key][2] if key in self.elements else None
        if key in self.positions:
            return self.positions[key]
        return next((line for _, nodes, line in self.elements.values() if key in nodes), None)

    def keyword_at(self, line: int) -> str:
        statement = self.by_line.get(line)
        return statement.keyword if statement else "END"

    def run_settings(self, model: Model) -> RunSettings:
        """The settings, with initial values checked to name dynamic degrees of freedom."""
        dynamic = {label for label, c in zip(model.coordinate_labels, model.coordinate_class,
                                             strict=True) if c == CoordinateClass.DYNAMIC}
        dynamic |= {label for label, c in zip(model.deformation_labels,
                                              model.deformation_class, strict=True)
                    if c == DeformationClass.DYNAMIC}
        for label, (_, statement) in self.initial.items():
            if label not in dynamic:
                self.fail(statement, f"{label} is not a dynamic degree of freedom (those are: "
                                     f"{', '.join(sorted(dynamic)) or 'none'}); classify it "
                                     f"with DYNX or DYNE in the kinematics block")
        self.check_settings(model)
        initial = {label: pair for label, (pair, _) in self.initial.items()}
        linear: dict[str, Any] = {
            name: FrozenMap(values) if isinstance(values, dict) else tuple(values)
            for name, values in self.linear.items()}
        notes = tuple(f"{what} on line{'s' if len(lines) > 1 else ''} "
                      f"{', '.join(map(str, lines))}: read and ignored"
                      for what, lines in self.ignored.items()) + tuple(self.remarks)
        return RunSettings(initial=FrozenMap(initial), **self.settings, **linear,
                           notes=notes)

    def check_settings(self, model: Model) -> None:
        """ITERSTEP, ERROR and TIMESTEP values that cannot work, refused at their line
        before any run: tolerances below round-off or not small against the model,
        iteration limits that cannot help, outputs that cannot fit in memory."""
        given, length = self.setting_statements, model.characteristic_length
        try:
            if "ITERSTEP" in given:
                checks.iteration_limit(self.settings["max_iterations"])
                if "tolerance" in self.settings:
                    checks.position_tolerance(self.settings["tolerance"], length,
                                              float(abs(model.x0).max(initial=0)))
            if "ERROR" in given:
                checks.integrator_tolerances(self.settings["rtol"], self.settings["atol"],
                                             length)
            if "TIMESTEP" in given:
                checks.output_memory(self.settings["steps"] + 1, output_bytes(model),
                                     "steps")
        except ArgumentError as error:
            keyword = {"max_iterations": "ITERSTEP", "tolerance": "ITERSTEP", "rtol": "ERROR",
                       "atol": "ERROR", "steps": "TIMESTEP"}[error.argument]
            self.fail(given[keyword], str(error))

    # --- block 1 -------------------------------------------------------------------------
    def kinematic(self, s: Statement) -> None:
        b, v = self.builder, s.values
        if s.keyword in ELEMENT_TYPES:
            number, nodes = v[0], tuple(v[1:])
            if number in self.elements:
                self.fail(s, f"element {number} is already defined on line "
                             f"{self.elements[number][2]}")
            etype = ELEMENT_TYPES[s.keyword]
            nodes, given = nodes[:len(etype.roles)], v[1 + len(etype.roles):]
            if number < 1 or min(nodes) < 1:
                self.fail(s, "element and node numbers must be positive")
            self.check_family(s, etype.is_spatial())
            for node, role in zip(nodes, etype.roles, strict=True):
                if self.kinds.setdefault(node, role.kind) != role.kind:
                    self.fail(s, f"node {node} is {self.kinds[node]} elsewhere but {role.kind} "
                                 f"here")
            data, at = {}, 0
            for name in etype.element_data:
                if name in LINE_DATA and (given[at:] or name not in etype.optional_data):
                    words = LINE_DATA[name]
                    if len(given[at:at + len(words)]) != len(words):
                        self.fail(s, f"the {name} takes {len(words)} values ({' '.join(words)})"
                                     f", got {len(given[at:at + len(words)])}")
                    data[name] = tuple(given[at:at + len(words)])
                    at += len(words)
            if "orientation" in etype.element_data and not any(data.get("orientation", ())):
                self.unoriented.append(s.line)
            self.elements[number] = (s.keyword, nodes, s.line)
            b.add_element(number, etype, nodes, **data)
        elif s.keyword == "X":
            node = v[0]
            if node in self.positions:
                self.fail(s, f"node {node} already has a position (line {self.positions[node]})")
            if self.kinds.get(node) in (ROTATIONAL, SPATIAL_ROTATIONAL):
                self.fail(s, f"node {node} is a rotational node (its rotation starts at 0); "
                             f"only translational nodes take X")
            self.positions[node] = s.line
            self.dimensions[node] = len(v) - 1
            b.add_node(node, *v[1:])
        elif s.keyword == "OUTLEVEL":
            self.ignore("OUTLEVEL (SPACAR's output level)", s)
        elif s.keyword in ("FIX", "INPUTX", "DYNX"):
            node, directions = v[0], v[1:]
            if node not in self.kinds and node not in self.positions:
                self.pending.append(s)  # an element or X line may name it further down
                return
            self.check_directions(s, node, directions)
            ks = directions or self.all_directions(s, node)
            self.classify(s, (f"x{node}.{k}" for k in ks))
            if s.keyword == "INPUTX":
                self.inputs |= {("x", node, k) for k in ks}
            {"FIX": b.fix, "INPUTX": b.input_coordinate, "DYNX": b.dynamic_coordinate}[
                s.keyword](node, *ks)
        else:  # INPUTE, DYNE, RLSE
            element, ks = v[0], v[1:]
            self.check_deformations(s, element, ks)
            ks = ks or range(1, self.etype(s, element).n_deformations() + 1)
            if self.etype(s, element).keyword == "RBEAM" and any(k > 1 for k in ks):
                self.fail(s, f"element {element} is an RBEAM: SPACAR's manual does not say "
                             f"which of its deformations 2 and 3 is which offset, so only its "
                             f"elongation (1) may be classified; the offsets stay rigid")
            self.classify(s, (f"e{element}.{k}" for k in ks))
            if s.keyword == "INPUTE":
                self.inputs |= {("e", element, k) for k in ks}
            {"INPUTE": b.input_deformation, "DYNE": b.dynamic_deformation,
             "RLSE": b.release}[s.keyword](element, *ks)

    def check_family(self, s: Statement, spatial: bool) -> None:
        """Refuse a file of planar and spatial elements, naming a line of each."""
        self.family_line.setdefault(spatial, s)
        other = self.family_line.get(not spatial)
        if other is not None:
            planar, space = (other, s) if spatial else (s, other)
            self.fail(s, f"the file mixes planar and spatial elements: {planar.keyword} on "
                         f"line {planar.line}, {space.keyword} on line {space.line}; a model "
                         f"is planar or spatial")

    def ignore(self, what: str, s: Statement) -> None:
        """Note a value flexmbd reads but does not model (reported once per kind)."""
        self.ignored.setdefault(what, []).append(s.line)

    def all_directions(self, s: Statement, node: int) -> range:
        """A node's directions when a line names none: all, but ``lam1..lam3`` of a spatial
        rotational node (its ``lam0`` follows from the normalization)."""
        kind = self.kind(s, node)
        return range(2, 5) if kind == SPATIAL_ROTATIONAL else \
            range(1, COORDINATES_PER_NODE[kind] + 1)

    def classify(self, s: Statement, labels) -> None:
        for label in labels:
            self.classified.setdefault(label, []).append(s.line)

    def kind(self, s: Statement, node: int) -> str:
        """Kind of a node known from elements or X; unknown nodes are an error."""
        if node in self.kinds:
            return self.kinds[node]
        if node in self.positions:
            return SPATIAL_TRANSLATIONAL if self.dimensions[node] == 3 else TRANSLATIONAL
        self.fail(s, f"node {node} is not used by any element and has no position")
        raise AssertionError  # unreachable: fail raises

    def check_directions(self, s: Statement, node: int, directions) -> None:
        kind = self.kind(s, node)
        top = COORDINATES_PER_NODE[kind]
        for k in directions:
            if not 1 <= k <= top:
                names = {1: "1", 2: "1 and 2"}.get(top, f"1 to {top}")
                self.fail(s, f"node {node} is {kind}: directions are {names}, got {k}")

    def etype(self, s: Statement, element: int):
        """The type of a defined element."""
        if element not in self.elements:
            self.fail(s, f"element {element} is not defined")
        return ELEMENT_TYPES[self.elements[element][0]]

    def check_deformations(self, s: Statement, element: int, ks) -> None:
        etype = self.etype(s, element)
        nd = etype.n_deformations()
        for k in ks:
            if not 1 <= k <= nd:
                self.fail(s, f"a {etype.keyword} has deformations 1 to {nd}, got {k}")

    def spatial(self) -> bool:
        """Whether the file is spatial: it has a spatial element, or (without elements) its
        first position has three coordinates."""
        if self.family_line:
            return True in self.family_line
        return next(iter(self.dimensions.values()), 2) == 3

    def check_family_values(self, s: Statement, count: int, planar: str, spatial: str) -> None:
        """Refuse an X or GRAVITY line with the other family's number of values."""
        want = 3 if self.spatial() else 2
        if count != want:
            self.fail(s, f"a {'spatial' if want == 3 else 'planar'} file gives "
                         f"{spatial if want == 3 else planar}, got {count} value(s)")

    def check_positions(self) -> None:
        """After block 1: the classification of nodes named before their elements, and
        the positions of all translational nodes."""
        for statement in self.pending:
            node = statement.values[0]
            if node in self.kinds or node in self.positions:
                self.kinematic(statement)
            elif statement.keyword == "FIX":  # SPACAR Light fixes every warping node
                self.remarks.append(f"FIX on line {statement.line}: node {node} is used by no "
                                    f"element; nothing to fix")
            else:
                self.kind(statement, node)  # refused: a node nothing defines
        for statement in self.text.kinematics:
            if statement.keyword == "X":
                self.check_family_values(statement, len(statement.values) - 1, "x y", "x y z")
        for number, (keyword, nodes, line) in sorted(self.elements.items()):
            for node in nodes:
                kind = self.kinds[node]
                if is_translational(kind) and node not in self.positions:
                    # SPACAR starts a translational node without an X line at the origin
                    origin = (0.0,) * (3 if kind == SPATIAL_TRANSLATIONAL else 2)
                    self.builder.add_node(node, *origin)
                    self.positions[node] = line
                    self.dimensions[node] = len(origin)
                    self.remarks.append(f"node {node} ({keyword} {number}, line {line}) has no "
                                        f"X line: it starts at the origin, as in SPACAR")

    # --- block 2 -------------------------------------------------------------------------
    def dynamic(self, s: Statement) -> None:
        if s.keyword in ("ITERSTEP", "ERROR", "TIMESTEP"):
            self.setting_statements[s.keyword] = s
        getattr(self, f"_{s.keyword.lower()}")(s)

    def positive(self, s: Statement, values) -> None:
        for value in values:
            if not value > 0:
                self.fail(s, f"values must be positive, got {value:g}")

    def _gravity(self, s: Statement) -> None:
        self.check_family_values(s, len(s.values), "gx gy", "gx gy gz")
        self.builder.set_gravity(*s.values)

    def _error(self, s: Statement) -> None:
        self.positive(s, s.values)
        self.settings.update(atol=s.values[0], rtol=s.values[1])

    def _iterstep(self, s: Statement) -> None:
        limit, *rest = s.values
        self.positive(s, s.values[:3])
        self.settings["max_iterations"] = limit
        if rest:
            self.settings["load_steps"] = int(rest[0])
        if len(rest) > 1:
            self.settings["tolerance"] = rest[1]
        if len(rest) > 2:
            self.settings["iteration_options"] = tuple(
                int(v) if float(v).is_integer() else v for v in rest[2:])

    def _usersig(self, s: Statement) -> None:
        self.routine(s, "user_loads")

    def _userinp(self, s: Statement) -> None:
        self.routine(s, "user_inputs")

    def routine(self, s: Statement, setting: str) -> None:
        """A user routine, found as a Python module of its name beside the file (SPACAR
        runs a MATLAB function of that name)."""
        name = s.values[0]
        directory = Path(self.path).resolve().parent if self.path else Path.cwd()
        if not (directory / f"{name}.py").is_file():
            ported = (f"; {name}.m is there: flexmbd runs routines in Python, so port it "
                      f"to {name}.py (the arguments and tables are SPACAR's, 1-based)"
                      if (directory / f"{name}.m").is_file() else "")
            self.fail(s, f"no {name}.py in {directory} for the routine {name}{ported}")
        self.settings[setting] = name
        self.settings["routine_dir"] = str(directory)

    def _timestep(self, s: Statement) -> None:
        self.positive(s, s.values)
        self.settings.update(t_end=s.values[0], steps=s.values[1])

    def _em(self, s: Statement,
            formulation: Literal["consistent", "lumped"] = "consistent") -> None:
        element, rho_a = s.values[0], s.values[1]
        etype = self.etype(s, element)
        if not etype.has_mass:
            self.fail(s, f"element {element} is a {etype.name}, which has no mass; use XM on "
                         f"its nodes")
        try:
            extra, unused = etype.mass_line(tuple(s.values[2:]))
        except ValueError as error:
            self.fail(s, str(error))
        for what in unused:
            self.ignore(what, s)
        if rho_a < 0:
            self.fail(s, f"mass per length {rho_a:g} is negative")
        self.builder.set_mass(element, rho_a, formulation, **extra)

    def _emlump(self, s: Statement) -> None:
        self._em(s, "lumped")

    def _estiff(self, s: Statement, what: str = "stiffness") -> None:
        element, values = s.values[0], s.values[1:]
        etype = self.etype(s, element)
        declared = etype.stiffness_values if what == "stiffness" else etype.damping_values
        if what == "stiffness":
            values, unused = etype.stiffness_line(tuple(values))
            for value in unused:
                self.ignore(value, s)
        if len(values) > len(declared):
            names = ", ".join(v.symbol for v in declared) or "none"
            self.fail(s, f"a {etype.keyword} takes {len(declared)} value(s) ({names}), got "
                         f"{len(values)}")
        if any(x < 0 for x in values):
            self.fail(s, "values must not be negative")
        setter = self.builder.set_stiffness if what == "stiffness" else self.builder.set_damping
        setter(element, **{v.name: x for v, x in zip(declared, values, strict=False)})

    def _edamp(self, s: Statement) -> None:
        self._estiff(s, "damping")

    def _esig(self, s: Statement) -> None:
        element, stresses = s.values[0], s.values[1:]
        etype = self.etype(s, element)
        if len(stresses) > etype.n_deformations():
            self.fail(s, f"a {etype.keyword} has {etype.n_deformations()} deformation(s), one "
                         f"pre-stress each in order; got {len(stresses)} values")
        for k, sigma0 in enumerate(stresses, 1):
            self.builder.set_prestress(element, k, sigma0)

    def _xm(self, s: Statement) -> None:
        node, values = s.values[0], s.values[1:]
        kind = self.kind(s, node)
        self.nodal_masses[node] = s.line
        if kind == SPATIAL_ROTATIONAL:
            if len(values) != 6:
                self.fail(s, f"node {node} is {kind}: give its inertia tensor Ixx Ixy Ixz "
                             f"Iyy Iyz Izz [kg m^2], got {len(values)} value(s)")
            self.builder.add_rotary_inertia(node, *values)
            return
        if len(values) != 1:
            self.fail(s, f"node {node} is {kind}: give one mass, got {len(values)} values")
        self.builder.add_point_mass(node, values[0])

    def nodal_load(self, s: Statement, increment: bool = False) -> tuple[int, tuple]:
        """Node and values of an ``XF``-like line, as many as the node's kind takes."""
        node, loads = s.values[0], s.values[1:]
        kind = self.kind(s, node)
        words = LOAD_WORDS[kind]
        if kind == SPATIAL_ROTATIONAL and len(loads) == 4:
            loads = self.euler_parameter_forces(s, node, loads)
        if len(loads) != len(words):
            self.fail(s, f"node {node} is {kind}: give "
                         f"{' '.join(('d' if increment else '') + w for w in words)}")
        return node, loads

    def euler_parameter_forces(self, s: Statement, node: int, forces) -> tuple:
        """The global moment of SPACAR's loads of a rotational node before 2017: forces on
        its four Euler parameters, ``0 2Mx 2My 2Mz`` at the reference orientation."""
        if forces[0] != 0.0:
            self.fail(s, f"node {node} is spatial rotational: its load is the global moment "
                         f"Mx My Mz; four values are SPACAR's Euler-parameter forces of before "
                         f"2017, 0 2Mx 2My 2Mz, whose first must be 0 (got {forces[0]:g})")
        moment = tuple(f / 2.0 for f in forces[1:])
        shown = ", ".join(f"{m:g}" for m in moment)
        self.remarks.append(f"{s.keyword} on line {s.line}: the four values on rotational "
                            f"node {node} are read as SPACAR's Euler-parameter forces of before "
                            f"2017, 0 2Mx 2My 2Mz: the moment ({shown})")
        return moment

    def check_input(self, s: Statement, kind: str, number: int, k: int) -> None:
        """Refuse a value for a coordinate (``kind`` ``"x"``) or deformation (``"e"``) that
        block 1 did not declare an input."""
        if (kind, number, k) not in self.inputs:
            what = (f"coordinate {k} of node {number}" if kind == "x" else
                    f"deformation {k} of element {number}")
            self.fail(s, f"{what} is not an input (INPUT{kind.upper()} in the kinematics "
                         f"block)")

    def _xf(self, s: Statement) -> None:
        node, loads = self.nodal_load(s)
        self.builder.add_force(node, *loads)

    def _inputx(self, s: Statement) -> None:
        node, k, *law = s.values
        self.check_directions(s, node, [k])
        self.check_input(s, "x", node, k)
        self.builder.input_coordinate(node, k, law=Polynomial(*law))

    def _inpute(self, s: Statement) -> None:
        element, k, *law = s.values
        self.check_deformations(s, element, [k])
        self.check_input(s, "e", element, k)
        self.builder.input_deformation(element, k, law=Polynomial(*law))

    def _startde(self, s: Statement) -> None:
        element, k, *start = s.values
        self.check_deformations(s, element, [k])
        self.initial[f"e{element}.{k}"] = ((start[0], start[1] if len(start) > 1 else 0.0), s)

    def _delxf(self, s: Statement) -> None:
        node, loads = self.nodal_load(s, increment=True)
        increments = self.linear.setdefault("load_increment", {})
        first = 2 if self.kind(s, node) == SPATIAL_ROTATIONAL else 1  # a moment's slots
        for k, value in enumerate(loads, first):
            increments[f"x{node}.{k}"] = increments.get(f"x{node}.{k}", 0.0) + value

    def _delinpx(self, s: Statement) -> None:
        node, k, delta = s.values
        self.check_directions(s, node, [k])
        self.check_input(s, "x", node, k)
        self.linear.setdefault("input_increment", {})[f"x{node}.{k}"] = delta

    def _delinpe(self, s: Statement) -> None:
        element, k, delta = s.values
        self.check_deformations(s, element, [k])
        self.check_input(s, "e", element, k)
        self.linear.setdefault("input_increment", {})[f"e{element}.{k}"] = delta

    def _inputf(self, s: Statement, name: str = "force_inputs") -> None:
        node, directions = s.values[0], s.values[1:]
        self.check_directions(s, node, directions)
        ks = directions or self.all_directions(s, node)
        self.linear.setdefault(name, []).extend(f"x{node}.{k}" for k in ks)
        if name != "force_inputs":  # the outputs in the order of the lines
            prefix = "xd" if name == "rate_outputs" else "x"
            self.linear.setdefault("output_order", []).extend(f"{prefix}{node}.{k}" for k in ks)

    def _outlevel(self, s: Statement) -> None:
        self.ignore("OUTLEVEL (SPACAR's output level)", s)

    def _outx(self, s: Statement) -> None:
        self._inputf(s, "outputs")

    def _outxp(self, s: Statement) -> None:
        self._inputf(s, "rate_outputs")

    # --- block 3 (transfer functions, SPACAR's mode 9) -----------------------------------
    def transfer(self, s: Statement) -> None:
        """``INPUTF i n dir``, ``OUTX i n dir``, ``OUTXP i n dir``: input or output number
        ``i`` of the state-space model."""
        number, node, k = s.values
        self.check_directions(s, node, [k])
        family = "inputs" if s.keyword == "INPUTF" else "outputs"
        if number < 1:
            self.fail(s, f"{family} are numbered from 1, got {number}")
        if number in self.numbered[family]:
            self.fail(s, f"{family[:-1]} {number} is already defined on line "
                         f"{self.numbered[family][number][1].line}")
        label = f"{'xd' if s.keyword == 'OUTXP' else 'x'}{node}.{k}"
        self.numbered[family][number] = (label, s)

    def order_transfer(self) -> None:
        """The inputs and outputs of block 3 in the order of their numbers."""
        inputs = [label for _, (label, _) in sorted(self.numbered["inputs"].items())]
        outputs = [label for _, (label, _) in sorted(self.numbered["outputs"].items())]
        if inputs:
            self.linear.setdefault("force_inputs", []).extend(inputs)
        if outputs:
            self.linear.setdefault("outputs", []).extend(
                label for label in outputs if not label.startswith("xd"))
            self.linear.setdefault("rate_outputs", []).extend(
                "x" + label[2:] for label in outputs if label.startswith("xd"))
            self.linear.setdefault("output_order", []).extend(outputs)

    def _startdx(self, s: Statement) -> None:
        node, k, *start = s.values
        self.check_directions(s, node, [k])
        self.initial[f"x{node}.{k}"] = ((start[0], start[1] if len(start) > 1 else 0.0), s)
