"""Generate the compiled element kernels from the element definitions (needs SymPy).

For every type in :data:`flexmbd.elements.ELEMENT_TYPES` the one definition of its
deformation functions, :meth:`~flexmbd.elements.base.ElementType.deformations`,
and of its material point, :meth:`~flexmbd.elements.base.ElementType.material_point`,
are differentiated here and written as C with common subexpressions eliminated:

* ``e = D(x)`` alone, and with the Jacobian ``D_x`` (row-major ``nd x nc``);
* the quadratic velocity terms ``(D_xx xdot) xdot`` (THEORY 2), by evaluating the
  deformation functions on :class:`Jet` values (second-order forward differentiation
  along ``xdot``): the chain rule through the definition's own intermediate values keeps
  the spatial beam's kernel 15 times smaller than differentiating its composed
  expression twice;
* the Hessians ``D_xx`` (``nd x nc x nc``);
* per unit element mass (THEORY 5): the consistent mass matrix ``int N^T N dxi``,
  the velocity-dependent inertia ``int N^T (Ndot xdot) dxi`` and the gravity load
  ``int N^T g dxi``, with ``N`` the derivative of the material point.

It also writes, from :func:`~flexmbd.elements.rotations.global_rates`, the two maps
between a global moment ``M`` on a spatial rotational node and the generalized force
``f`` on its Euler parameters: ``fm_moment_load``, ``f = 2 E(lam)^T M`` (loads), and
``fm_moment_of``, ``M = 1/2 E(lam) f`` (reactions).

The output, ``flexmbd/engine/csrc/kernels.c``, is committed and compiled by ``pip install``;
it records a hash of the definitions it was made from, which the tests compare with
the definitions as they are now, and a hash of its own body, so that a hand edit of a
kernel fails the tests too. With it comes ``kernels.h``, the sizes of the largest
element, which size the core's fixed buffers (``system.c``, ``runs.c``): no hand-kept
limit can fall behind a new element type, and one too large for them is refused here.
After changing or adding an element type run::

    python -m flexmbd.engine.codegen

with SymPy :data:`SYMPY_VERSION`: another version prints the same mathematics in other
words. ``.ci/run`` regenerates the kernels with that version and fails on any
difference from the committed ones.
"""

from __future__ import annotations

import ast
import hashlib
import inspect
import sys
from pathlib import Path

from ..elements import ELEMENT_TYPES, rotations
from ..elements.base import ElementType

#: where the generated kernels go, and the sizes of the largest element
KERNELS = Path(__file__).resolve().parent / "csrc" / "kernels.c"
SIZES = KERNELS.with_suffix(".h")

#: the SymPy whose printing the committed kernels are (``.ci/run`` regenerates with it)
SYMPY_VERSION = "1.14.0"
#: the line of kernels.c that holds the hash of the text below it
BODY_MARK = "   body: "

#: the most coordinates an element may have: the core keeps an element's Hessian
#: (``nd nc nc`` values) on the stack, 256 kB at 32 coordinates and 6 deformations
MAX_COORDINATES = 32


def definitions_hash() -> str:
    """SHA-256 of what the kernels are generated from, and of nothing else: each element
    type's definitions as SymPy expressions (deformations, their quadratic velocity terms
    by jets, material point, body angular velocity, inertia tensor, sizes), the moment
    maps, and this generator's code without its docstrings. An element's drawing, its
    parsing or a comment can change without the kernels being made again."""
    import sympy as sp

    def srepr(expression) -> str:
        # the terms as SymPy stores them (its canonical order, the same in every process
        # and hash seed) rather than sorted for printing, which is 4/5 of the time
        return sp.srepr(expression, order="none")

    parts = [_code_without_docstrings(inspect.getsource(sys.modules[__name__]))]
    for cls in ELEMENT_TYPES.values():
        nc = cls.n_coordinates()
        c = list(sp.symbols(f"c0:{nc}", real=True))
        v = list(sp.symbols(f"v0:{nc}", real=True))
        p = list(sp.symbols(f"p0:{cls.reference}", real=True)) if cls.reference else []
        parts.append(repr((cls.keyword, nc, cls.n_deformations(), cls.reference,
                           cls.dimension(), cls.has_mass)))
        parts += [srepr(cls.deformations(c, p, sp)),
                  srepr(quadratic_terms(cls, c, v, p, sp))]
        rotary = cls.body_angular_velocity(c, sp) if cls.has_mass else None
        if rotary is not None:  # as derive() takes them
            parts += [srepr(rotary), srepr(cls.inertia_tensor(p))]
        elif cls.has_mass:
            parts.append(srepr(cls.material_point(c, p, sp.Symbol("xi", real=True), sp)))
    parts += [srepr(moment_load(sp)), srepr(moment_of(sp))]
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


