"""Results of analyses over a time grid, with SPACAR-style column names.

Columns: ``t``; coordinates ``x<node>.<k>``; deformations ``e<elem>.<k>``; first
and second time derivatives with prefixes ``xd``, ``xdd``, ``ed``, ``edd``.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, TypeVar

import numpy as np

from . import checks, orientation
from .elements.base import SPATIAL_ROTATIONAL
from .errors import (
    ArgumentError,
    ColumnError,
    LabelError,
    OptionalDependencyError,
    OutputError,
    SimulationError,
)
from .model import Model
from .model.naming import suggestion
from .plot import plot_columns
from .summary import Columns, clip

_COLUMN = re.compile(r"^(xdd|xd|x|edd|ed|e)(\d+)(?:\.(\d+))?$")


@dataclass(eq=False)
class KinematicResult:
    """Positions, velocities and accelerations over time.

    Attributes:
        model: the analysed model.
        t: output times [s], shape ``(nt,)``.
        x, xd, xdd: coordinates and their first and second time derivatives,
            shape ``(nt, nx)`` [m, rad, per s, per s^2].
        e, ed, edd: deformations and their derivatives, shape ``(nt, ne)``.
            Rates and accelerations are ``None`` where a simulation did not record
            them (``simulate(..., outputs="positions")``).
        success: ``False`` when the run stopped early; the arrays then hold the
            points computed before the failure.
        message: what happened, one line.
        error: the exception that stopped the run, if any.
    """

    model: Model
    t: np.ndarray
    x: np.ndarray
    xd: np.ndarray | None = None
    xdd: np.ndarray | None = None
    e: np.ndarray | None = None
    ed: np.ndarray | None = None
    edd: np.ndarray | None = None
    success: bool = True
    message: str = "completed"
    error: SimulationError | None = None

    def __repr__(self) -> str:
        """A few lines: the run's size, span and status, its columns and how to get them
        (never the arrays: a 201-point run printed 64 kB)."""
        span = (f"{len(self.t)} point{'s' if len(self.t) != 1 else ''}" +
                (f", t = {self.t[0]:.6g} to {self.t[-1]:.6g} s" if len(self.t) else ""))
        return clip(self._headline(span) + "\n  columns: " + self._column_groups() +
                    "\n  one: res['x3.1'] (an array over the rows); all: res.columns(); "
                    "the model: res.model")

    __str__ = __repr__

    def _headline(self, span: str) -> str:
        status = "completed" if self.success else f"stopped early: {self.message}"
        return (f"{type(self).__name__} of model {self.model.name!r}: {span}; "
                f"{status}")

    def _column_groups(self) -> str:
        """``"t, x (9), xd (9), ..."``: the recorded groups of columns, with their sizes."""
        groups = ["t"]
        for prefix, labels in (("x", self.model.coordinate_labels),
                               ("e", self.model.deformation_labels)):
            for suffix in ("", "d", "dd"):
                if getattr(self, prefix + suffix) is not None:
                    groups.append(f"{prefix + suffix} ({len(labels)})")
        return ", ".join(groups + self._more_groups())

    def _more_groups(self) -> list[str]:
        return []

    def __getitem__(self, name: str) -> np.ndarray:
        """One column, shape ``(nt,)``, by name: ``"t"``, ``"x3.2"``, ``"xd2.1"``, ``"edd1.1"``."""
        if name == "t":
            return self.t
        match = _COLUMN.match(name.strip()) if isinstance(name, str) else None
        if not match:
            raise self._unknown(name, "is not a result column")
        prefix, number, k = match.group(1), match.group(2), match.group(3) or "1"
        try:
            if prefix.startswith("x"):
                index = self.model._coordinate_index(f"x{number}.{k}")
            else:
                index = self.model._deformation_index(f"e{number}.{k}")
        except LabelError as error:
            raise self._unknown(name, f"is not a result column: {error}") from None
        return self._recorded(prefix, name)[:, index]

    def _unknown(self, name, what: str) -> ColumnError:
        """A column that names nothing, with the closest columns and the naming scheme."""
        tail = suggestion(str(name), list(self.columns()), self.model.directions)
        return ColumnError(f"{name!r} {what}{tail}")

    def _recorded(self, attribute: str, name: str) -> np.ndarray:
        values = getattr(self, attribute)
        if values is None:
            raise ColumnError(f"{name!r} was not recorded: simulate(..., outputs='all') "
                           f"records every column")
        return values

    def columns(self) -> dict[str, np.ndarray]:
        """All columns by name, in the order ``t, x, xd, xdd, e, ed, edd``."""
        out = Columns({"t": self.t})
        for prefix, labels in (("x", self.model.coordinate_labels),
                               ("e", self.model.deformation_labels)):
            for suffix in ("", "d", "dd"):
                values = getattr(self, prefix + suffix)
                for j, label in enumerate(labels if values is not None else ()):
                    out[prefix + suffix + label[1:]] = values[:, j]
        return out

    # --- orientations of spatial rotational nodes ------------------------------------------
    def euler_parameters(self, node: int, derivative: int = 0) -> np.ndarray:
        """``lam`` of spatial rotational node ``node`` ``(nt, 4)`` (``derivative`` 1 and 2:
        its rates and accelerations)."""
        kind = self.model.nodes[node].kind if node in self.model.nodes else None
        if kind != SPATIAL_ROTATIONAL:
            raise ArgumentError("node", f"{node!r} is not a spatial rotational node of the "
                                        f"model")
        columns = {0: "x", 1: "xd", 2: "xdd"}
        if derivative not in columns or isinstance(derivative, bool):
            raise ArgumentError("derivative", f"must be 0, 1 or 2, got {derivative!r}")
        values = self._recorded(columns[derivative], f"x{node}")
        return values[:, list(self.model.nodes[node].coordinates)]

    def rotation_matrix(self, node: int) -> np.ndarray:
        """``R`` of a spatial rotational node ``(nt, 3, 3)`` (:func:`flexmbd.rotation_matrix`)."""
        return orientation.rotation_matrix(self.euler_parameters(node))

    def axis_angle(self, node: int) -> tuple[np.ndarray, np.ndarray]:
        """Axis ``(nt, 3)`` and angle ``(nt,)`` [rad] of a spatial rotational node
        (:func:`flexmbd.axis_angle`)."""
        return orientation.axis_angle(self.euler_parameters(node))

    def angular_velocity(self, node: int, frame: Literal["global", "body"] = "global"
                         ) -> np.ndarray:
        """``omega`` (global) or ``omega'`` (body frame) of a spatial rotational node
        ``(nt, 3)`` [rad/s]."""
        return orientation.angular_velocity(self.euler_parameters(node),
                                            self.euler_parameters(node, 1), frame)

    def angular_acceleration(self, node: int, frame: Literal["global", "body"] = "global"
                             ) -> np.ndarray:
        """``alpha`` (global) or ``alpha'`` (body frame) of a spatial rotational node
        ``(nt, 3)`` [rad/s^2]."""
        return orientation.angular_velocity(self.euler_parameters(node),
                                            self.euler_parameters(node, 2), frame)

    def to_csv(self, path: str | Path) -> Path:
        """Write all columns to a CSV file with a header row; returns the path."""
        return write_csv(path, self.columns())

    def to_npz(self, path: str | Path) -> Path:
        """Write all columns to a compressed NumPy archive: one array per column name
        (``np.load(path)["x5.1"]``) and ``columns``, the names in order."""
        cols: dict[str, Any] = {"columns": np.array(list(self.columns())), **self.columns()}
        return _writing(path, lambda p: np.savez_compressed(p, **cols))

    def to_hdf5(self, path: str | Path) -> Path:
        """Write all columns as datasets of an HDF5 file (needs h5py: the ``hdf5`` extra)."""
        try:
            import h5py
        except ImportError:
            raise OptionalDependencyError("writing .h5 needs h5py: pip install "
                                          "'flexmbd[hdf5]' (or write .csv or .npz)") from None

        def write(p):
            with h5py.File(p, "w") as f:
                f.attrs["model"] = self.model.name
                f.attrs["columns"] = list(self.columns())
                for name, values in self.columns().items():
                    f.create_dataset(name, data=values)
        return _writing(path, write)

    def to_pandas(self):
        """All columns as a ``pandas.DataFrame`` (needs pandas)."""
        try:
            import pandas
        except ImportError:
            raise OptionalDependencyError("to_pandas needs pandas: pip install pandas") from None
        return pandas.DataFrame(self.columns())

    def save(self, path: str | Path) -> Path:
        """Write the columns in the format of the file name: ``.csv``, ``.npz``, ``.h5``."""
        writers = {".csv": self.to_csv, ".npz": self.to_npz, ".h5": self.to_hdf5,
                   ".hdf5": self.to_hdf5}
        suffix = Path(path).suffix.lower()
        if suffix not in writers:
            raise OutputError(f"cannot write results as {Path(path).name!r}: use .csv, .npz "
                              f"or .h5" + (" (SPACAR's .sbd: flexmbd.write_sbd(path, result))"
                                           if suffix == ".sbd" else ""))
        return writers[suffix](path)

    def plot(self, columns: list[str], against: str = "t", **options):
        """Plot columns against time or another column (see :func:`flexmbd.plot.plot_columns`)."""
        return plot_columns(self, columns, against, **options)

    def raise_for_status(self) -> None:
        """Raise the error that stopped the run, if any."""
        if self.error is not None:
            raise self.error


@dataclass(eq=False)
class SimulationResult(KinematicResult):
    """A forward simulation or inverse-dynamics run: kinematics plus dynamics.

    It has the attributes of :class:`KinematicResult` and these.

    Attributes:
        q, qd, qdd: generalized coordinates ``[x(m); e(m)]`` and their derivatives
            ``(nt, nq)``, labelled by ``model.q_labels``.
        sigma: generalized stresses ``(nt, ne)`` [N, N m]: the elastic law on dynamic
            and released deformations; with reactions, also constraint and actuator
            stresses on rigid and input deformations.
        reactions: loads of supports (fixed coordinates) and drives (input
            coordinates) ``(nt, nx)`` [N, N m], zero elsewhere; ``None`` when not computed.
            On a spatial rotational node the entries of ``lam1..lam3`` (``f<n>.2`` to
            ``f<n>.4``) hold the global moment ``(Mx, My, Mz)`` (``1/2 E(lam) f_lam``) and
            ``lam0``'s is zero, as loads are given.
        driving: generalized driving forces ``tau = Mbar qddot - g`` on every entry
            of ``q`` ``(nt, nq)`` [N, N m]: what the drives of the prescribed entries
            supply; zero (to solver accuracy) on freely moving dynamic entries.
        stats: solver counters (``nfev``, ``njev``, ``nlu``, ``nsteps``) and the method.
        applied_forces: the function ``forces(t, x, xdot)`` the run applied besides the
            model's constant loads (``None``: none), kept so that :func:`~flexmbd.energy`
            counts its work.
    """

    q: np.ndarray = None  # type: ignore[assignment]
    qd: np.ndarray = None  # type: ignore[assignment]
    qdd: np.ndarray = None  # type: ignore[assignment]
    sigma: np.ndarray = None  # type: ignore[assignment]
    reactions: np.ndarray | None = None
    driving: np.ndarray | None = None
    stats: dict = field(default_factory=dict)
    applied_forces: Callable | None = field(default=None, repr=False)

    __repr__ = KinematicResult.__repr__
    __str__ = KinematicResult.__repr__

    @property
    def sig(self) -> np.ndarray:
        """:attr:`sigma` under its columns' prefix (``res["sig2.1"]`` is a column of it)."""
        return self.sigma

    @property
    def f(self) -> np.ndarray | None:
        """:attr:`reactions` under its columns' prefix (``res["f1.2"]``)."""
        return self.reactions

    def _more_groups(self) -> list[str]:
        groups = [f"sig ({self.model.n_deformations})"] if self.sigma is not None else []
        if self.reactions is not None:
            count = len(self.model.fixed) + len(self.model.input_coordinates)
            groups.append(f"f ({count}: the loads of supports and drives)")
        return groups

    def __getitem__(self, name: str) -> np.ndarray:
        """As :meth:`KinematicResult.__getitem__`, plus ``sig<elem>.<k>`` and ``f<node>.<k>``."""
        stripped = name.strip() if isinstance(name, str) else ""
        if stripped.startswith("sig") and not _COLUMN.match("e" + stripped[3:]):
            raise self._unknown(name, "is not a result column")
        try:
            if stripped.startswith("sig"):
                index = self.model._deformation_index("e" + stripped[3:])
                return self._recorded("sigma", name)[:, index]
            if stripped.startswith("f") and _COLUMN.match("x" + stripped[1:]):
                if self.reactions is None:   # a reaction column of a run that kept none
                    self.model._coordinate_index("x" + stripped[1:])   # names a bad label
                    raise ColumnError(f"{name!r} is a reaction (the load of a support or "
                                      f"drive), which this run did not compute: run "
                                      f"simulate(..., with_reactions=True) to get the f.. "
                                      f"columns (inverse_dynamics keeps them by default)")
                return self.reactions[:, self.model._coordinate_index("x" + stripped[1:])]
        except ColumnError:
            raise
        except LabelError as error:
            raise self._unknown(name, f"is not a result column: {error}") from None
        return super().__getitem__(name)

    def columns(self) -> dict[str, np.ndarray]:
        """All columns: those of :class:`KinematicResult`, stresses ``sig..`` and, when
        computed, the loads ``f..`` on fixed and input coordinates."""
        out = super().columns()
        for j, label in enumerate(self.model.deformation_labels if self.sigma is not None
                                  else ()):
            out["sig" + label[1:]] = self.sigma[:, j]
        if self.reactions is not None:
            model = self.model
            for i in sorted(np.concatenate([model.fixed, model.input_coordinates])):
                out["f" + self.model.coordinate_labels[i][1:]] = self.reactions[:, i]
        return out


