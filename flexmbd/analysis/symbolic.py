"""The symbolic path: deformation functions, Jacobians and transfer functions in SymPy.

The expressions come from the same :meth:`ElementType.deformations` definitions
from which the compiled kernels are generated (:mod:`flexmbd.engine.codegen`), so the
symbolic and numeric paths rest on one definition of every element. Reference
lengths and angles are taken from the model and turned into exact numbers where
they are simple (``sqrt(3)`` stays ``sqrt(3)``). Needs the ``symbolic`` extra
(SymPy); imported only here.

Symbols: coordinate ``x<n>.<k>`` is the symbol ``x<n>_<k>``, its rate
``xd<n>_<k>``.
"""

from __future__ import annotations

import functools

import numpy as np

from ..errors import ModelError, OptionalDependencyError
from ..model import Model


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


def _planar_only(model: Model, name: str) -> None:
    """Refuse the closed-form transfer functions of a spatial model at once: SymPy would
    work for hours on the Euler parameters' constraints."""
    if model.is_spatial:
        raise ModelError(f"symbolic.{name} solves the constraints in closed form, which is "
                         f"practical for planar models only; for the spatial model "
                         f"{model.name!r} use flexmbd.{name}(model, x) at a configuration "
                         f"(deformations, jacobian and quadratic_velocity are symbolic "
                         f"for spatial models too)")


def first_order_transfer(model: Model, simplify: bool = True):
    """``F_q`` as an ``(nx, nq)`` Matrix in the coordinate symbols (THEORY section 4).

    Rows of ``x(o)`` are zero, rows of ``x(m)`` unit, rows of ``x(c)`` solve
    ``D_c F_c = [-D_(m) | 0; 0 | I]``. With ``simplify`` each entry goes through
    ``sympy.simplify`` (slow for large models).

    Raises:
        ModelError: a spatial model, whose constraints (with the Euler parameters'
            normalization) have no closed-form solution of practical size.
    """
    _planar_only(model, "first_order_transfer")
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
    """``E_q = D_x F_q`` as an ``(ne, nq)`` Matrix (zero on rigid rows once simplified).
    Refuses spatial models (:func:`first_order_transfer`)."""
    _planar_only(model, "deformation_transfer")
    sp = _sympy()
    E_q = jacobian(model) * first_order_transfer(model, simplify)
    return E_q.applyfunc(sp.simplify) if simplify else E_q


# --- second-order transfer functions -------------------------------------------------------
def generalized_symbols(model: Model, prefix: str = ""):
    """One symbol per entry of ``q``, named after its label: ``x2_1`` (``prefix="d"``:
    ``xd2_1``, ``"dd"``: ``xdd2_1``; a deformation ``e3_2`` gives ``ed3_2``, ...)."""
    sp = _sympy()
    return sp.Matrix([sp.Symbol(label[0] + prefix + label[1:].replace(".", "_"), real=True)
                      for label in model.q_labels])


def _along_q(columns, F_q, x):
    """``d/dq_b`` of each column ``a`` of ``columns`` (functions of ``x`` only):
    ``(d columns[:, a] / dx) F_q[:, b]``, as an Array ``(rows, nq, nq)``."""
    sp = _sympy()
    rows, nq = columns.shape[0], F_q.shape[1]
    out = sp.MutableDenseNDimArray.zeros(rows, nq, nq)
    for a in range(nq):
        slope = columns[:, a].jacobian(x)
        for b in range(nq):
            column = slope * F_q[:, b]
            for r in range(rows):
                out[r, a, b] = column[r]
    return sp.ImmutableDenseNDimArray(out)


def second_order_transfer(model: Model, simplify: bool = False):
    """``F_qq`` ``(nx, nq, nq)`` and ``E_qq`` ``(ne, nq, nq)`` as SymPy Arrays in the
    coordinate symbols: the derivatives of ``F_q`` and ``E_q`` along each ``q`` (THEORY 4),
    so that ``xddot = F_q qddot + (F_qq qdot) qdot``. With ``simplify`` every entry goes
    through ``sympy.simplify``. Refuses spatial models (:func:`first_order_transfer`)."""
    _planar_only(model, "second_order_transfer")
    sp = _sympy()
    x = coordinate_symbols(model)
    F_q = first_order_transfer(model, simplify=False)
    F_qq = _along_q(F_q, F_q, x)
    E_qq = _along_q(jacobian(model) * F_q, F_q, x)
    if simplify:
        F_qq, E_qq = (a.applyfunc(sp.simplify) for a in (F_qq, E_qq))
    return F_qq, E_qq


