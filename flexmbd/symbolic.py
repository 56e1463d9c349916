"""The symbolic path: deformation functions, Jacobians and transfer functions in SymPy.

The expressions come from the same :meth:`ElementType.deformations` definitions
from which the compiled kernels are generated (:mod:`flexmbd.codegen`), so the
symbolic and numeric paths rest on one definition of every element. Reference
lengths and angles are taken from the model and turned into exact numbers where
they are simple (``sqrt(3)`` stays ``sqrt(3)``). Needs the ``symbolic`` extra
(SymPy); imported only here.

Symbols: coordinate ``x<n>.<k>`` is the symbol ``x<n>_<k>``, its rate
``xd<n>_<k>``.
"""

from __future__ import annotations

import numpy as np

from .errors import OptionalDependencyError
from .model import Model


def _sympy():
    try:
        import sympy
    except ImportError:
        raise OptionalDependencyError(
            "the symbolic path needs SymPy: pip install 'flexmbd[symbolic]'"
        ) from None
    return sympy


def coordinate_symbols(model: Model, prefix: str = "x"):
    """One SymPy symbol per coordinate, ``x3_1`` for ``x3.1`` (``xd3_1`` with ``prefix="xd"``)."""
    sp = _sympy()
    return sp.Matrix([sp.Symbol(prefix + label[1:].replace(".", "_"), real=True)
                      for label in model.coordinate_labels])


def _exact(value: float):
    """``value`` as an exact SymPy number when one matches it to rounding, else a Float."""
    sp = _sympy()
    value = float(value)
    guess = sp.nsimplify(value, [sp.pi], tolerance=1e-15 * max(1.0, abs(value)),
                         rational=False)
    if abs(float(guess) - value) <= 4 * np.finfo(float).eps * max(1.0, abs(value)):
        return guess
    return sp.Float(value)


def deformations(model: Model):
    """``e = D(x)`` as a column Matrix of length ``ne`` in the coordinate symbols."""
    sp = _sympy()
    x = coordinate_symbols(model)
    e = [None] * model.n_deformations
    for element in model.elements.values():
        exprs = element.type.deformations([x[i] for i in element.coordinates],
                                          [_exact(v) for v in element.reference], sp)
        for i, expr in zip(element.deformations, exprs, strict=True):
            e[i] = expr
    return sp.Matrix(e)


def jacobian(model: Model):
    """``D_x`` as an ``(ne, nx)`` Matrix."""
    return deformations(model).jacobian(coordinate_symbols(model))


def quadratic_velocity(model: Model):
    """``(D_xx xdot) xdot`` as a column Matrix in the coordinate and rate symbols."""
    sp = _sympy()
    x, xd = coordinate_symbols(model), coordinate_symbols(model, "xd")
    rate = jacobian(model) * xd
    return sp.Matrix([(sp.Matrix([r]).jacobian(x) * xd)[0] for r in rate])


def first_order_transfer(model: Model, simplify: bool = True):
    """``F_q`` as an ``(nx, nq)`` Matrix in the coordinate symbols (THEORY section 4).

    Rows of ``x(o)`` are zero, rows of ``x(m)`` unit, rows of ``x(c)`` solve
    ``D_c F_c = [-D_(m) | 0; 0 | I]``. With ``simplify`` each entry goes through
    ``sympy.simplify`` (slow for large models).
    """
    sp = _sympy()
    D_x = jacobian(model)
    rows, dep = list(model.constrained), list(model.dependent)
    x_m = list(model.independent_coordinates)
    nxm, nq = len(x_m), model.n_dof
    rhs = sp.zeros(len(rows), nq)
    for r, i in enumerate(rows):
        for j, c in enumerate(x_m):
            rhs[r, j] = -D_x[i, c]
    for k in range(nq - nxm):
        rhs[len(model.rigid) + k, nxm + k] = 1
    F_c = D_x.extract(rows, dep).LUsolve(rhs) if dep else sp.zeros(0, nq)
    F_q = sp.zeros(model.n_coordinates, nq)
    for j, c in enumerate(x_m):
        F_q[c, j] = 1
    for r, c in enumerate(dep):
        for j in range(nq):
            F_q[c, j] = sp.simplify(F_c[r, j]) if simplify else F_c[r, j]
    return F_q


def deformation_transfer(model: Model, simplify: bool = True):
    """``E_q = D_x F_q`` as an ``(ne, nq)`` Matrix (zero on rigid rows once simplified)."""
    sp = _sympy()
    E_q = jacobian(model) * first_order_transfer(model, simplify)
    return E_q.applyfunc(sp.simplify) if simplify else E_q