def _code_without_docstrings(source: str) -> str:
    """The syntax tree of ``source`` with every docstring removed, as text."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) and \
                isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
            setattr(node, "body", body[1:] or [ast.Pass()])  # noqa: B010 (any node's body)
    return ast.dump(tree)


def _integrate(expr, xi, sp):
    """``int_0^1 expr dxi`` of a polynomial in ``xi``, trigonometry simplified."""
    return sp.trigsimp(sp.integrate(sp.expand(expr), (xi, 0, 1)))


def consistent_inertia(cls: type[ElementType], c: list, v: list, p: list, g: list, sp):
    """Per unit element mass, in the symbols given (THEORY 5): the consistent mass matrix
    ``int N^T N dxi`` ``(nc, nc)``, the velocity-dependent inertia ``int N^T (Ndot v) dxi``
    ``(nc, 1)`` and the gravity load ``int N^T g dxi`` ``(nc, 1)``, with ``N`` the
    derivative of the type's material point with respect to the coordinates ``c``."""
    xi = sp.Symbol("xi", real=True)
    point = sp.Matrix(cls.material_point(c, p, xi, sp))
    N = point.jacobian(c)
    Ndot = sum((N.diff(ck) * vk for ck, vk in zip(c, v, strict=True)), sp.zeros(*N.shape))
    mass = (N.T * N).applyfunc(lambda z: _integrate(z, xi, sp))
    inertia = (N.T * Ndot * sp.Matrix(v)).applyfunc(lambda z: _integrate(z, xi, sp))
    gravity = (N.T * sp.Matrix(g)).applyfunc(lambda z: _integrate(z, xi, sp))
    return mass, inertia, gravity


def rotary_inertia(cls: type[ElementType], c: list, v: list, p: list, sp):
    """For a type with a body angular velocity ``omega' = W cdot`` and inertia tensor ``J``
    (the Euler element, THEORY-SPATIAL 4): the mass ``W^T J W`` ``(nc, nc)`` and the
    velocity term ``W^T (J Wdot v + omega' x J omega')`` ``(nc, 1)``, by the principle of
    virtual work like the consistent inertia of a material point."""
    W = sp.Matrix(cls.body_angular_velocity(c, sp))
    J = sp.Matrix(cls.inertia_tensor(p))
    omega = W * sp.Matrix(v)
    w_dot_v = omega.jacobian(c) * sp.Matrix(v)
    return W.T * J * W, W.T * (J * w_dot_v + omega.cross(J * omega))


class Jet:
    """A value with its first and second derivatives along a direction, ``(a, a', a'')``
    (second-order forward differentiation). Evaluating an element's deformation
    functions on jets of its coordinates, ``(c, v, 0)``, gives the quadratic velocity
    terms ``(D_xx v) v`` as the second derivatives, by the chain rule through every
    intermediate value: the expressions keep the structure of the definition (a rotated
    frame vector is differentiated once and shared) instead of differentiating the
    composed expression twice."""

    __slots__ = ("a", "d1", "d2")

    def __init__(self, a, d1=0, d2=0):
        self.a, self.d1, self.d2 = a, d1, d2

    @staticmethod
    def of(x) -> Jet:
        return x if isinstance(x, Jet) else Jet(x)

    def __add__(self, other):
        o = Jet.of(other)
        return Jet(self.a + o.a, self.d1 + o.d1, self.d2 + o.d2)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.a, -self.d1, -self.d2)

    def __sub__(self, other):
        return self + (-Jet.of(other))

    def __rsub__(self, other):
        return Jet.of(other) + (-self)

    def __mul__(self, other):
        o = Jet.of(other)
        return Jet(self.a * o.a, self.d1 * o.a + self.a * o.d1,
                   self.d2 * o.a + 2 * self.d1 * o.d1 + self.a * o.d2)

    __rmul__ = __mul__

    def __truediv__(self, other):
        o = Jet.of(other)
        q = self.a / o.a
        q1 = (self.d1 - q * o.d1) / o.a
        return Jet(q, q1, (self.d2 - 2 * q1 * o.d1 - q * o.d2) / o.a)

    def __rtruediv__(self, other):
        return Jet.of(other) / self

    def __pow__(self, n):
        if n == 1:
            return self
        return Jet(self.a**n, n * self.a ** (n - 1) * self.d1,
                   n * self.a ** (n - 1) * self.d2 + n * (n - 1) * self.a ** (n - 2) * self.d1**2)


