"""Figures and animations of results (matplotlib, imported only when used).

Plotting receives results and models and draws them; it imports no analysis and no
result class (a result's ``plot`` method forwards here). Figures are created without
pyplot, so saving never opens a window; pass ``show=True`` to the functions that offer
it for an interactive window.
"""

from __future__ import annotations

import weakref
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from .elements.base import SPATIAL_ROTATIONAL, is_translational
from .engine import workspace_of
from .errors import OptionalDependencyError, OutputError
from .model import CoordinateClass, Model
from .ribbons import quads, ribbon, ribbon_beams


class Motion(Protocol):
    """What a figure takes of a result (a :class:`~flexmbd.results.Motion` or any
    of its kind): the model, the times or load factors ``t`` ``(n,)``, coordinates ``x``
    ``(n, nx)``, their rates ``xd`` and deformations ``e`` when computed, and columns by
    name (``result["x5.1"]``). Plotting is given results; it imports none."""

    model: Model
    t: np.ndarray
    x: np.ndarray
    xd: np.ndarray | None
    e: np.ndarray | None

    def __getitem__(self, name: str) -> np.ndarray: ...

#: arrows are scaled so that the longest one over the run is this share of the model size
ARROW_SHARE = 0.3
_HERMITE_POINTS = 21


def _new_figure(window: bool, **kwargs):
    """A figure: managed by pyplot (so :func:`show` displays it) only when ``window``."""
    if window:
        import matplotlib.pyplot as plt

        return plt.figure(**kwargs)
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def element_polylines(model: Model, x: np.ndarray, exaggeration: float = 1.0,
                      e: np.ndarray | None = None) -> list[np.ndarray]:
    """Drawable shape of every element at coordinates ``x``, as its type draws it
    (:meth:`~flexmbd.elements.base.ElementType.outline`): straight lines for trusses and
    rigid beams, the deflected centre line for beams (``exaggeration`` times the
    deflection from the chord), a zigzag for springs. Each polyline has shape ``(n, 2)``
    [m]; ``e`` are the deformations at ``x`` when known."""
    x = np.asarray(x, dtype=float)
    if e is None:
        e = workspace_of(model).assembly.deformations(x)
    lines = []
    for element in model.elements.values():
        xe = x[list(element.coordinates)][None]
        lines += element.type.outline(xe, np.array([element.reference]),
                                      e[list(element.deformations)][None], exaggeration)
    return lines


class Stresses(Protocol):
    """What a figure takes of a stress history (:class:`flexmbd.StressHistory`): the
    sectioned beams and the largest von Mises stress at both ends of each, per row."""

    elements: tuple[int, ...]
    ends: np.ndarray   # (n, n_beams, 2) [Pa]


