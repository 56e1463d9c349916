"""What an exercise is made of: its lettered parts, their reference answers and the
typical wrong answers the checker recognises.

A :class:`Part` is one function the student writes. Besides its name, arguments and
what it returns (for ``flexmbd exercise list``), it carries:

* ``answer``: flexmbd's answer for given arguments, computed by the engine;
* ``cases``: the arguments the checker tries, the exercise's configuration first and
  then random ones drawn from a generator;
* ``mistakes``: typical wrong answers, each a function of the same arguments with a
  hint; a failed answer that equals one of them gets its hint;
* ``angles``: which arguments are angles [rad], so that an answer computed as if they
  were degrees is recognised;
* ``symbolic``: optionally the names of the SymPy symbols to call the student's
  function with and the reference expression in them, so that an answer written in
  SymPy is accepted when it is algebraically equal.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ArgumentError


@dataclass(frozen=True)
class Mistake:
    """A typical wrong answer: ``wrong(*args)`` gives it, ``hint`` says what to fix."""

    hint: str
    wrong: Callable[..., Any]


@dataclass(frozen=True)
class Probe:
    """A check of a part through what it is made of: the student's function is called with
    ``args`` while the functions of the student's file named in ``substitutes`` return the
    given arrays, and must then return ``expected`` (for a part whose answer is zero at
    every consistent state, the formula shows only with other ingredients)."""

    args: tuple
    substitutes: dict
    expected: Any
    uses: str  #: what the part must be made of, for the message


@dataclass(frozen=True)
class Part:
    """One part of an exercise (see the module docstring).

    Attributes:
        letter: ``"a"``, ``"b"``, ...
        function: the name of the function the student writes.
        arguments: its arguments, as written in its signature.
        returns: what it returns, with shapes and units.
        hint: where to start, shown while the part is not done.
        answer: flexmbd's answer, ``answer(*args)``: an array, or a tuple of arrays.
        cases: ``cases(rng)``, the argument tuples to check, the exercise's first.
        mistakes: typical wrong answers recognised in a failure.
        angles: indices of the arguments that are angles [rad].
        symbolic: ``() -> (symbol names per argument, reference expression)``.
        probes: ``probes(rng)``, the :class:`Probe` checks of the part's formula.
        wrapped: ``wrapped(*args)``, the indices of the answer's (flattened) entries that are
            angles: they are compared modulo ``2 pi`` (a Newton start a turn away gives
            the same configuration).
        rtol: tolerance of the comparison, relative to the answer's largest entry.
        iterative: the part iterates (Newton-Raphson), so a nearly right answer may be a
            loose convergence tolerance.
    """

    letter: str
    function: str
    arguments: str
    returns: str
    answer: Callable[..., Any] = field(repr=False)
    cases: Callable[[Any], list[tuple]] = field(repr=False)
    hint: str = ""
    mistakes: tuple[Mistake, ...] = field(default=(), repr=False)
    angles: tuple[int, ...] = ()
    symbolic: Callable[[], tuple[Sequence, Any]] | None = field(default=None, repr=False)
    probes: Callable[[Any], list[Probe]] | None = field(default=None, repr=False)
    wrapped: Callable[..., Sequence[int]] | None = field(default=None, repr=False)
    rtol: float = 1e-7
    iterative: bool = False


@dataclass(frozen=True)
class Exercise:
    """One exercise: its number, command name, title, the model it is about and parts."""

    number: int
    name: str
    title: str
    model: str
    parts: tuple[Part, ...]
    module: str = ""  #: the solution file's stem, e.g. ``"sliding_bar"``

    def part(self, letter: str) -> Part:
        """The part with ``letter``."""
        for part in self.parts:
            if part.letter == letter:
                return part
        raise ArgumentError("part", f"exercise {self.number} has parts "
                                    f"{', '.join(p.letter for p in self.parts)}, not {letter!r}")


def lettered(*parts: dict) -> tuple[Part, ...]:
    """Parts lettered a, b, ... in order from keyword dictionaries of :class:`Part`."""
    return tuple(Part(chr(ord("a") + k), **fields) for k, fields in enumerate(parts))


def without_nodal_masses(model):
    """``model`` without its point masses and rotary inertias (for one element's mass)."""
    from ..model import Model

    fields = {name: getattr(model, name) for name, spec in Model.__dataclass_fields__.items()
              if spec.init}
    return Model(**{**fields, "nodal_masses": {}})


def negated_rows(function, rows: list[int]):
    """``function``'s answer with the sign of ``rows`` reversed: the typical wrong answer
    with the opposite sign convention of those deformations."""
    def wrong(*args):
        answer = np.array(function(*args), dtype=float)
        answer[rows] = -answer[rows]
        return answer
    return wrong


def model_answer(of, function: str):
    """A part's answer: ``function`` of :mod:`flexmbd.analysis.kinematics` (deformations, jacobian)
    on the model ``of()`` at the coordinates ``x`` a part is called with."""
    def answer(x):
        from ..analysis import kinematics

        return getattr(kinematics, function)(of(), np.asarray(x, dtype=float))
    return answer


def model_reference(of, function: str):
    """A part's SymPy reference: ``function`` of :mod:`flexmbd.analysis.symbolic` (deformations,
    jacobian, quadratic_velocity) applied to the model ``of()``, called with the model's
    coordinate symbols (and rate symbols for the quadratic velocity terms)."""
    def reference():
        from ..analysis import symbolic

        model = of()
        names = [[str(s) for s in symbolic.coordinate_symbols(model)]]
        if function == "quadratic_velocity":
            names.append([str(s) for s in symbolic.coordinate_symbols(model, "xd")])
        return names, getattr(symbolic, function)(model)
    return reference