def write_csv(path: str | Path, columns: dict[str, np.ndarray]) -> Path:
    """Write equally long columns ``{name: values}`` as CSV with a header row; every number
    as ``"%.17g"`` writes it, which reads back to the same double. Returns the path."""
    from .engine import write_rows

    def write(p: Path) -> None:
        with open(p, "wb") as file:
            file.write((",".join(columns) + "\n").encode())
            file.flush()  # the core writes the rows to the file itself, after the header
            write_rows(file.fileno(), list(columns.values()))
    return _writing(path, write)


def check_times(times) -> np.ndarray:
    """Output times as a float array ``(nt,)``; they must be finite and increase.

    Raises:
        ArgumentError: not one-dimensional, empty, non-finite or not strictly increasing.
    """
    return checks.time_grid(times)


def _writing(path: str | Path, write) -> Path:
    """Run ``write(path)``; a file that cannot be written is an :class:`OutputError`."""
    path = Path(path)
    try:
        write(path)
    except OSError as error:
        raise OutputError(f"cannot write {path}: {error.strerror or error}") from None
    return path


def first_rows(arrays: Mapping[str, np.ndarray], done: int) -> dict[str, Any]:
    """The first ``done`` rows of a run's output arrays ``{name: (n, size)}``, by name: the
    arrays of a result of the rows reached (views, no copy)."""
    return {name: values[:done] for name, values in arrays.items()}


#: a result of any kind (kinematic, simulation, static), given back as it came
Result = TypeVar("Result", bound="KinematicResult")


def conclude(result: Result, error: BaseException | None, on_failure: str,
             completed: str) -> Result:
    """Finish a run: on failure raise ``error`` with ``result`` as its partial result
    (``on_failure="raise"``) or return ``result`` with ``success=False``. An exception
    that is not a :class:`SimulationError` (raised by a user's law or load, or an
    interrupt) is raised in either case, with the partial result attached."""
    check_on_failure(on_failure)
    if error is None:
        result.message = completed
        return result
    if not isinstance(error, SimulationError):
        result.success, result.message = False, f"stopped by {type(error).__name__}: {error}"
        error.partial_result = result  # type: ignore[attr-defined]  # a user's exception
        raise error
    result.success, result.message, result.error = False, str(error), error
    if on_failure == "raise":
        error.partial_result = result
        raise error
    return result


def check_on_failure(on_failure: str) -> None:
    """Reject a bad ``on_failure`` before a run does any work."""
    checks.choice(on_failure, "on_failure", ("raise", "return"))