class Sections:
    """Spatial beams with rectangular sections drawn as ribbons (:mod:`flexmbd.ribbons`)
    on 3D axes, coloured by von Mises stress when a :class:`Stresses` is given (one colour
    scale over all rows, with a colour bar), else by ``styles``."""

    def __init__(self, ax, model: Model, stresses: Stresses | None = None,
                 styles: dict[int, dict] | None = None, exaggeration: float = 1.0):
        from matplotlib import colormaps
        from matplotlib.colors import Normalize
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        self.model, self.stresses, self.exaggeration = model, stresses, exaggeration
        styles = styles or {}
        self.beams = [k for k in ribbon_beams(model) if not styles.get(k, {}).get("hide")]
        self.columns = ({k: stresses.elements.index(k) for k in self.beams
                         if k in stresses.elements} if stresses is not None else {})
        top = float(np.nanmax(stresses.ends, initial=0.0)) if stresses is not None else 0.0
        self.norm = Normalize(0.0, top / 1e6 if top > 0 else 1.0)
        self.cmap = colormaps["viridis"]
        self.base = [styles.get(k, {}).get("color", "0.6") for k in self.beams]
        self.alpha = [styles.get(k, {}).get("alpha", 0.9) for k in self.beams]
        self.collection = Poly3DCollection([], edgecolor="0.25", linewidths=0.2)
        ax.add_collection3d(self.collection)
        if stresses is not None and self.columns:
            from matplotlib.cm import ScalarMappable

            mappable = ScalarMappable(self.norm, self.cmap)
            ax.figure.colorbar(mappable, ax=ax, shrink=0.7, label="von Mises stress [MPa]")

    def draw(self, x: np.ndarray, e: np.ndarray, row: int | None = None) -> None:
        """The ribbons at coordinates ``x`` and deformations ``e``, coloured by the
        stresses of ``row``."""
        from matplotlib.colors import to_rgba

        faces, colors = [], []
        for beam, base, alpha in zip(self.beams, self.base, self.alpha, strict=True):
            cells = quads(ribbon(self.model, beam, x, e, self.exaggeration))
            faces += list(cells)
            if row is not None and beam in self.columns:
                assert self.stresses is not None
                p_end, q_end = self.stresses.ends[row, self.columns[beam]] / 1e6
                xi = (np.arange(len(cells)) + 0.5) / len(cells)
                colors += [self.cmap(self.norm(v)) for v in (1 - xi) * p_end + xi * q_end]
            else:
                try:
                    colour = to_rgba(base, alpha)
                except ValueError:   # a name matplotlib does not know
                    colour = to_rgba("0.6", alpha)
                colors += [colour] * len(cells)
        self.collection.set_verts(faces)
        self.collection.set_facecolor(colors)


def plot_sections(result: Motion, row: int = -1, *, stresses: Stresses | None = None,
                  styles: dict[int, dict] | None = None, exaggeration: float = 1.0,
                  title: str | None = None, filename: str | Path | None = None,
                  window: bool = False):
    """A spatial mechanism at one row of a result (a load step, a time) with its leaf
    springs drawn as ribbons of their width, coloured by von Mises stress with a colour
    bar when ``stresses`` (:func:`flexmbd.stress_history` of the result) is given; the
    other elements as lines.

    Args:
        result: a spatial model's result that recorded its deformations.
        row: the row (default the last).
        stresses: the stresses of every row; one colour scale for all rows.
        styles: per beam ``{"color": .., "alpha": .., "hide": bool}`` without stresses.
        exaggeration: factor on the beams' deflections.

    Returns the ``matplotlib.figure.Figure``; saved to ``filename`` when given.
    """
    model = result.model
    if not model.is_spatial:
        raise ValueError("sections are drawn for spatial models; plot a planar one with "
                         "animate or plot_shapes")
    if result.e is None or not len(result.t):
        raise ValueError("the result holds no rows with deformations to draw")
    row = range(len(result.t))[row]
    _, index, _ = _translational_nodes(model)
    lo, hi, _ = _limits(result, index)
    fig = _new_figure(window, figsize=(7.5, 6))
    ax = _axes(fig, model, lo, hi)
    x, e = result.x[row], result.e[row]
    sections = Sections(ax, model, stresses, styles, exaggeration)
    sections.draw(x, e, row if stresses is not None else None)
    drawn = set(ribbon_beams(model))
    for number, element in model.elements.items():
        if number in drawn:
            continue
        for line in element.type.outline(x[list(element.coordinates)][None],
                                         np.array([element.reference]),
                                         e[list(element.deformations)][None], exaggeration):
            ax.plot(*line.T, "-", color="0.2", lw=2)
    label = "load factor" if result.xd is None or not np.any(result.xd) else "t ="
    ax.set_title(title or f"{model.name}, {label} {result.t[row]:.4g}")
    save_figure(fig, filename)
    return fig


