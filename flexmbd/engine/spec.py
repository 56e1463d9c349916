"""What crosses into the compiled core: a model's sizes and arrays, checked at the door.

:func:`~flexmbd.engine.workspace.compile_model` makes a :class:`CoreSpec`, and
``flexmbd.engine._core.Core`` takes nothing else. Every array is declared once here, in
a small typed container per concern (elements, classification, loads, reference, the
square systems), with its dtype, its length as a function of the :class:`Sizes` and, for
an index array, the range of its values. A spec checks all of them when it is made and
keeps read-only contiguous copies, so the core, which reads them at C speed without
checks, never reads past an array. The element offsets are checked against the compiled
kernels' own sizes. ``csrc/runs.c`` names the same fields; the binding refuses a spec
whose names differ from them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

Length = Callable[["Sizes", Any], int]
Range = Callable[["Sizes"], tuple[int, int]]


class SpecError(ValueError):
    """An array handed to the core does not have the length or the values it must have
    (a defect of flexmbd's compilation, never of the user's model)."""


@dataclass(frozen=True)
class Sizes:
    """The counts the core's arrays are sized by."""
    nx: int          #: coordinates
    ne: int          #: deformations
    nel: int         #: elements
    nq: int          #: entries of q: independent coordinates, then independent deformations
    nxm: int         #: independent coordinates
    nr: int          #: rows and columns of D_c
    nrigid: int      #: rigid deformations
    nfree: int       #: free coordinates (dependent and dynamic)
    nmult: int       #: multipliers (rigid and input deformations)
    nd_dyn: int      #: dynamic entries of q
    ndc: int         #: dynamic coordinates
    total_j: int     #: values of all element Jacobians
    total_b: int     #: values of all element matrices
    nfixed: int      #: fixed coordinates
    nsupported: int  #: fixed and input coordinates
    nrot: int        #: spatial rotational nodes
    ndc_map: int     #: entries of D_c from the element Jacobians
    nsd_a: int       #: entries of the saddle matrix from element matrices
    nsd_m: int       #: nodal masses on the saddle matrix's diagonal
    nsd_c: int       #: entries of the saddle matrix from the element Jacobians

    @property
    def ns(self) -> int:
        """Unknowns of the saddle-point matrix."""
        return self.nfree + self.nmult


def ints(length: Length, values: Range | None = None) -> Any:
    """An int32 array of ``length`` entries, each within ``values`` (from, to) if given."""
    return field(metadata={"dtype": np.int32, "length": length, "values": values})


def floats(length: Length) -> Any:
    """A float64 array of ``length`` entries."""
    return field(metadata={"dtype": np.float64, "length": length})


def _positions(size: str, missing: bool = False) -> Range:
    """Indices into something of ``size`` (a field of :class:`Sizes`), -1 allowed where
    ``missing``."""
    return lambda s: (-1 if missing else 0, getattr(s, size))


def _count(size: str, times: int = 1, plus: int = 0) -> Length:
    return lambda s, a: times * getattr(s, size) + plus


class _Arrays:
    """A group of the core's arrays: read-only contiguous copies of what it is given,
    checked against the sizes by :meth:`check`."""

    def __post_init__(self) -> None:
        for declared in dataclasses.fields(self):  # type: ignore[arg-type]
            array = np.array(getattr(self, declared.name), dtype=declared.metadata["dtype"])
            array = np.ascontiguousarray(array.reshape(-1))
            array.setflags(write=False)
            object.__setattr__(self, declared.name, array)

    def check(self, sizes: Sizes) -> None:
        """Raise :class:`SpecError` for an array of the wrong length or an index out of
        its range."""
        for declared in dataclasses.fields(self):  # type: ignore[arg-type]
            array = getattr(self, declared.name)
            length = int(declared.metadata["length"](sizes, self))
            if len(array) != length:
                raise SpecError(f"core spec: {declared.name} has {len(array)} entries, "
                                f"{length} expected")
            values = declared.metadata["values"] if declared.metadata["dtype"] is np.int32 \
                else None
            if values is not None and len(array):
                low, high = values(sizes)
                if array.min() < low or array.max() >= high:
                    raise SpecError(f"core spec: {declared.name} has entries outside "
                                    f"[{low}, {high})")

    def items(self) -> dict[str, np.ndarray]:
        return {f.name: getattr(self, f.name)
                for f in dataclasses.fields(self)}  # type: ignore[arg-type]


