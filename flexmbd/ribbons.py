"""Spatial beams drawn with their cross-sections: a leaf spring as a ribbon of its width.

A beam built with a rectangular section (``ModelBuilder.set_section``) is drawn as the
band its wider side sweeps along the deflected centre line: the centre line the element
type draws (:meth:`~flexmbd.elements.base.ElementType.outline`), widened across it along
the section's wide axis. That axis is interpolated between the turned axes of the two
end nodes, so the band twists as the beam does. Geometry only; :mod:`flexmbd.plot` colours
and draws the bands.
"""

from __future__ import annotations

import numpy as np

from .elements.base import SPATIAL_ROTATIONAL
from .elements.rotations import rotate
from .model import Model
from .sections import Rectangle

#: the element keywords drawn as ribbons
RIBBON_TYPES = ("BEAM", "BEAMW")


def ribbon_beams(model: Model) -> list[int]:
    """The beams drawn as ribbons: spatial (or warping) beams with a rectangular section."""
    return [k for k, element in model.elements.items()
            if element.type.keyword in RIBBON_TYPES
            and (props := model.element_properties.get(k)) is not None
            and isinstance(props.section, Rectangle)]


def ribbon(model: Model, number: int, x: np.ndarray, e: np.ndarray,
           exaggeration: float = 1.0) -> np.ndarray:
    """The band of beam ``number`` at coordinates ``x`` ``(nx,)`` with deformations ``e``
    ``(ne,)``: its two long edges ``(2, k, 3)`` [m] along the deflected centre line."""
    element = model.elements[number]
    props = model.element_properties[number]
    section = props.section
    assert isinstance(section, Rectangle)
    xe = np.asarray(x, dtype=float)[list(element.coordinates)]
    p = np.array(element.reference)
    line = element.type.outline(xe[None], p[None], np.asarray(e)[list(element.deformations)]
                                [None], exaggeration)[0]
    # the wide side: across y (the orientation vector) when w >= t, else across z
    wide0, half = (p[4:7], section.w / 2) if section.w >= section.t else (p[7:10], section.t / 2)
    nodes = [n for n in element.nodes if model.nodes[n].kind == SPATIAL_ROTATIONAL]
    lam_p, lam_q = (xe[_columns(model, element, n)] for n in nodes)
    wide_p = np.array(rotate(list(lam_p), list(wide0)))
    wide_q = np.array(rotate(list(lam_q), list(wide0)))
    xi = np.linspace(0.0, 1.0, len(line))[:, None]
    across = (1 - xi) * wide_p + xi * wide_q
    tangent = np.gradient(line, axis=0)
    tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-300)
    across -= np.sum(across * tangent, axis=1, keepdims=True) * tangent
    across /= np.maximum(np.linalg.norm(across, axis=1, keepdims=True), 1e-300)
    return np.stack([line - half * across, line + half * across])


def _columns(model: Model, element, node: int) -> list[int]:
    """The columns of ``node``'s coordinates in the element's coordinates."""
    columns, at = [], 0
    for n in element.nodes:
        width = len(model.nodes[n].coordinates)
        if n == node:
            columns = list(range(at, at + width))
        at += width
    return columns


def quads(edges: np.ndarray) -> np.ndarray:
    """The band's quadrilaterals ``(k - 1, 4, 3)`` from its two edges ``(2, k, 3)``."""
    a, b = edges
    return np.stack([a[:-1], a[1:], b[1:], b[:-1]], axis=1)