def _translational_nodes(model: Model):
    """The translational nodes, their coordinates ``(k, 2)`` or ``(k, 3)`` and whether each
    is fixed."""
    nodes = [n for n in model.nodes.values() if is_translational(n.kind)]
    width = 3 if model.is_spatial else 2
    index = np.array([n.coordinates for n in nodes], dtype=int).reshape(-1, width)
    fixed = np.array([np.all(model.coordinate_class[list(n.coordinates)] == CoordinateClass.FIXED)
                      for n in nodes], dtype=bool)
    return nodes, index, fixed


def _limits(result: Motion, index: np.ndarray):
    pts = result.x[:, index].reshape(-1, index.shape[1])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    size = max(float(np.max(hi - lo)), result.model.characteristic_length)
    pad = 0.25 * size
    if index.shape[1] == 3:  # a cube around the middle: equal scales on the three axes
        middle = 0.5 * (lo + hi)
        return middle - 0.5 * size - pad, middle + 0.5 * size + pad, size
    return lo - pad, hi + pad, size


def _axes(fig, model: Model, lo, hi):
    """Axes with the model's limits: planar, equal scales; spatial, a 3D box."""
    spatial = model.is_spatial
    ax = fig.add_subplot(projection="3d") if spatial else fig.add_subplot()
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if spatial:
        ax.set_zlim(lo[2], hi[2])
        ax.set_zlabel("z [m]")
        ax.set_box_aspect((1, 1, 1))
    else:
        ax.set_aspect("equal")
        ax.grid(True, alpha=0.3)
    return ax


def _set_line(line, points: np.ndarray) -> None:
    """Move a planar or 3D line to ``points`` ``(k, 2)`` or ``(k, 3)``."""
    line.set_data(points[:, 0], points[:, 1])
    if points.shape[1] == 3:
        line.set_3d_properties(points[:, 2])


