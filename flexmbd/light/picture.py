"""SPACAR Light's ``opt.showinputonly``: a numbered picture of the input, drawn before any
model is built, so that a description that does not build can be looked at too.

Drawn: the elements as lines in their sets' colours (grey: no set) with their numbers at
their middles; the nodes with their numbers, a filled square where a node is fixed in
all directions, a triangle where in some, a larger marker where it carries a mass; the
loads (``force``, ``force_initial``) as red arrows, moments as purple ones, prescribed
displacements as blue ones, each scaled to a sixth of the model's size, as SPACAR Light's
``showGeom`` scales them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import plot
from .fields import ElementSet, NodeProps, element_sets, geometry, node_props, options

__all__ = ["show_input"]

#: arrows are this share of the model's largest extent, as SPACAR Light draws them
ARROW_SHARE = 1 / 6
#: the default colour of an element without a set, and of node markers
GREY, INK = "0.55", "black"


def show_input(nodes, elements, nprops=None, eprops=None, opt=None, *,
               filename: str | Path | None = None, window: bool = False):
    """The numbered picture of a SPACAR Light description (``opt.showinputonly``).

    Args:
        nodes, elements, nprops, eprops: as :func:`flexmbd.light.run` takes them; checked
            field by field as there, but no model is built.
        opt: SPACAR Light's options, checked as :func:`~flexmbd.light.run` checks them
            (none changes the picture).
        filename: save the figure there (.png, .pdf, .svg).
        window: make it a pyplot figure (:func:`flexmbd.plot.show` shows it).

    Returns:
        The matplotlib figure (3D axes, metres).

    Raises:
        ArgumentError: a field SPACAR Light refuses, named.
    """
    notes: list[str] = []
    positions, pairs = geometry(nodes, elements, notes)
    props = node_props(nprops, len(positions))
    sets = element_sets(eprops, len(pairs), notes)
    options(opt, len(pairs), notes)
    fig = plot._new_figure(window, figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    size = float(np.ptp(positions, axis=0).max()) or 1.0
    _elements(ax, positions, pairs, {e: s for s in sets for e in s.elems}, size)
    _nodes(ax, positions, props, size)
    _arrows(ax, positions, props, size * ARROW_SHARE)
    lo, hi = positions.min(axis=0), positions.max(axis=0)
    middle, half = (lo + hi) / 2, 0.6 * size
    for set_limits, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), middle, strict=True):
        set_limits(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(f"input: {len(positions)} nodes (black numbers), {len(pairs)} elements "
                 f"(boxed)", fontsize=10)
    plot.save_figure(fig, filename)
    return fig


def _elements(ax, positions: np.ndarray, pairs: np.ndarray, owner: dict[int, ElementSet],
              size: float) -> None:
    for i, (p, q) in enumerate(pairs, 1):
        ends = positions[[p - 1, q - 1]]
        s = owner.get(i)
        color = s.color if s is not None and s.color is not None else GREY
        ax.plot(*ends.T, color=color, lw=3 if s is not None and s.flex else 1.5)
        ax.text(*ends.mean(axis=0), str(i), fontsize=8, ha="center", va="center",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": color})


def _nodes(ax, positions: np.ndarray, props: dict[int, NodeProps], size: float) -> None:
    offset = 0.03 * size
    for j, at in enumerate(positions, 1):
        p = props.get(j, NodeProps())
        held = p.fix or (p.fix_pos and p.fix_orien)
        marker = "s" if held else "^" if (p.fix_pos or p.fix_orien or p.fix_dirs) else "o"
        big = p.mass is not None or p.mominertia is not None
        ax.scatter(*at, marker=marker, s=70 if big else 25, color=INK,
                   facecolors=INK if held or big else "white", depthshade=False)
        ax.text(*(at + offset), str(j), fontsize=9, color=INK)


def _arrows(ax, positions: np.ndarray, props: dict[int, NodeProps], length: float) -> None:
    """Loads, moments and prescribed displacements, each arrow ``length`` [m] long."""
    kinds = (("force", "tab:red"), ("force_initial", "tab:red"), ("moment", "tab:purple"),
             ("moment_initial", "tab:purple"))
    for j, p in props.items():
        at = positions[j - 1]
        for name, color in kinds:
            _arrow(ax, at, getattr(p, name), length, color)
        moved = {**p.displ_initial, **p.displ}
        if moved:
            direction = np.zeros(3)
            for k, value in moved.items():
                direction[k - 1] = value
            _arrow(ax, at, direction, length, "tab:blue")


def _arrow(ax, at: np.ndarray, vector, length: float, color: str) -> None:
    if vector is None:
        return
    vector = np.asarray(vector, dtype=float)
    norm = float(np.linalg.norm(vector))
    if norm == 0.0:
        return
    ax.quiver(*at, *(vector / norm * length), color=color, arrow_length_ratio=0.25)
