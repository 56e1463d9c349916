"""Reading a planar SPACAR input file into a :class:`~flexmbd.model.Model`.

Readings chosen where the format leaves room (documented in the README):

* ``EM e rhoA`` gives the consistent mass of THEORY 5; ``EMLUMP e rhoA``
  (flexmbd's own keyword) the lumped one. A non-zero ``rhoI`` is refused:
  planar flexmbd beams carry no rotary inertia of the cross-section.
* ``ESTIFF`` and ``EDAMP`` values follow the element's deformations: a truss
  or rigid beam takes ``EA`` (``c_A``); a beam ``EA EI [GA_s]`` (``c_A c_I``);
  a hinge its rotational stiffness (damping).
* ``XF n Fx Fy`` loads a translational node, ``XF n M`` a rotational one;
  ``XM`` is a mass on a translational node and a rotary inertia on a
  rotational one.
* Block 2 ``INPUTX n dir x0 [v0 [a0]]`` is the law ``x0 + v0 t + a0 t^2 / 2``
  of a coordinate block 1 declared an input (``INPUTE`` likewise);
  ``STARTDE e k e0 [edot0]`` and ``STARTDX`` set initial values of dynamic
  degrees of freedom.
* ``TIMESTEP t_end n`` asks for ``n + 1`` output times; ``ERROR atol rtol``
  sets the integrator tolerances; ``ITERSTEP nmax [tol]`` the iteration limit
  and tolerance [m, rad] of the Newton position solve.
"""

from __future__ import annotations

from pathlib import Path

from ..builder import ModelBuilder
from ..elements import ELEMENT_TYPES, ROTATIONAL, TRANSLATIONAL
from ..errors import InputFileError, ModelError
from ..model import Model
from ..motion import Polynomial
from .syntax import DatText, Statement, parse_text

#: which values ESTIFF / EDAMP take, per element keyword
_STIFFNESS = {"PLTRUSS": ("axial",), "PLRBEAM": ("axial",),
              "PLBEAM": ("axial", "bending", "shear"), "PLHINGE": ("hinge",)}
_DAMPING = {"PLTRUSS": ("axial",), "PLRBEAM": ("axial",), "PLBEAM": ("axial", "bending"),
            "PLHINGE": ("hinge",)}