def animate(result: Motion, filename: str | Path | None = None, *,
            arrows: bool = True, max_frames: int = 200, fps: int = 25,
            exaggeration: float = 1.0, title: str | None = None, window: bool = False,
            sections: bool = False, stresses: Stresses | None = None):
    """Animate the mechanism with velocity (blue) and acceleration (red) arrows at the nodes.

    Args:
        result: a run over time.
        filename: ``.gif`` (Pillow, always available) or ``.mp4`` (ffmpeg from
            imageio-ffmpeg, the ``movie`` extra); ``None`` returns the animation unsaved.
        arrows: draw velocity and acceleration arrows at translational nodes,
            each scaled so that a typical frame's longest arrow is 30 % of the model size.
        max_frames: the run is subsampled to at most this many frames.
        fps: frames per second of the movie.
        exaggeration: factor on beam deflections.
        title: figure title (default: the model name).
        window: draw in a pyplot window (shown by :func:`show`) instead of off-screen.
        sections: draw a spatial model's leaf springs as ribbons of their width
            (:func:`plot_sections`).
        stresses: colour them by von Mises stress (:func:`flexmbd.stress_history` of the
            result), one colour scale for the whole run.

    Returns:
        ``matplotlib.animation.FuncAnimation`` (keep a reference while it plays); None
        when a planar movie was written straight to ``filename`` (its fixed parts drawn
        once, :func:`write_blitted`).
    """
    from matplotlib.animation import FuncAnimation

    model = result.model
    if len(result.t) == 0:
        raise ValueError("the result holds no time points to animate")
    frames = np.unique(np.linspace(0, len(result.t) - 1, min(max_frames, len(result.t)))
                       .round().astype(int))
    nodes, index, fixed = _translational_nodes(model)
    lo, hi, size = _limits(result, index)
    fig = _new_figure(window, figsize=(7, 5.5))
    ax = _axes(fig, model, lo, hi)
    ax.set_title(title or model.name)
    empty: list[list[float]] = [[]] * index.shape[1]

    ribbons = None
    if (sections or stresses is not None) and model.is_spatial and result.e is not None:
        ribbons = Sections(ax, model, stresses, exaggeration=exaggeration)
    n_lines = len(element_polylines(model, result.x[0],
                                    e=None if result.e is None else result.e[0]))
    lines = [ax.plot(*empty, "-", color="0.2", lw=2.5)[0] for _ in range(n_lines)]
    moving = ax.plot(*empty, "o", color="tab:orange", ms=6, zorder=3)[0]
    anchored = ax.plot(*empty, "s", color="k", ms=7, zorder=3)[0]
    clock = (ax.text2D if model.is_spatial else ax.text)(0.02, 0.96, "", transform=ax.transAxes,
                                                         va="top")
    quivers = []
    static = result.xd is None or not np.any(result.xd)  # load steps: t is the load factor
    arrows = arrows and not static
    if arrows and len(nodes) and model.is_spatial:
        quivers = _stick_arrows(ax, result, index, size)
    elif arrows and len(nodes):
        for name, color in (("xd", "tab:blue"), ("xdd", "tab:red")):
            vectors = getattr(result, name)[:, index]
            # a typical, not the extreme, frame sets the scale: near singular points
            # the arrows grow without bound and would hide everything else
            peak = float(np.percentile(np.linalg.norm(vectors, axis=-1).max(axis=1), 75))
            scale = peak / (ARROW_SHARE * size) if peak > 0 else 1.0
            unit = "m/s" if name == "xd" else "m/s^2"
            q = ax.quiver(np.zeros(len(nodes)), np.zeros(len(nodes)), np.zeros(len(nodes)),
                          np.zeros(len(nodes)), color=color, angles="xy", scale_units="xy",
                          scale=scale, width=0.006, zorder=4,
                          label=f"{'velocity' if name == 'xd' else 'acceleration'} "
                                f"(1 m on screen = {scale:.3g} {unit})")
            quivers.append((q, vectors))
        ax.legend(loc="upper right", fontsize=8)

    def draw(k):
        x = result.x[k]
        for line, poly in zip(lines, element_polylines(model, x, exaggeration, result.e[k]),
                              strict=True):
            _set_line(line, poly)
        if ribbons is not None:
            ribbons.draw(x, result.e[k], k if stresses is not None else None)
        pts = x[index]
        _set_line(moving, pts[~fixed])
        _set_line(anchored, pts[fixed])
        for q, vectors in quivers:
            if model.is_spatial:  # one line per node from it along its scaled vector
                for stick, start, vector in zip(q, pts, vectors[k], strict=True):
                    _set_line(stick, np.stack([start, start + vector]))
            else:
                q.set_offsets(pts)
                q.set_UVC(vectors[k, :, 0], vectors[k, :, 1])
        clock.set_text(f"load factor {result.t[k]:.4f}" if static else
                       f"t = {result.t[k]:.4f} s")
        artists = [q for q, _ in quivers if not model.is_spatial]
        return [*lines, moving, anchored, clock, *artists]

    if filename is not None and not model.is_spatial and ribbons is None and not window:
        # a planar picture's moving parts are all that draw() returns: draw the rest once
        write_blitted(fig, draw, frames, filename, fps)
        return None
    animation = FuncAnimation(fig, draw, frames=frames, interval=1000 / fps, blit=False)
    if filename is not None:
        save_animation(animation, filename, fps)
    elif window:
        _WINDOW_ANIMATIONS.add(animation)
    return animation


def _stick_arrows(ax, result: Motion, index: np.ndarray, size: float):
    """Velocity (blue) and acceleration (red) of every translational node of a spatial
    model as lines from the node, scaled as the planar arrows (matplotlib's 3D quivers
    cannot be moved): ``[(lines, scaled vectors (nt, k, 3))]``."""
    out = []
    for name, color in (("xd", "tab:blue"), ("xdd", "tab:red")):
        vectors = getattr(result, name)[:, index]
        peak = float(np.percentile(np.linalg.norm(vectors, axis=-1).max(axis=1), 75))
        scale = peak / (ARROW_SHARE * size) if peak > 0 else 1.0
        unit = "m/s" if name == "xd" else "m/s^2"
        sticks = [ax.plot([], [], [], "-", color=color, lw=1.5)[0] for _ in range(index.shape[0])]
        sticks[0].set_label(f"{'velocity' if name == 'xd' else 'acceleration'} "
                            f"(1 m on screen = {scale:.3g} {unit})")
        out.append((sticks, vectors / scale))
    ax.legend(loc="upper right", fontsize=8)
    return out


