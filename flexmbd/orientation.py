"""Orientations of spatial rotational nodes as a user reads and gives them (the spatial
theory, section 1): rotation matrices, axis and angle, angular velocities and
accelerations from Euler parameters, and Euler parameters and their rates from an axis,
an angle and an angular velocity.

Every function takes Euler parameters ``lam = (lam0, lam1, lam2, lam3)`` as an array
whose last axis has length 4 (one orientation ``(4,)`` or a history ``(nt, 4)``) and
evaluates the same formulas the element kernels are generated from
(:mod:`flexmbd.elements.rotations`).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from .elements.rotations import body_rates, global_rates, rotate
from .errors import ArgumentError

__all__ = ["angular_velocity", "axis_angle", "euler_forces", "euler_parameters",
           "euler_rates", "moment_of", "rotation_matrix"]

Frame = Literal["global", "body"]


def _lam(lam, name: str = "lam") -> np.ndarray:
    try:
        lam = np.asarray(lam, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError(name, "must be an array of Euler parameters") from None
    if lam.ndim == 0 or lam.shape[-1] != 4 or not np.all(np.isfinite(lam)):
        raise ArgumentError(name, f"must be finite Euler parameters, shape (4,) or (nt, 4), "
                                  f"got shape {lam.shape}")
    return lam


def _rates_matrix(lam: np.ndarray, frame: Frame) -> np.ndarray:
    """``E(lam)`` (global) or ``G(lam)`` (body), shape ``(..., 3, 4)``."""
    if frame not in ("global", "body"):
        raise ArgumentError("frame", f"must be 'global' or 'body', got {frame!r}")
    of = global_rates if frame == "global" else body_rates
    return np.moveaxis(np.array(of(np.moveaxis(lam, -1, 0))), (0, 1), (-2, -1))


def rotation_matrix(lam) -> np.ndarray:
    """``R(lam)``, shape ``(..., 3, 3)``: a vector fixed to the node's material frame turns
    from ``a0`` (its reference) to ``R a0``."""
    lam = _lam(lam)
    parts = np.moveaxis(lam, -1, 0)
    columns = [rotate(parts, unit) for unit in np.eye(3)]
    return np.moveaxis(np.array(columns), (0, 1), (-1, -2))


def axis_angle(lam) -> tuple[np.ndarray, np.ndarray]:
    """The rotation as a unit axis ``(..., 3)`` and an angle ``(...)`` [rad] in ``[0, pi]``
    (after flipping ``lam`` to ``lam0 >= 0``, the same rotation). At zero angle the axis
    is undefined and given as zeros."""
    lam = _lam(lam)
    lam = np.where(lam[..., :1] < 0.0, -lam, lam)
    sine = np.linalg.norm(lam[..., 1:], axis=-1)
    angle = 2.0 * np.arctan2(sine, lam[..., 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        axis = np.where(sine[..., None] > 0.0, lam[..., 1:] / sine[..., None], 0.0)
    return axis, angle


def angular_velocity(lam, lam_rate, frame: Frame = "global") -> np.ndarray:
    """``omega = 2 E(lam) lamdot`` (global) or ``omega' = 2 G(lam) lamdot`` (body)
    ``(..., 3)`` [rad/s]. With the second derivatives ``lamddot`` for ``lam_rate`` it is
    the angular acceleration [rad/s^2] (``E(lamdot) lamdot = 0``)."""
    lam, rate = _lam(lam), _lam(lam_rate, "lam_rate")
    return 2.0 * np.einsum("...ij,...j->...i", _rates_matrix(lam, frame), rate)


def euler_parameters(axis, angle: float) -> np.ndarray:
    """``lam`` ``(4,)`` of a turn by ``angle`` [rad] about ``axis`` (any length)."""
    axis = np.asarray(axis, dtype=float)
    length = float(np.linalg.norm(axis)) if axis.shape == (3,) else 0.0
    if not length > 0.0 or not np.isfinite(length):
        raise ArgumentError("axis", f"must be a non-zero vector of 3 numbers, got {axis!r}")
    half = 0.5 * float(angle)
    return np.concatenate([[np.cos(half)], np.sin(half) * axis / length])


def euler_rates(lam, omega, frame: Frame = "global") -> np.ndarray:
    """``lamdot = 1/2 E(lam)^T omega`` (global ``omega``) or ``1/2 G(lam)^T omega'`` (body)
    ``(..., 4)``: the Euler-parameter rates of a node turning at ``omega`` [rad/s], as the
    initial rates of dynamic Euler parameters take them. ``lam`` must be normalized."""
    lam = _lam(lam)
    omega = np.asarray(omega, dtype=float)
    if omega.shape[-1:] != (3,):
        raise ArgumentError("omega", f"must have 3 components, got shape {omega.shape}")
    return 0.5 * np.einsum("...ji,...j->...i", _rates_matrix(lam, frame), omega)


def euler_forces(lam, moment) -> np.ndarray:
    """``f_lam = 2 E(lam)^T M`` ``(..., 4)``: the generalized force on the Euler parameters
    of a global moment ``M`` [N m] (the form the core gives every moment load)."""
    lam = _lam(lam)
    moment = np.asarray(moment, dtype=float)
    return 2.0 * np.einsum("...ji,...j->...i", _rates_matrix(lam, "global"), moment)


def moment_of(lam, force, frame: Frame = "global") -> np.ndarray:
    """``M = 1/2 E(lam) f_lam`` (global) or ``M' = 1/2 G(lam) f_lam`` (body) ``(..., 3)``
    [N m]: the moment of a generalized force ``f_lam`` on the Euler parameters. Its
    component along ``lam`` carries no moment (``E lam = 0``)."""
    lam, force = _lam(lam), _lam(force, "force")
    return 0.5 * np.einsum("...ij,...j->...i", _rates_matrix(lam, frame), force)