class JetMath:
    """The math module of the deformation functions (``m``) for :class:`Jet` arguments,
    built on SymPy's functions."""

    def __init__(self, sp):
        self.sp = sp

    def sqrt(self, x):
        x = Jet.of(x)
        r = self.sp.sqrt(x.a)
        r1 = x.d1 / (2 * r)
        return Jet(r, r1, (x.d2 - 2 * r1**2) / (2 * r))

    def sin(self, x):
        x = Jet.of(x)
        s, c = self.sp.sin(x.a), self.sp.cos(x.a)
        return Jet(s, c * x.d1, c * x.d2 - s * x.d1**2)

    def cos(self, x):
        x = Jet.of(x)
        s, c = self.sp.sin(x.a), self.sp.cos(x.a)
        return Jet(c, -s * x.d1, -s * x.d2 - c * x.d1**2)

    def atan2(self, y, x):
        y, x = Jet.of(y), Jet.of(x)
        r2 = x.a**2 + y.a**2
        num = x.a * y.d1 - y.a * x.d1
        num1 = x.a * y.d2 - y.a * x.d2
        r2_1 = 2 * (x.a * x.d1 + y.a * y.d1)
        return Jet(self.sp.atan2(y.a, x.a), num / r2, (num1 * r2 - num * r2_1) / r2**2)


def quadratic_terms(cls: type[ElementType], c: list, v: list, p: list, sp) -> list:
    """``(D_xx v) v`` of every deformation, ``(nd,)``, by :class:`Jet` arithmetic."""
    jets = [Jet(ck, vk) for ck, vk in zip(c, v, strict=True)]
    return [sp.sympify(Jet.of(e).d2) for e in cls.deformations(jets, p, JetMath(sp))]


def derive(cls: type[ElementType], sp) -> dict[str, tuple[list, list]]:
    """The kernels of one type as ``{name: (arguments, expressions)}``."""
    nc, nd = cls.n_coordinates(), cls.n_deformations()
    c = list(sp.symbols(f"c0:{nc}", real=True))
    v = list(sp.symbols(f"v0:{nc}", real=True))
    p = list(sp.symbols(f"p0:{cls.reference}", real=True)) if cls.reference else []
    e = sp.Matrix(cls.deformations(c, p, sp))
    jac = e.jacobian(c)
    quadratic = quadratic_terms(cls, c, v, p, sp)
    hessians = [sp.hessian(e[i], c) for i in range(nd)]
    kernels = {
        "deform": (["c", "p"], list(e)),
        "deform_jac": (["c", "p"], list(e) + list(jac)),
        "quadratic": (["c", "v", "p"], list(quadratic)),
        "hessian": (["c", "p"], [h[a, b] for h in hessians for a in range(nc)
                                  for b in range(nc)]),
    }
    if cls.has_mass and cls.body_angular_velocity(c, sp) is not None:
        mass, inertia = rotary_inertia(cls, c, v, p, sp)
        kernels["mass"] = (["c", "p"], list(mass))
        kernels["inertia"] = (["c", "v", "p"], list(inertia))
    elif cls.has_mass:
        g = list(sp.symbols(f"g0:{cls.dimension()}", real=True))
        mass, inertia, gravity = consistent_inertia(cls, c, v, p, g, sp)
        kernels["mass"] = (["c", "p"], list(mass))
        kernels["inertia"] = (["c", "v", "p"], list(inertia))
        kernels["gravity"] = (["c", "p", "g"], list(gravity))
        # its slope: a load that turns with the element's rotations stiffens or softens
        # it (the linearization's load stiffness, THEORY 9)
        slope = gravity.jacobian(c)
        kernels["gravity_jac"] = (["c", "p", "g"], [slope[a, b] for a in range(nc)
                                                    for b in range(nc)])
    return kernels