def read_dat(path: str | Path) -> Model:
    """Read a planar SPACAR input file (``.dat``) into a model.

    The run settings of the file (``TIMESTEP``, ``STARTDE``, ``ERROR``,
    ``ITERSTEP``) are in ``model.settings``.

    Raises:
        InputFileError: naming the file, the line and the reason.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as error:
        raise InputFileError(f"cannot read the file: {error.strerror or error}",
                             str(path)) from None
    return model_from_text(text, path)


def model_from_text(text: str, path: str | Path | None = None) -> Model:
    """:func:`read_dat` for the text of a file (``path`` is used in messages and the name)."""
    return _Reader(parse_text(text, path)).model()


class _Reader:
    """Applies the statements to a :class:`ModelBuilder`, checking what needs a line number."""

    def __init__(self, text: DatText):
        self.text, self.path = text, text.path
        name = Path(self.path).stem if self.path else "SPACAR model"
        self.builder = ModelBuilder(name)
        self.elements: dict[int, tuple[str, tuple[int, ...], int]] = {}  # keyword, nodes, line
        self.kinds: dict[int, str] = {}
        self.positions: dict[int, int] = {}  # node -> line of X
        self.inputs: set[tuple[str, int, int]] = set()  # ("x"|"e", number, k) of block 1

    def fail(self, statement: Statement, message: str):
        raise InputFileError(f"{statement.keyword}: {message}", self.path, statement.line)

    def model(self) -> Model:
        for statement in self.text.kinematics:
            self.kinematic(statement)
        self.check_positions()
        for statement in self.text.dynamics:
            self.dynamic(statement)
        try:
            return self.builder.build()
        except ModelError as error:
            raise InputFileError(f"the model is not valid: {error}", self.path) from None

    # --- block 1 -------------------------------------------------------------------------
    def kinematic(self, s: Statement) -> None:
        b, v = self.builder, s.values
        if s.keyword in ELEMENT_TYPES:
            number, nodes = v[0], tuple(v[1:])
            if number in self.elements:
                self.fail(s, f"element {number} is already defined on line "
                             f"{self.elements[number][2]}")
            if number < 1 or min(nodes) < 1:
                self.fail(s, "element and node numbers must be positive")
            etype = ELEMENT_TYPES[s.keyword]
            for node, kind in zip(nodes, etype.node_kinds, strict=True):
                if self.kinds.setdefault(node, kind) != kind:
                    self.fail(s, f"node {node} is {self.kinds[node]} elsewhere but {kind} here")
            self.elements[number] = (s.keyword, nodes, s.line)
            b.add_element(number, etype, nodes)
        elif s.keyword == "X":
            node = v[0]
            if node in self.positions:
                self.fail(s, f"node {node} already has a position (line {self.positions[node]})")
            if self.kinds.get(node) == ROTATIONAL:
                self.fail(s, f"node {node} is a rotational node (its angle starts at 0); only "
                             f"translational nodes take X")
            self.positions[node] = s.line
            b.add_node(node, v[1], v[2])
        elif s.keyword in ("FIX", "INPUTX", "DYNX"):
            node, directions = v[0], v[1:]
            self.check_directions(s, node, directions)
            if s.keyword == "INPUTX":
                ks = directions or range(1, 3 if self.kind(s, node) == TRANSLATIONAL else 2)
                self.inputs |= {("x", node, k) for k in ks}
            {"FIX": b.fix, "INPUTX": b.input_coordinate, "DYNX": b.dynamic_coordinate}[
                s.keyword](node, *directions)
        else:  # INPUTE, DYNE, RLSE
            element, ks = v[0], v[1:]
            self.check_deformations(s, element, ks)
            if s.keyword == "INPUTE":
                self.inputs |= {("e", element, k) for k in ks or
                                range(1, self.n_deformations(element) + 1)}
            {"INPUTE": b.input_deformation, "DYNE": b.dynamic_deformation,
             "RLSE": b.release}[s.keyword](element, *ks)

    def kind(self, s: Statement, node: int) -> str:
        """Kind of a node known from elements or X; unknown nodes are an error."""
        if node in self.kinds:
            return self.kinds[node]
        if node in self.positions:
            return TRANSLATIONAL
        self.fail(s, f"node {node} is not used by any element and has no position")
        raise AssertionError  # unreachable: fail raises

    def check_directions(self, s: Statement, node: int, directions) -> None:
        top = 2 if self.kind(s, node) == TRANSLATIONAL else 1
        for k in directions:
            if not 1 <= k <= top:
                self.fail(s, f"node {node} is {self.kind(s, node)}: directions are 1"
                             f"{' and 2' if top == 2 else ''}, got {k}")

    def n_deformations(self, element: int) -> int:
        return ELEMENT_TYPES[self.elements[element][0]].n_deformations()

    def check_element(self, s: Statement, element: int) -> str:
        if element not in self.elements:
            self.fail(s, f"element {element} is not defined")
        return self.elements[element][0]

    def check_deformations(self, s: Statement, element: int, ks) -> None:
        keyword = self.check_element(s, element)
        nd = self.n_deformations(element)
        for k in ks:
            if not 1 <= k <= nd:
                self.fail(s, f"a {keyword} has deformations 1 to {nd}, got {k}")

    def check_positions(self) -> None:
        for number, (keyword, nodes, line) in sorted(self.elements.items()):
            for node in nodes:
                if self.kinds[node] == TRANSLATIONAL and node not in self.positions:
                    raise InputFileError(f"{keyword} {number}: node {node} has no coordinates; "
                                         f"add 'X {node} x y' to the kinematics block",
                                         self.path, line)

    # --- block 2 -------------------------------------------------------------------------
    def dynamic(self, s: Statement) -> None:
        b, v = self.builder, s.values
        handler = getattr(self, f"_{s.keyword.lower()}", None)
        if handler is not None:
            handler(s)
        elif s.keyword == "GRAVITY":
            b.set_gravity(*v)
        elif s.keyword == "ERROR":
            self.positive(s, v)
            b.set_tolerances(atol=v[0], rtol=v[1])
        elif s.keyword == "ITERSTEP":
            self.positive(s, v)
            b.set_tolerances(max_iterations=v[0], tolerance=v[1] if len(v) > 1 else None)
        elif s.keyword == "TIMESTEP":
            self.positive(s, v)
            b.set_time_grid(v[0], v[1])

    def positive(self, s: Statement, values) -> None:
        for value in values:
            if not value > 0:
                self.fail(s, f"values must be positive, got {value:g}")

    def _em(self, s: Statement, formulation: str = "consistent") -> None:
        element, rho_a = s.values[0], s.values[1]
        if self.check_element(s, element) == "PLHINGE":
            self.fail(s, f"element {element} is a hinge, which has no mass; use XM on its "
                         f"rotational nodes")
        if len(s.values) > 2 and s.values[2] != 0:
            self.fail(s, "a rotary inertia per length (rhoI) is not supported for planar "
                         "elements; set it to 0 or put rotary inertia on nodes with XM")
        if rho_a < 0:
            self.fail(s, f"mass per length {rho_a:g} is negative")
        self.builder.set_mass(element, rho_a, formulation)

    def _emlump(self, s: Statement) -> None:
        self._em(s, "lumped")

    def _estiff(self, s: Statement, table=_STIFFNESS, apply=None) -> None:
        element, values = s.values[0], s.values[1:]
        keyword = self.check_element(s, element)
        names = table[keyword]
        if len(values) > len(names):
            self.fail(s, f"a {keyword} takes {len(names)} value(s) ({', '.join(names)}), got "
                         f"{len(values)}")
        if any(x < 0 for x in values):
            self.fail(s, "values must not be negative")
        (apply or self.builder.set_stiffness)(element, **dict(zip(names, values, strict=False)))

    def _edamp(self, s: Statement) -> None:
        self._estiff(s, _DAMPING, self.builder.set_damping)

    def _esig(self, s: Statement) -> None:
        element, k, sigma0 = s.values
        self.check_deformations(s, element, [k])
        self.builder.set_prestress(element, k, sigma0)

    def _xm(self, s: Statement) -> None:
        node, mass = s.values
        self.kind(s, node)
        if mass < 0:
            self.fail(s, f"mass {mass:g} is negative")
        self.builder.add_point_mass(node, mass)

    def _xf(self, s: Statement) -> None:
        node, loads = s.values[0], s.values[1:]
        want = 2 if self.kind(s, node) == TRANSLATIONAL else 1
        if len(loads) != want:
            self.fail(s, f"node {node} is {self.kinds.get(node, TRANSLATIONAL)}: give "
                         f"{'Fx Fy' if want == 2 else 'one torque M'}")
        self.builder.add_force(node, *loads)

    def _inputx(self, s: Statement) -> None:
        node, k, *law = s.values
        self.check_directions(s, node, [k])
        if ("x", node, k) not in self.inputs:
            self.fail(s, f"coordinate {k} of node {node} is not an input (INPUTX in the "
                         f"kinematics block)")
        self.builder.input_coordinate(node, k, law=Polynomial(*law))

    def _inpute(self, s: Statement) -> None:
        element, k, *law = s.values
        self.check_deformations(s, element, [k])
        if ("e", element, k) not in self.inputs:
            self.fail(s, f"deformation {k} of element {element} is not an input (INPUTE in "
                         f"the kinematics block)")
        self.builder.input_deformation(element, k, law=Polynomial(*law))

    def _startde(self, s: Statement) -> None:
        element, k, *start = s.values
        self.check_deformations(s, element, [k])
        self.builder.set_initial(f"e{element}.{k}", *start)

    def _startdx(self, s: Statement) -> None:
        node, k, *start = s.values
        self.check_directions(s, node, [k])
        self.builder.set_initial(f"x{node}.{k}", *start)