@dataclass(frozen=True)
class Elements(_Arrays):
    """Per element (in the order of their numbers): type, where its coordinates,
    deformations, reference parameters, Jacobian, matrices and elastic law are (offsets
    ``(nel + 1,)``), and its mass and elastic law."""
    etype: np.ndarray = ints(_count("nel"))
    c_off: np.ndarray = ints(_count("nel", plus=1))
    c_idx: np.ndarray = ints(lambda s, a: a.c_off[-1], _positions("nx"))
    d_off: np.ndarray = ints(_count("nel", plus=1))
    d_idx: np.ndarray = ints(lambda s, a: a.d_off[-1], _positions("ne"))
    p_off: np.ndarray = ints(_count("nel", plus=1))
    j_off: np.ndarray = ints(_count("nel", plus=1))
    b_off: np.ndarray = ints(_count("nel", plus=1))
    law_off: np.ndarray = ints(_count("nel", plus=1))
    param: np.ndarray = floats(lambda s, a: a.p_off[-1])
    emass: np.ndarray = floats(_count("nel"))           #: consistent mass [kg]
    consistent: np.ndarray = ints(_count("nel"))
    lumped_diag: np.ndarray = floats(lambda s, a: a.c_off[-1])
    S: np.ndarray = floats(lambda s, a: a.law_off[-1])  #: stiffness, nd x nd per element
    C: np.ndarray = floats(lambda s, a: a.law_off[-1])  #: damping
    elastic: np.ndarray = ints(_count("nel"))
    sigma0: np.ndarray = floats(_count("ne"))           #: pre-stress per deformation

    def check(self, sizes: Sizes, kernels: tuple[tuple[int, int, int], ...] = ()) -> None:
        """Also: the offsets follow from the compiled ``kernels``' sizes (coordinates,
        deformations, parameters per type), which size the core's element buffers."""
        super().check(sizes)
        if len(self.etype) and (self.etype.min() < 0 or self.etype.max() >= len(kernels)):
            raise SpecError(f"core spec: etype has entries outside [0, {len(kernels)})")
        nc, nd, npar = (np.array([kernels[t][k] for t in self.etype], dtype=int)
                        for k in range(3))
        expected = {"c_off": nc, "d_off": nd, "p_off": npar, "j_off": nd * nc,
                    "b_off": nc * nc, "law_off": nd * nd}
        for name, per_element in expected.items():
            if not np.array_equal(getattr(self, name),
                                  np.concatenate([[0], np.cumsum(per_element)])):
                raise SpecError(f"core spec: {name} does not follow the element types' sizes")
        if (self.j_off[-1], self.b_off[-1], self.d_off[-1]) != (
                sizes.total_j, sizes.total_b, sizes.ne):
            raise SpecError("core spec: the element offsets do not end at total_j, total_b "
                            "and ne")


@dataclass(frozen=True)
class Classification(_Arrays):
    """Which coordinates and deformations are fixed, independent, dependent, dynamic or
    inputs, and where each sits in ``q``, in ``D_c`` and among the free coordinates and
    multipliers (-1: not there)."""
    fixed: np.ndarray = ints(_count("nfixed"), _positions("nx"))
    x_fixed: np.ndarray = floats(_count("nfixed"))
    q_coord: np.ndarray = ints(_count("nxm"), _positions("nx"))
    q_def: np.ndarray = ints(lambda s, a: s.nq - s.nxm, _positions("ne"))
    q_input: np.ndarray = ints(_count("nq"))
    q_dyn: np.ndarray = ints(_count("nd_dyn"), _positions("nq"))
    rows: np.ndarray = ints(_count("nr"), _positions("ne"))
    row_of_def: np.ndarray = ints(_count("ne"), _positions("nr", missing=True))
    dep: np.ndarray = ints(_count("nr"), _positions("nx"))
    free_of: np.ndarray = ints(_count("nx"), _positions("nfree", missing=True))
    dyn_coord: np.ndarray = ints(_count("ndc"), _positions("nx"))
    dyn_def: np.ndarray = ints(lambda s, a: s.nd_dyn - s.ndc, _positions("ne"))
    supported: np.ndarray = ints(_count("nsupported"), _positions("nx"))
    elastic_def: np.ndarray = ints(_count("ne"))
    periodic: np.ndarray = ints(_count("ne"))
    rotations: np.ndarray = ints(_count("nrot", times=4), _positions("nx"))
    mult_of_def: np.ndarray = ints(_count("ne"), _positions("nmult", missing=True))