def quadratic_accelerations(model: Model, simplify: bool = False):
    """``(F_qq qdot) qdot``, the accelerations at ``qddot = 0`` ``(nx, 1)``, in the
    coordinate symbols and the rates of :func:`generalized_symbols` (``prefix="d"``)."""
    sp = _sympy()
    F_qq, _ = second_order_transfer(model, simplify)
    qd = generalized_symbols(model, "d")
    nx, nq = model.n_coordinates, model.n_dof
    return sp.Matrix([sum(F_qq[i, a, b] * qd[a] * qd[b] for a in range(nq)
                          for b in range(nq)) for i in range(nx)])


# --- inertia and equations of motion -------------------------------------------------------
def _element_masses(model: Model, given):
    """Element mass (``rhoA l0``) by element number, exact where simple, ``given`` first."""
    given = dict(given or {})
    return {number: given.get(number, _exact(props.mass_per_length
                                             * model.elements[number].reference[0]))
            for number, props in model.element_properties.items()
            if props.mass_per_length > 0 or number in given}


@functools.lru_cache(maxsize=64)
def _consistent(model: Model, number: int):
    """Per unit mass of element ``number``: its consistent mass matrix, velocity-dependent
    inertia and gravity load in the model's coordinate, rate and gravity values
    (:func:`flexmbd.engine.codegen.consistent_inertia`), integrated once per model and element."""
    from ..engine.codegen import consistent_inertia

    sp = _sympy()
    element = model.elements[number]
    x, xd = coordinate_symbols(model), coordinate_symbols(model, "xd")
    return consistent_inertia(element.type, [x[i] for i in element.coordinates],
                              [xd[i] for i in element.coordinates],
                              [_exact(r) for r in element.reference],
                              [_exact(g) for g in model.gravity], sp)


def mass_matrix(model: Model, lumped: bool | None = None, element_masses=None,
                nodal_masses=None):
    """The system mass matrix ``M`` ``(nx, nx)`` in the coordinate symbols (THEORY 5).

    Args:
        lumped: ``True``/``False`` for every element's mass, ``None`` (default) as the
            model says (:meth:`~flexmbd.ModelBuilder.set_mass`).
        element_masses: ``{element: mass}`` [kg] overriding ``rhoA l0``, e.g. a symbol.
        nodal_masses: ``{node: mass}`` [kg, kg m^2] overriding the model's point masses.

    The consistent element matrices come from the element types' material points, the
    same integrals the compiled kernels are generated from (:mod:`flexmbd.engine.codegen`).
    """
    sp = _sympy()
    nx = model.n_coordinates
    M = sp.zeros(nx, nx)
    for number, mass in _element_masses(model, element_masses).items():
        element = model.elements[number]
        is_lumped = model.element_properties[number].lumped if lumped is None else lumped
        if is_lumped:
            diagonal = element.type.lumped_masses(np.array([element.reference]),
                                                  np.array([1.0]))[0]
            block = sp.diag(*[_exact(d) for d in diagonal])
        else:
            block = _consistent(model, number)[0]
        for a, i in enumerate(element.coordinates):
            for b, j in enumerate(element.coordinates):
                M[i, j] += mass * block[a, b]
    masses = dict(model.nodal_masses)
    masses.update(nodal_masses or {})
    for node, mass in masses.items():
        for i in model.nodes[node].coordinates:
            M[i, i] += mass if isinstance(mass, sp.Basic) else _exact(mass)
    return M


def velocity_inertia(model: Model, element_masses=None):
    """The velocity-dependent inertia ``h`` ``(nx, 1)`` (inertia force ``M xddot + h``) in
    the coordinate and rate symbols; zero for lumped masses (THEORY 5)."""
    sp = _sympy()
    h = sp.zeros(model.n_coordinates, 1)
    for number, mass in _element_masses(model, element_masses).items():
        element = model.elements[number]
        if model.element_properties[number].lumped:
            continue
        inertia = _consistent(model, number)[1]
        for a, i in enumerate(element.coordinates):
            h[i] += mass * inertia[a]
    return h


def reduced_mass_matrix(model: Model, lumped: bool | None = None, element_masses=None,
                        nodal_masses=None, simplify: bool = False):
    """``Mbar = F_q^T M F_q`` ``(nq, nq)`` in the coordinate symbols (THEORY 7)."""
    sp = _sympy()
    F_q = first_order_transfer(model, simplify=False)
    Mbar = F_q.T * mass_matrix(model, lumped, element_masses, nodal_masses) * F_q
    return Mbar.applyfunc(sp.simplify) if simplify else Mbar