def write_blitted(fig, draw, frames, filename: str | Path, fps: int = 25) -> Path:
    """Write a movie whose moving artists are those ``draw(frame)`` returns: the rest of
    the figure (axes, ticks, legend) is drawn once, and each frame only redraws the
    moving artists over it (blitting into the off-screen canvas), several times faster
    than a full redraw per frame. ``.gif`` (Pillow) or ``.mp4`` (imageio-ffmpeg)."""
    path = Path(filename)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4", ".m4v", ".mov"):
        raise OutputError(f"cannot write a movie as {path.name!r}: use .gif or .mp4")
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)                   # an off-screen canvas that keeps pixels
    moving = draw(frames[0])
    for artist in moving:
        artist.set_animated(True)
    canvas.draw()                                   # everything that does not move
    background = canvas.copy_from_bbox(fig.bbox)
    images = []
    for k in frames:
        canvas.restore_region(background)
        for artist in draw(k):
            fig.draw_artist(artist)
        images.append(np.asarray(canvas.buffer_rgba())[..., :3].copy())
    for artist in moving:
        artist.set_animated(False)
    if suffix == ".gif":
        from PIL import Image

        # a fast palette per frame (Pillow's default quantizer is several times slower)
        first, *rest = (Image.fromarray(image).quantize(256, Image.Quantize.FASTOCTREE)
                        for image in images)
        first.save(path, save_all=True, append_images=rest, duration=1000 / fps, loop=0)
        return path
    try:
        import imageio_ffmpeg
    except ImportError:
        raise OptionalDependencyError(
            "writing .mp4 needs ffmpeg from imageio-ffmpeg: pip install 'flexmbd[movie]' "
            "(or save a .gif, which needs nothing extra)") from None
    height, width = images[0].shape[:2]
    writer = imageio_ffmpeg.write_frames(str(path), (width, height), fps=fps,
                                         codec="libx264", pix_fmt_out="yuv420p",
                                         macro_block_size=2)
    writer.send(None)
    for image in images:
        writer.send(np.ascontiguousarray(image))
    writer.close()
    return path


def save_animation(animation, filename: str | Path, fps: int = 25) -> Path:
    """Write an animation as ``.gif`` (Pillow) or ``.mp4`` (ffmpeg from imageio-ffmpeg)."""
    path = Path(filename)
    suffix = path.suffix.lower()
    writer: Any
    if suffix == ".gif":
        from matplotlib.animation import PillowWriter

        writer = PillowWriter(fps=fps)
    elif suffix in (".mp4", ".m4v", ".mov"):
        import matplotlib as mpl
        from matplotlib.animation import FFMpegWriter

        try:
            import imageio_ffmpeg
        except ImportError:
            raise OptionalDependencyError(
                "writing .mp4 needs ffmpeg from imageio-ffmpeg: pip install 'flexmbd[movie]' "
                "(or save a .gif, which needs nothing extra)"
            ) from None
        mpl.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
        writer = FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    else:
        raise OutputError(f"cannot write a movie as {path.name!r}: use .gif or .mp4")
    animation.save(str(path), writer=writer)
    return path