@dataclass(frozen=True)
class Loads(_Arrays):
    """Point masses and rotary inertias, constant loads with the weight of constant
    masses ``(nx,)``, and gravity ``(3,)`` (a planar model's third component zero)."""
    nodal_mass: np.ndarray = floats(_count("nx"))
    f_const: np.ndarray = floats(_count("nx"))
    gravity: np.ndarray = floats(lambda s, a: 3)


@dataclass(frozen=True)
class Reference(_Arrays):
    """The reference configuration, the scale of each coordinate in ``D_c``'s columns and
    what a change of it is measured against (the model's size, or 1 rad)."""
    x0: np.ndarray = floats(_count("nx"))
    coord_scale: np.ndarray = floats(_count("nx"))
    coord_size: np.ndarray = floats(_count("nx"))


@dataclass(frozen=True)
class SquareSystems(_Arrays):
    """Where the entries of ``D_c`` and of the saddle-point matrix come from (positions in
    the element Jacobians and matrices), their rows and columns, and the orderings that
    keep the two bands narrow."""
    dc_src: np.ndarray = ints(_count("ndc_map"), _positions("total_j"))
    dc_row: np.ndarray = ints(_count("ndc_map"), _positions("nr"))
    dc_col: np.ndarray = ints(_count("ndc_map"), _positions("nr"))
    dc_rowband: np.ndarray = ints(_count("nr"), _positions("nr"))
    dc_colband: np.ndarray = ints(_count("nr"), _positions("nr"))
    dc_colscale: np.ndarray = floats(_count("nr"))
    sd_band: np.ndarray = ints(lambda s, a: s.ns, _positions("ns"))
    sd_a_src: np.ndarray = ints(_count("nsd_a"), _positions("total_b"))
    sd_a_u: np.ndarray = ints(_count("nsd_a"), _positions("nfree"))
    sd_a_v: np.ndarray = ints(_count("nsd_a"), _positions("nfree"))
    sd_m_coord: np.ndarray = ints(_count("nsd_m"), _positions("nx"))
    sd_m_u: np.ndarray = ints(_count("nsd_m"), _positions("nfree"))
    sd_c_src: np.ndarray = ints(_count("nsd_c"), _positions("total_j"))
    sd_c_u: np.ndarray = ints(_count("nsd_c"), _positions("ns"))
    sd_c_v: np.ndarray = ints(_count("nsd_c"), _positions("nfree"))


@dataclass(frozen=True)
class CoreSpec:
    """A model as the core takes it; checked when made.

    Raises:
        SpecError: an array of the wrong length, an index out of range, or element
            offsets that do not follow the compiled kernels' sizes.
    """
    sizes: Sizes
    elements: Elements
    classification: Classification
    loads: Loads
    reference: Reference
    systems: SquareSystems
    kernels: tuple[tuple[int, int, int], ...]  #: the compiled kernels' (nc, nd, np) per type

    def __post_init__(self) -> None:
        self.elements.check(self.sizes, self.kernels)
        for group in (self.classification, self.loads, self.reference, self.systems):
            group.check(self.sizes)

    def fields(self) -> dict[str, Any]:
        """Every size and array by the name the core gives it."""
        named: dict[str, Any] = dataclasses.asdict(self.sizes)
        for group in (self.elements, self.classification, self.loads, self.reference,
                      self.systems):
            named.update(group.items())
        return named
