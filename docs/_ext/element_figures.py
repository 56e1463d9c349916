"""Figures of the element types for the theory page, drawn at build time from each type's
one definition: for every deformation, the element moved along the smallest change of its
coordinates that makes that deformation alone (the pseudo-inverse of its Jacobian at the
reference), beside the reference.

Written to ``docs/generated/elements/<KEYWORD>.png`` when the build starts.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from flexmbd.elements import ELEMENT_TYPES
from flexmbd.elements.base import (
    COORDINATES_PER_NODE,
    ROTATIONAL,
    SPATIAL_ROTATIONAL,
    WARPING,
    is_translational,
)

#: the types drawn (the Euler normalization is not a user's element)
DRAWN = [keyword for keyword in ELEMENT_TYPES if keyword != "EULER"]
AMPLITUDE = 0.4


def _reference(cls) -> tuple[np.ndarray, np.ndarray]:
    """Coordinates: points at (0, 0[, 0]) and (1, 0[, 0]), angles 0, Euler parameters
    (1, 0, 0, 0); reference parameters with the orientation along y, a hinge about z."""
    c0, points = [], 0
    for role in cls.roles:
        if is_translational(role.kind):
            position = [float(points), 0.0, 0.0][:COORDINATES_PER_NODE[role.kind]]
            c0 += position
            points += 1
        elif role.kind == SPATIAL_ROTATIONAL:
            c0 += [1.0, 0.0, 0.0, 0.0]
        else:
            c0 += [0.0] * COORDINATES_PER_NODE[role.kind]
    data = {}
    for name, default in cls.element_data.items():
        if name == "orientation":
            data[name] = np.array([[0.0, 1.0, 0.0]])
        elif name == "axis":
            data[name] = np.array([[0.0, 0.0, 1.0]])
        elif default is not None:
            data[name] = np.array([default], dtype=float)
    c0 = np.array(c0)
    return c0, np.asarray(cls.reference_parameters(c0[None], data)[0], dtype=float)


def _jacobian(cls, c: np.ndarray, p: np.ndarray, h: float = 1e-7) -> np.ndarray:
    def e(z):
        return np.array(cls.deformations(list(z), list(p), np), dtype=float)
    return np.stack([(e(c + h * u) - e(c - h * u)) / (2 * h) for u in np.eye(len(c))], axis=1)


def _shape(cls, c: np.ndarray, p: np.ndarray) -> list[np.ndarray]:
    """The element's drawing at ``c``: its material line (or chord), as points (k, dim)."""
    try:
        xi = np.linspace(0.0, 1.0, 30)
        return [np.stack([np.array(cls.material_point(list(c), list(p), s, np), dtype=float)
                          for s in xi])]
    except NotImplementedError:
        ends = cls.ends()
        if ends is None:
            return []
        width = cls.dimension()
        return [np.stack([c[ends[0]:ends[0] + width], c[ends[1]:ends[1] + width]])]


def _node_marks(cls, c: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """For each rotational node: where it is drawn, its turned body axis y (a short tick
    across the element, so that bending and torsion show) and its label; warping nodes
    are not drawn."""
    marks, at, points = [], 0, []
    for role in cls.roles:
        width = COORDINATES_PER_NODE[role.kind]
        if is_translational(role.kind):
            points.append(c[at:at + width])
        at += width
    at = 0
    for k, role in enumerate(cls.roles):
        width = COORDINATES_PER_NODE[role.kind]
        place = points[min(len(points) - 1, sum(is_translational(r.kind)
                                                for r in cls.roles[:k]) - 1)] \
            if points and k else (points[0] if points else np.zeros(cls.dimension()))
        if role.kind == ROTATIONAL:
            angle = c[at]
            marks.append((place, np.array([-np.sin(angle), np.cos(angle)]), role.name))
        elif role.kind == SPATIAL_ROTATIONAL:
            lam = c[at:at + 4] / np.linalg.norm(c[at:at + 4])
            l0, l1, l2, l3 = lam
            axis = np.array([2 * (l1 * l2 - l0 * l3), l0**2 - l1**2 + l2**2 - l3**2,
                             2 * (l2 * l3 + l0 * l1)])
            marks.append((place, axis, role.name))
        elif role.kind == WARPING:
            pass
        at += width
    return marks


def draw(keyword: str, path: Path) -> None:
    cls = ELEMENT_TYPES[keyword]
    c0, p = _reference(cls)
    D = _jacobian(cls, c0, p)
    nd = cls.n_deformations()
    spatial = cls.dimension() == 3
    fig = plt.figure(figsize=(max(4.5, 2.6 * nd), 2.8))
    for k in range(nd):
        ax = fig.add_subplot(1, nd, k + 1, projection="3d" if spatial else None)
        target = np.zeros(nd)
        target[k] = 1.0
        move = np.linalg.pinv(D) @ target
        for c, style in ((c0, dict(color="0.7", ls="--")), (c0 + AMPLITUDE * move,
                                                           dict(color="C0", lw=2))):
            for line in _shape(cls, c, p):
                ax.plot(*line.T, **style)
            for place, axis, _ in _node_marks(cls, c):
                tick = np.stack([place - 0.2 * axis[:len(place)],
                                 place + 0.2 * axis[:len(place)]])
                ax.plot(*tick.T, color=style["color"], lw=1.2)
        ax.set_title(f"e{k + 1}: {cls.deformation_names[k]}", fontsize=8)
        if spatial:
            ax.set_box_aspect((1, 1, 1))
            ax.set_xlim(-0.3, 1.3), ax.set_ylim(-0.8, 0.8), ax.set_zlim(-0.8, 0.8)
            ax.tick_params(labelsize=5)
        else:
            ax.set_aspect("equal")
            ax.set_xlim(-0.4, 1.4) if cls.ends() else ax.set_xlim(-0.5, 0.5)
            ax.set_ylim(-0.6, 0.6)
            ax.tick_params(labelsize=6)
    fig.suptitle(f"{keyword} ({cls.name}): the reference (dashed) and each deformation alone",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def generate(app) -> None:
    """Every figure, into ``docs/generated/elements`` (which git ignores)."""
    folder = Path(app.srcdir) / "generated" / "elements"
    folder.mkdir(parents=True, exist_ok=True)
    for keyword in DRAWN:
        draw(keyword, folder / f"{keyword}.png")


def setup(app):
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True}