def plot_motion(result: Motion, columns: list[str], *, against: str = "t",
                labels: list[str] | None = None, title: str | None = None,
                filename: str | Path | None = None, window: bool = False):
    """Position, velocity and acceleration of coordinates or deformations, stacked.

    Args:
        result: a run over time.
        columns: coordinate or deformation names (``"x5.1"``, ``"e2.1"``); their
            rates ``xd..``/``ed..`` and accelerations are plotted below them.
        against: column for the horizontal axis (default time).
        labels: legend text per column.
        title: figure title (default: the model name).
        filename: save the figure there when given (``.png``, ``.pdf``, ``.svg``).
        window: draw in a pyplot window (shown by :func:`show`).

    Returns:
        The ``matplotlib.figure.Figure``.
    """
    fig = _new_figure(window, figsize=(7, 7.5))
    axes = fig.subplots(3, 1, sharex=True)
    xs = result[against]
    for k, name in enumerate(columns):
        prefix, rest = name[0], name[1:]
        label = labels[k] if labels else name
        for ax, suffix in zip(axes, ("", "d", "dd"), strict=True):
            ax.plot(xs, result[prefix + suffix + rest], label=label)
    unit = _unit(result.model, columns)
    quantities = zip(axes, ("position", "velocity", "acceleration"), ("", "/s", "/s^2"),
                     strict=True)
    for ax, what, per in quantities:
        ax.set_ylabel(f"{what} [{unit}{per}]" if unit else what)
        ax.grid(True, alpha=0.3)
    axes[0].legend()
    axes[0].set_title(title or result.model.name)
    axes[-1].set_xlabel("t [s]" if against == "t" else against)
    fig.tight_layout()
    save_figure(fig, filename)
    return fig


def _unit(model: Model, columns: list[str]) -> str:
    """``"m"`` or ``"rad"`` when all columns share it, else ``""``."""
    units = set()
    for name in columns:
        if name.startswith("x"):
            node = model.nodes[int(name[1:].split(".")[0])]
            units.add("rad" if node.kind == "rotational" else "m")
        else:
            etype = model.elements[int(name[1:].split(".")[0])].type
            units.add("rad" if etype.ends() is None else "m")
    return units.pop() if len(units) == 1 else ""


def column_unit(model: Model, name: str) -> str:
    """The unit of a result column: ``"m/s"`` for ``"xd5.1"`` of a translational node,
    ``"N m"`` for the stress ``"sig2.2"`` of a bending deformation, ``"s"`` for ``"t"``."""
    name = name.strip()
    if name == "t":
        return "s"
    if name == "load":  # the load factor of a static analysis
        return "-"
    prefix = next(p for p in ("sig", "xdd", "xd", "x", "edd", "ed", "e", "f")
                  if name.startswith(p))
    number, _, which = name[len(prefix):].partition(".")
    k = int(which or 1)
    if prefix in ("sig", "e", "ed", "edd"):
        element = model.elements[int(number)]
        base = element.type.deformation_units[k - 1]
    else:
        base = "rad" if model.nodes[int(number)].kind == "rotational" else "m"
    if prefix in ("sig", "f"):
        return "N m" if base == "rad" else "N"
    return base + {"": "", "d": "/s", "dd": "/s^2"}[prefix[1:]]


def plot_columns(result: Motion, columns: list[str], against: str = "t", *,
                 labels: list[str] | None = None, title: str | None = None,
                 filename: str | Path | None = None, ylabel: str | None = None,
                 window: bool = False):
    """Plot result columns (``"x5.1"``, ``"xd5.1"``, ...) against time or another column.
    The axes are labelled with the columns' units unless ``ylabel`` is given.

    Returns the ``matplotlib.figure.Figure``; saved to ``filename`` when given.
    """
    model = result.model
    curves = {labels[k] if labels else name: result[name] for k, name in enumerate(columns)}
    if ylabel is None:
        units = {column_unit(model, name) for name in columns}
        ylabel = (f"{', '.join(columns[:3])}{', ...' if len(columns) > 3 else ''} "
                  f"[{', '.join(sorted(units))}]")
    return plot_curves(result[against], curves,
                       xlabel=f"{against} [{column_unit(model, against)}]", ylabel=ylabel,
                       title=title or model.name, filename=filename, window=window)