_SIGNATURES = {"c": "const double *c", "v": "const double *v", "p": "const double *p",
               "g": "const double *g", "m": "const double *m", "f": "const double *f"}


def _printer(sp):
    """C99 printing with small powers as products and half-integer ones with sqrt: the
    kernels' differences stay as written (expanding them would cancel digits)."""
    from sympy.printing.c import C99CodePrinter

    half = sp.Rational(1, 2)

    class Printer(C99CodePrinter):
        def _print_Pow(self, expr):
            base, exponent = expr.as_base_exp()
            b = self.parenthesize(base, 1000)
            if exponent in (2, 3):
                return "(" + "*".join([b] * int(exponent)) + ")"  # also as a divisor
            if exponent == -1:
                return f"1.0/{b}"
            if exponent == half:
                return f"sqrt({self._print(base)})"
            if exponent == -half:
                return f"1.0/sqrt({self._print(base)})"
            if exponent == 3 * half:
                return f"({b}*sqrt({self._print(base)}))"
            if exponent == -3 * half:
                return f"1.0/({b}*sqrt({self._print(base)}))"
            return super()._print_Pow(expr)

    return Printer()


def _function(name: str, arguments: list[str], expressions: list, sp,
              storage: str = "static ") -> str:
    """One C function ``void name(args, double *out)`` with common subexpressions."""
    replacements = {}
    for letter in arguments:
        for s in set().union(*(x.free_symbols for x in expressions)):
            if s.name.startswith(letter) and s.name[len(letter):].isdigit():
                replacements[s] = sp.Symbol(f"{letter}[{s.name[len(letter):]}]")
    expressions = [sp.sympify(x).xreplace(replacements) for x in expressions]
    shared, reduced = sp.cse(expressions, symbols=sp.numbered_symbols("t"))
    printer = _printer(sp)
    lines = [f"{storage}void {name}({', '.join(_SIGNATURES[a] for a in arguments)}, double *out)",
             "{"]
    lines += [f"    const double {s} = {printer.doprint(x)};" for s, x in shared]
    lines += [f"    out[{i}] = {printer.doprint(x)};" for i, x in enumerate(reduced)]
    unused = [a for a in arguments if not any(
        str(s).startswith(f"{a}[") for x in expressions for s in x.free_symbols)]
    lines[2:2] = [f"    (void){a};" for a in unused]
    return "\n".join([*lines, "}"])


def moment_load(sp) -> list:
    """``2 E(lam)^T M`` ``(4,)`` in the symbols ``c0..c3`` (``lam``) and ``m0..m2`` (the
    global moment ``M``): the generalized force of ``M`` on the Euler parameters."""
    lam, moment = sp.symbols("c0:4"), sp.symbols("m0:3")
    E = rotations.global_rates(lam)
    return [2 * sum(E[i][a] * moment[i] for i in range(3)) for a in range(4)]


def moment_of(sp) -> list:
    """``1/2 E(lam) f`` ``(3,)`` in the symbols ``c0..c3`` (``lam``) and ``f0..f3`` (a
    generalized force on the Euler parameters): its global moment."""
    lam, force = sp.symbols("c0:4"), sp.symbols("f0:4")
    E = rotations.global_rates(lam)
    return [sum(E[i][a] * force[a] for a in range(4)) / 2 for i in range(3)]


