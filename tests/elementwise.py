"""The generated kernels evaluated one element at a time (the core's ``kernel`` entry
point): an independent path to the arrays the engine assembles by element type, which
the tests hold them against (the engine's own element-by-element ``D_x`` serves the
builder's checks of a model not yet compiled)."""

import numpy as np

from flexmbd.engine import deformations_and_jacobian, element_kernel

__all__ = ["deformations_and_jacobian", "dense_hessian", "dense_jacobian", "quadratic_velocity"]

def dense_jacobian(model, x: np.ndarray) -> np.ndarray:
    """``D_x`` ``(ne, nx)``, element by element."""
    return deformations_and_jacobian(model, x)[1]


def dense_hessian(model, x: np.ndarray) -> np.ndarray:
    """``D_xx`` ``(ne, nx, nx)``, element by element."""
    x = np.asarray(x, dtype=float)
    H = np.zeros((model.n_deformations, len(x), len(x)))
    for element in model.elements.values():
        nd, nc = len(element.deformations), len(element.coordinates)
        coords = list(element.coordinates)
        H[np.ix_(list(element.deformations), coords, coords)] = element_kernel(
            element, "hessian", x, nd * nc * nc).reshape(nd, nc, nc)
    return H


def quadratic_velocity(model, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """``(D_xx xdot) xdot`` ``(ne,)`` from the jets' kernels, element by element."""
    x, xd = np.asarray(x, dtype=float), np.asarray(xd, dtype=float)
    out = np.zeros(model.n_deformations)
    for element in model.elements.values():
        nd = len(element.deformations)
        out[list(element.deformations)] = element_kernel(element, "quadratic", x, nd, xd)
    return out