def plot_curves(x: np.ndarray, curves: dict[str, np.ndarray], *, xlabel: str,
                ylabel: str | None = None, title: str | None = None,
                filename: str | Path | None = None, window: bool = False):
    """Plot named curves ``{label: y}`` (each shaped like ``x``) against ``x`` in one axes.

    Returns the ``matplotlib.figure.Figure``; saved to ``filename`` when given.
    """
    return plot_panels(x, [curves], xlabel=xlabel, ylabels=[ylabel], title=title,
                       filename=filename, window=window)


def plot_panels(x: np.ndarray, panels: list[dict[str, np.ndarray]], *, xlabel: str,
                ylabels: list[str | None] | None = None, title: str | None = None,
                filename: str | Path | None = None, window: bool = False):
    """Stacked axes sharing ``x``; panel ``k`` plots the curves ``{label: y}`` of ``panels[k]``.

    Returns the ``matplotlib.figure.Figure``; saved to ``filename`` when given.
    """
    fig = _new_figure(window, figsize=(7, 2.0 + 2.5 * len(panels)))
    axes = np.atleast_1d(fig.subplots(len(panels), 1, sharex=True))
    for ax, curves, ylabel in zip(axes, panels, ylabels or [None] * len(panels), strict=True):
        for label, y in curves.items():
            ax.plot(x, y, label=label)
        if ylabel:
            ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend()
    if title:
        axes[0].set_title(title)
    axes[-1].set_xlabel(xlabel)
    fig.tight_layout()
    save_figure(fig, filename)
    return fig


def plot_study(x: np.ndarray, histories: dict[str, np.ndarray], parameter: np.ndarray,
               metric: np.ndarray, *, xlabel: str, ylabel: str, parameter_label: str,
               metric_label: str, title: str | None = None,
               filename: str | Path | None = None, window: bool = False):
    """A parameter study side by side: the cases' histories ``{label: y}`` (each shaped
    like ``x``) on the left, one metric per case ``(n,)`` against the varied parameter
    ``(n,)`` on the right (its convergence).

    Returns the ``matplotlib.figure.Figure``; saved to ``filename`` when given.
    """
    fig = _new_figure(window, figsize=(11, 4.5))
    left, right = fig.subplots(1, 2, gridspec_kw={"width_ratios": [3, 2]})
    for label, y in histories.items():
        left.plot(x, y, label=label, linewidth=1)
    left.set_xlabel(xlabel)
    left.set_ylabel(ylabel)
    left.legend(fontsize="small", ncol=2)
    right.plot(parameter, metric, "o-")
    right.set_xlabel(parameter_label)
    right.set_ylabel(metric_label)
    for ax in (left, right):
        ax.grid(True, alpha=0.3)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    save_figure(fig, filename)
    return fig


def displaced(model: Model, x: np.ndarray, motion: np.ndarray) -> np.ndarray:
    """``x`` moved by ``motion`` ``(nx,)`` as modes and compliances report it: added to
    positions; on a spatial rotational node the global rotation ``dtheta`` in the entries
    of ``lam1..lam3`` turns its Euler parameters (``lam + 1/2 E(lam)^T dtheta``,
    normalized)."""
    from .orientation import euler_rates

    moved = np.asarray(x, dtype=float) + motion
    for node in model.nodes.values():
        if node.kind == SPATIAL_ROTATIONAL:
            at = list(node.coordinates)
            lam = x[at] + euler_rates(x[at], motion[at[1:]])
            moved[at] = lam / np.linalg.norm(lam)
    return moved