def generate() -> str:
    """The text of ``kernels.c`` for the current element definitions."""
    import sympy as sp

    parts = ["#include <math.h>", "#include <stddef.h>", '#include "core.h"', ""]
    table = []
    for cls in ELEMENT_TYPES.values():
        prefix = cls.keyword.lower()
        kernels = derive(cls, sp)
        for name, (arguments, expressions) in kernels.items():
            parts += [_function(f"{prefix}_{name}", arguments, expressions, sp), ""]
        constant = cls.has_mass and not any(
            s.name.startswith("c") for x in kernels["mass"][1] for s in sp.sympify(x).free_symbols)
        pointers = ", ".join(f"{prefix}_{k}" if k in kernels else "NULL" for k in
                             ("deform", "deform_jac", "quadratic", "hessian", "mass",
                              "inertia", "gravity", "gravity_jac"))
        table.append(f'    {{"{cls.keyword}", {cls.n_coordinates()}, {cls.n_deformations()}, '
                     f"{cls.reference}, {cls.dimension()}, {pointers}, {int(constant)}}},")
    parts += [_function("fm_moment_load", ["c", "m"], moment_load(sp), sp, storage=""), "",
              _function("fm_moment_of", ["c", "f"], moment_of(sp), sp, storage=""), ""]
    parts += ["const FmKernels FM_KERNELS[] = {", *table, "};",
              f"const int FM_N_TYPES = {len(ELEMENT_TYPES)};",
              f'const char FM_DEFINITIONS_HASH[] = "{definitions_hash()}";', ""]
    body = "\n".join(parts)
    return (f"/* Generated by flexmbd.engine.codegen from the element definitions: do not edit.\n"
            f"   Regenerate with `python -m flexmbd.engine.codegen` (SymPy {SYMPY_VERSION}).\n"
            f"   definitions: {definitions_hash()}\n"
            f"{BODY_MARK}{body_hash(body)} */\n{body}")


def body_hash(body: str) -> str:
    """SHA-256 of the text of kernels.c below its opening comment."""
    return hashlib.sha256(body.encode()).hexdigest()


def recorded_body_hash(text: str) -> tuple[str, str]:
    """The body hash kernels.c records, and the hash of its body as it is."""
    head, _, body = text.partition(" */\n")
    recorded = next((line.removeprefix(BODY_MARK) for line in head.splitlines()
                     if line.startswith(BODY_MARK)), "")
    return recorded, body_hash(body)


def sizes_header() -> str:
    """The text of ``kernels.h``: the largest coordinates, deformations, reference
    parameters and gravity components of any element type.

    Raises:
        ValueError: an element type has more than :data:`MAX_COORDINATES` coordinates, or
            more deformations than coordinates (the core's buffers of the quadratic terms
            take ``nc`` values).
    """
    types = list(ELEMENT_TYPES.values())
    for cls in types:
        nc, nd = cls.n_coordinates(), cls.n_deformations()
        if nc > MAX_COORDINATES or nd > nc:
            raise ValueError(f"element type {cls.keyword}: {nc} coordinates and {nd} "
                             f"deformations; the core takes at most {MAX_COORDINATES} "
                             f"coordinates and no more deformations than coordinates")
    largest = {"NC": max(cls.n_coordinates() for cls in types),
               "ND": max(cls.n_deformations() for cls in types),
               "NP": max([cls.reference for cls in types] + [1]),
               "NG": max(cls.dimension() for cls in types)}
    return "\n".join(
        ["/* Generated by flexmbd.engine.codegen with kernels.c: do not edit.",
         "   The sizes of the largest element type, for the core's fixed buffers. */",
         "#ifndef FLEXMBD_KERNELS_H", "#define FLEXMBD_KERNELS_H", "",
         *(f"#define FM_MAX_{name} {value}" for name, value in largest.items()),
         "", "#endif", ""])


def main() -> None:
    """Write :data:`KERNELS` and :data:`SIZES`."""
    import sympy as sp

    if sp.__version__ != SYMPY_VERSION:
        print(f"note: SymPy {sp.__version__} here; the committed kernels are SymPy "
              f"{SYMPY_VERSION}'s printing, which .ci/run checks "
              f"(pip install sympy=={SYMPY_VERSION})", file=sys.stderr)
    header = sizes_header()  # refuses an element the core cannot hold, before any work
    KERNELS.write_text(generate())
    SIZES.write_text(header)
    print(f"wrote {KERNELS} and {SIZES.name} ({len(ELEMENT_TYPES)} element types)")


if __name__ == "__main__":
    main()