def _stresses(model: Model, E_q, qd):
    """``sigma = S e + C edot + sigma0`` ``(ne, 1)`` on the deformations that carry an
    elastic stress (:attr:`Model.carries_elastic_stress`), zero elsewhere (THEORY 6)."""
    sp = _sympy()
    e, ed = deformations(model), E_q * qd
    carries = np.asarray(model.carries_elastic_stress)
    sigma = sp.zeros(model.n_deformations, 1)
    for number, props in model.element_properties.items():
        element = model.elements[number]
        kind, rows = element.type, list(element.deformations)
        S, C = kind.elastic_law(
            np.array([element.reference]),
            {v.name: np.array([props.stiffness.get(v.name, 0.0)]) for v in kind.stiffness_values},
            {v.name: np.array([props.damping.get(v.name, 0.0)]) for v in kind.damping_values})
        sigma0 = props.prestress or (0.0,) * len(rows)
        for a, i in enumerate(rows):
            if carries[i]:
                sigma[i] = _exact(sigma0[a]) + sum(
                    _exact(S[0, a, b]) * e[j] + _exact(C[0, a, b]) * ed[j]
                    for b, j in enumerate(rows) if carries[j])
    return sigma


def _applied_forces(model: Model, element_masses=None, nodal_masses=None):
    """Constant nodal loads and gravity ``f`` ``(nx, 1)`` (gravity on point masses and on
    the elements' consistent gravity load), with the masses of :func:`mass_matrix`."""
    sp = _sympy()
    f = sp.zeros(model.n_coordinates, 1)
    for node, load in model.nodal_forces.items():
        for i, value in zip(model.nodes[node].coordinates, load, strict=True):
            f[i] += _exact(value)
    g = [_exact(v) for v in model.gravity]
    if not any(model.gravity):
        return f
    masses = {**model.nodal_masses, **(nodal_masses or {})}
    for node, mass in masses.items():
        if model.nodes[node].kind == "translational":
            for i, gk in zip(model.nodes[node].coordinates, g, strict=True):
                f[i] += (mass if isinstance(mass, sp.Basic) else _exact(mass)) * gk
    for number, mass in _element_masses(model, element_masses).items():
        element = model.elements[number]
        load = _consistent(model, number)[2]
        for a, i in enumerate(element.coordinates):
            f[i] += mass * load[a]
    return f


def equations_of_motion(model: Model, lumped: bool | None = None, element_masses=None,
                        nodal_masses=None):
    """``(Mbar, rhs)`` with ``Mbar qddot = rhs`` (THEORY 7), in the coordinate symbols and
    the rates of :func:`generalized_symbols`:
    ``rhs = F_q^T (f - h - M (F_qq qdot) qdot) - E_q^T sigma``.

    ``h`` and ``sigma`` are taken at ``xdot = F_q qdot``, ``edot = E_q qdot``; the
    dependent coordinates stay symbols (substitute a solved position, or use
    :func:`numeric_function` with a Newton-Raphson solve).
    """
    sp = _sympy()
    qd = generalized_symbols(model, "d")
    F_q = first_order_transfer(model, simplify=False)
    E_q = jacobian(model) * F_q
    M = mass_matrix(model, lumped, element_masses, nodal_masses)
    rates = dict(zip(coordinate_symbols(model, "xd"), F_q * qd, strict=True))
    h = velocity_inertia(model, element_masses).xreplace(rates) if lumped is not True \
        else sp.zeros(model.n_coordinates, 1)
    forces = (_applied_forces(model, element_masses, nodal_masses) - h
              - M * quadratic_accelerations(model))
    rhs = F_q.T * forces - E_q.T * _stresses(model, E_q, qd)
    return F_q.T * M * F_q, rhs


def driving_forces(model: Model, lumped: bool | None = None, element_masses=None,
                   nodal_masses=None):
    """``tau = Mbar qddot - rhs`` ``(nq, 1)``: the generalized force each entry of ``q``
    needs for the motion ``(q, qdot, qddot)`` (inverse dynamics, THEORY 7); entry ``j`` of
    a prescribed input is its driving force or torque."""
    Mbar, rhs = equations_of_motion(model, lumped, element_masses, nodal_masses)
    return Mbar * generalized_symbols(model, "dd") - rhs


def substitute(expr, model: Model, values):
    """``expr`` with coordinates replaced: ``values`` maps labels (``"x3.1"``) or symbols
    to expressions, e.g. a closed-form position ``{"x3.1": l1*cos(phi2), ...}``."""
    x = coordinate_symbols(model)
    replace = {}
    for key, value in values.items():
        symbol = x[model.coordinate_index(key)] if isinstance(key, str) else key
        replace[symbol] = value
    return expr.xreplace(replace)


def numeric_function(arguments, expression):
    """A numpy function of ``arguments`` (symbols or lists of symbols) computing
    ``expression`` with its common subexpressions computed once (``sympy.lambdify``
    with ``cse=True``), as the course generated functions for its simulations. A Matrix
    gives an ndarray of its shape."""
    sp = _sympy()
    return sp.lambdify(arguments, expression, modules="numpy", cse=True)
