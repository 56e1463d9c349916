"""SPACAR Light's result structure: ``res.node[j]``, ``res.step[i]``, ``res.freq``, ...

Numbers are 1-based as in MATLAB: ``res.node[j]`` is user node ``j``, ``res.step[i]`` load
step ``i`` (1..nsteps), ``res.element[j]`` user element ``j``. Per-node arrays hold one
column per load step, as SPACAR Light's do.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

import numpy as np

from ..analysis.statespace import StateSpace
from ..summary import dataclass_repr

T = TypeVar("T")


class OneBased(Sequence[T], Generic[T]):
    """A list numbered from 1, as SPACAR Light's node, element and step arrays are."""

    def __init__(self, items: Sequence[T], what: str):
        self._items, self._what = list(items), what

    def __len__(self) -> int:
        return len(self._items)

    def __getitem__(self, number):
        if isinstance(number, slice):
            raise TypeError(f"{self._what} numbers are 1-based: index one {self._what} at a "
                            f"time, or iterate")
        if isinstance(number, bool) or not isinstance(number, (int, np.integer)) or \
                not 1 <= number <= len(self._items):
            raise IndexError(f"{self._what} {number!r} does not exist: {self._what}s are "
                             f"numbered 1 to {len(self._items)}")
        return self._items[number - 1]

    def __iter__(self) -> Iterator[T]:
        return iter(self._items)

    def __repr__(self) -> str:
        return f"<{len(self._items)} {self._what}s, numbered from 1>"


@dataclass
class NodeResult:
    """A user node's results over the load steps (one column per step), or at one step
    (``res.step[i].node[j]``, vectors).

    Attributes:
        p: position ``(3, nsteps)`` [m].
        r_quat: Euler parameters ``(4, nsteps)`` [-] (``lam0`` first).
        r_axang: rotation as ``[angle; axis]`` ``(4, nsteps)`` [rad, -], SPACAR Light's order.
        r_eulzyx: ZYX Euler angles ``[z; y; x]`` ``(3, nsteps)`` [rad].
        Freac, Mreac: the load of the node's support or drive on it ``(3, nsteps)``
            [N, N m] (zero where the node is free).
        CMglob, CMloc: compliance ``(6, 6, nsteps)`` in global axes and in the node's
            turned axes [m/N, m/(N m), rad/(N m)]; NaN where a step has none.
        spa_nrs: the flexmbd (SPACAR) node numbers: translational, rotational.
        attached: False for a node no element uses (it has only ``p``).
    """

    __repr__ = dataclass_repr

    p: np.ndarray
    r_quat: np.ndarray | None = None
    r_axang: np.ndarray | None = None
    r_eulzyx: np.ndarray | None = None
    Freac: np.ndarray | None = None
    Mreac: np.ndarray | None = None
    CMglob: np.ndarray | None = None
    CMloc: np.ndarray | None = None
    spa_nrs: tuple[int, int] = (0, 0)
    attached: bool = True

    # SPACAR Light's names before 2019, for older scripts
    @property
    def x(self) -> np.ndarray:
        """``p``, by SPACAR Light's name before 2019."""
        return self.p

    @property
    def rx_eulzyx(self) -> np.ndarray | None:
        """``r_eulzyx``, by SPACAR Light's name before 2019."""
        return self.r_eulzyx

    @property
    def rx_quat(self) -> np.ndarray | None:
        """``r_quat``, by SPACAR Light's name before 2019."""
        return self.r_quat

    def at(self, step: int) -> NodeResult:
        """The node at one load step (0-based column)."""
        def column(a):
            return None if a is None else a[..., step]
        return NodeResult(column(self.p), column(self.r_quat), column(self.r_axang),
                          column(self.r_eulzyx), column(self.Freac), column(self.Mreac),
                          column(self.CMglob), column(self.CMloc), self.spa_nrs, self.attached)


@dataclass
class ElementResult:
    """A user element's results.

    Attributes:
        spa_nrs: its beams' flexmbd (SPACAR) element numbers.
        L0: the beams' undeformed lengths [m].
        e: deformations per beam ``(nbeams, 6, nsteps)`` [m, rad].
        stressmax: the largest von Mises stress over its beams per step ``(nsteps,)`` [Pa]
            (with ``opt.stressperelement``; None otherwise or without a section).
        Ri: the initial orientation of its first beam ``(3, 3)``, columns ``ex0, ey0,
            ez0`` (SPACAR Light's ``element(i).Ri``).
    """

    __repr__ = dataclass_repr

    spa_nrs: tuple[int, ...]
    L0: np.ndarray
    e: np.ndarray
    stressmax: np.ndarray | None = None
    Ri: np.ndarray | None = None

    def at(self, step: int) -> ElementResult:
        return ElementResult(self.spa_nrs, self.L0, self.e[..., step],
                             None if self.stressmax is None else self.stressmax[..., step],
                             self.Ri)


@dataclass
class StepResult:
    """One load step: the fields of :class:`LightResult` at that step."""

    __repr__ = dataclass_repr

    node: OneBased[NodeResult]
    element: OneBased[ElementResult]
    freq: np.ndarray
    buck: np.ndarray | None
    stressmax: float
    load: float
    freqmodes: np.ndarray | None = None
    buckmodes: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class LightStateSpace(StateSpace):
    """The state-space model of :func:`flexmbd.light.run` (``opt.transfer``): a
    :class:`~flexmbd.StateSpace` with SPACAR Light's names of its inputs and outputs.

    Attributes:
        InputName: ``"force-x n3"`` per input, as SPACAR Light names them.
        OutputName: ``"displ-y n4"`` or ``"veloc-y n4"`` per output.
    """

    InputName: tuple[str, ...] = ()
    OutputName: tuple[str, ...] = ()