def save_figure(fig, filename: str | Path | None) -> None:
    """Save ``fig`` when ``filename`` is given; a file that cannot be written is an
    :class:`~flexmbd.errors.OutputError`, not a traceback."""
    if filename is None:
        return
    try:
        fig.savefig(filename, dpi=120)
    except (OSError, ValueError) as exc:
        raise OutputError(f"cannot save the figure as {str(filename)!r}: {exc}") from None


#: the backends that write files and show nothing
FILE_BACKENDS = frozenset({"agg", "cairo", "pdf", "pgf", "ps", "svg", "template"})
#: the animations made with ``window=True``, until they are shown or dropped
_WINDOW_ANIMATIONS: weakref.WeakSet = weakref.WeakSet()


def show() -> None:
    """Show the figures made with ``window=True``, and play their animations. Where
    matplotlib's backend only writes files (Agg, as on a machine without a screen), there
    is nothing to show: the animations are let go without a word (matplotlib would
    otherwise warn, when each is deleted, that it was never drawn)."""
    import matplotlib
    import matplotlib.pyplot as plt

    if matplotlib.get_backend().lower() not in FILE_BACKENDS:
        plt.show()
        return
    for animation in list(_WINDOW_ANIMATIONS):
        # the switch matplotlib's own Animation.save() turns: drawing is not missed
        animation._draw_was_started = True
    _WINDOW_ANIMATIONS.clear()


def plot_shapes(model: Model, x: np.ndarray, motions: np.ndarray, labels: list[str], *,
                title: str | None = None, filename: str | Path | None = None,
                window: bool = False, sections: bool = False):
    """Mode or buckled shapes drawn on the mechanism: one panel per column of ``motions``
    ``(nx, k)`` [m, rad], the configuration ``x`` grey and ``x + a motion`` on top, ``a``
    chosen so that the largest nodal translation is a tenth of the model size. With
    ``sections``, a spatial model's leaf springs are ribbons of their width in the shape.

    Returns the ``matplotlib.figure.Figure``; saved to ``filename`` when given.
    """
    motions = np.atleast_2d(np.asarray(motions, dtype=float).T).T
    count = motions.shape[1]
    fig = _new_figure(window, figsize=(4.0 * min(count, 3), 3.2 * -(-count // 3)))
    rows, columns = -(-count // 3), min(count, 3)
    projection = {"projection": "3d"} if model.is_spatial else {}
    axes = [fig.add_subplot(rows, columns, k + 1, **projection) for k in range(rows * columns)]
    _, index, _ = _translational_nodes(model)
    for ax, motion, label in zip(axes, motions.T, labels, strict=False):
        largest = np.max(np.abs(motion[index]), initial=0.0)
        scale = 0.1 * model.characteristic_length / largest if largest > 0 else 1.0
        drawn = []
        for lines, style in ((element_polylines(model, x), dict(color="0.7", lw=1)),
                             (element_polylines(model, displaced(model, x, scale * motion)),
                              dict(color="C0", lw=2))):
            for line in lines:
                ax.plot(*line.T, **style)
                drawn.append(line)
        if sections and model.is_spatial:
            moved = displaced(model, x, scale * motion)
            Sections(ax, model).draw(moved, workspace_of(model).assembly.deformations(moved))
        ax.set_title(label, fontsize=10)
        if model.is_spatial and drawn:  # equal scales: a cube around what is drawn
            points = np.concatenate(drawn)
            middle = 0.5 * (points.min(axis=0) + points.max(axis=0))
            half = 0.5 * float(np.ptp(points, axis=0).max()) or 1.0
            ax.set_xlim(middle[0] - half, middle[0] + half)
            ax.set_ylim(middle[1] - half, middle[1] + half)
            ax.set_zlim(middle[2] - half, middle[2] + half)
            ax.set_box_aspect((1, 1, 1))
        elif not model.is_spatial:
            ax.set_aspect("equal", adjustable="datalim")
        ax.axis("off")
    for ax in axes[count:]:
        ax.axis("off")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    save_figure(fig, filename)
    return fig
