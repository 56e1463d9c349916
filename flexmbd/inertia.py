"""System mass matrix, velocity-dependent inertia, applied and elastic forces.

Assembly over all elements of one type at once, scattered into global arrays
through the model's index maps (THEORY sections 5 and 6). Shapes: ``nx``
coordinates, ``ne`` deformations.
"""

from __future__ import annotations

import numpy as np

from .model import Model


def mass_matrix(model: Model, x: np.ndarray) -> np.ndarray:
    """System mass matrix ``M(x)``, shape ``(nx, nx)`` [kg, kg m, kg m^2]."""
    M = np.zeros((model.n_coordinates, model.n_coordinates))
    for g, props in zip(model.groups, model.group_properties, strict=True):
        if not np.any(props.mass):
            continue
        blocks = g.type.mass_matrix(x[g.coordinates], g.reference, props.mass, props.lumped)
        np.add.at(M, (g.coordinates[:, :, None], g.coordinates[:, None, :]), blocks)
    for number, mass in model.nodal_masses.items():
        coords = list(model.nodes[number].coordinates)
        M[coords, coords] += mass
    return M


def inertia_velocity(model: Model, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """``h(x, xdot)``, shape ``(nx,)``: the inertia force is ``M xddot + h``."""
    h = np.zeros(model.n_coordinates)
    for g, props in zip(model.groups, model.group_properties, strict=True):
        if not np.any(props.mass):
            continue
        np.add.at(h, g.coordinates, g.type.inertia_velocity(
            x[g.coordinates], xd[g.coordinates], g.reference, props.mass, props.lumped))
    return h


def applied_forces(model: Model, x: np.ndarray) -> np.ndarray:
    """Constant nodal loads and gravity, shape ``(nx,)`` [N, N m]."""
    f = np.zeros(model.n_coordinates)
    for number, load in model.nodal_forces.items():
        f[list(model.nodes[number].coordinates)] += load
    gravity = np.asarray(model.gravity, dtype=float)
    if not np.any(gravity):
        return f
    for g, props in zip(model.groups, model.group_properties, strict=True):
        if np.any(props.mass):
            np.add.at(f, g.coordinates, g.type.gravity_load(
                x[g.coordinates], g.reference, props.mass, props.lumped, gravity))
    for number, mass in model.nodal_masses.items():
        node = model.nodes[number]
        if node.kind == "translational":
            f[list(node.coordinates)] += mass * gravity
    return f


def elastic_stresses(model: Model, e: np.ndarray, ed: np.ndarray) -> np.ndarray:
    """``sigma = S e + C edot + sigma0`` of the dynamic and released deformations.

    Shape ``(ne,)``; zero on rigid and input deformations, whose stresses are
    constraint and actuator stresses (see :func:`flexmbd.dynamics.reactions`).
    """
    sigma = np.zeros(model.n_deformations)
    for g, props in zip(model.groups, model.group_properties, strict=True):
        sigma[g.deformations] = g.type.stress(e[g.deformations], ed[g.deformations],
                                              g.reference, props)
    return np.where(model.carries_elastic_stress, sigma, 0.0)