@dataclass
class LightResult:
    """What :func:`flexmbd.light.run` returns, read as SPACAR Light's ``out``.

    Attributes:
        node: per user node (1-based), :class:`NodeResult`.
        element: per user element (1-based), :class:`ElementResult`.
        step: per load step (1-based), :class:`StepResult`; ``res.step[i].freqmodes``
            and ``.buckmodes`` are the mass-normalized mode shapes and the buckled shapes
            over the degrees of freedom ``(ndof, k)``, as SPACAR Light gives them.
        freq: eigenfrequencies ``(k, nsteps)`` [Hz], lowest first: all ``ndof`` of a
            model below 120 degrees of freedom, else the 12 lowest (``opt.nmodes``).
        buck: buckling load factors ``(ndof, nsteps)`` (with ``opt.calcbuck``), smallest
            magnitude first, with their sign (negative: it buckles with the loads reversed).
        stressmax: the largest von Mises stress per step ``(nsteps,)`` [Pa] over the
            flexible elements (all with ``opt.rigidstress``).
        statespace: the state-space model (with ``opt.transfer``), inputs and outputs in
            SPACAR Light's order and names (:class:`flexmbd.StateSpace`).
        ndof: the number of dynamic degrees of freedom.
        load: the load factor of each step, 0 to 1.
        releases: the released deformations ``(beam, k)``, given or automatic.
        notes: what was read in a way worth saying, and SPACAR Light's warnings.
        model: the flexmbd model; statics: the static equilibria
            (:class:`flexmbd.StaticResult`), for anything beyond SPACAR Light's output.
        meshcheck: with ``opt.meshcheck`` (flexmbd's option), the largest relative
            change of the frequencies, the largest stress and the displacements when
            every set's ``nbeams`` is doubled, by name.
        fighandle: with ``opt.spavisual`` true, the figure of the last step
            (:meth:`plot`), as SPACAR Light's ``results.fighandle``.
    """


    node: OneBased[NodeResult]
    element: OneBased[ElementResult]
    freq: np.ndarray
    buck: np.ndarray | None
    stressmax: np.ndarray
    load: np.ndarray
    ndof: int
    releases: list[tuple[int, int]]
    notes: list[str]
    model: Any
    statics: Any
    statespace: object = None
    styles: dict = field(default_factory=dict)
    shapes: list = field(default_factory=list, repr=False)
    meshcheck: dict | None = None
    fighandle: Any = None
    step: OneBased[StepResult] = field(init=False)

    @property
    def version(self) -> str:
        """What ran, as SPACAR Light's ``out.version`` says which SPACAR Light did."""
        from .. import __version__

        return f"flexmbd {__version__} (flexmbd.light, SPACAR Light 1.38's fields)"

    def __post_init__(self):
        steps = []
        for i in range(len(self.load)):
            steps.append(StepResult(
                OneBased([n.at(i) for n in self.node], "node"),
                OneBased([e.at(i) for e in self.element], "element"),
                self.freq[:, i], None if self.buck is None else self.buck[:, i],
                float(self.stressmax[i]), float(self.load[i]),
                *(self.shapes[i].get(name) if i < len(self.shapes) else None
                  for name in ("freqmodes", "buckmodes"))))
        self.step = OneBased(steps, "step")

    def plot(self, step: int | None = None, *, stress: bool = True, exaggeration: float = 1.0,
             filename=None, window: bool = False):
        """The model at load step ``step`` (1-based, default the last), its leaf springs as
        ribbons coloured by von Mises stress (``stress``, one scale over all steps) or in
        their sets' colours, as SPACAR Light draws them. Returns the figure; saved to
        ``filename`` (.png, .pdf, .svg) when given."""
        from .. import plot

        row = len(self.load) - 1 if step is None else self._row(step)
        return plot.plot_sections(self.statics, row, stresses=self._stresses(stress),
                                  styles=self.styles, exaggeration=exaggeration,
                                  filename=filename, window=window)

    def animate(self, filename=None, *, stress: bool = True, exaggeration: float = 1.0,
                window: bool = False):
        """The load steps as a movie (``.gif``, or ``.mp4`` with the movie extra), the leaf
        springs as ribbons coloured by von Mises stress."""
        from .. import plot

        return plot.animate(self.statics, filename, sections=True,
                            stresses=self._stresses(stress), exaggeration=exaggeration,
                            window=window)

    def _row(self, step: int) -> int:
        self.step[step]   # a step that does not exist is refused by name
        return step - 1

    def _stresses(self, wanted: bool):
        from ..analysis.stresses import stress_history
        from ..ribbons import ribbon_beams

        if not wanted or not ribbon_beams(self.model):
            return None
        return stress_history(self.statics)

    def __repr__(self) -> str:
        return (f"<flexmbd.light result: {len(self.node)} nodes, {len(self.element)} "
                f"elements, {len(self.load)} load step(s), {self.ndof} degrees of freedom; "
                f"res.node[j], res.step[i], res.freq, res.stressmax>")
