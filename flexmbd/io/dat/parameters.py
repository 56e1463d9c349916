"""A SPACAR input file with named values to vary: the model of a parameter study.

A value is named by its keyword, the leading numbers that pick its line (the element
or node, and more when that is not unique) and its position after them, joined by
colons::

    ESTIFF 2 4.2e6 12.72     ESTIFF:2:2  is EI of element 2 (12.72)
    X 5 0.45 0.0             X:5:1       is the x of node 5
    INPUTX 2 1 0.0 150.0     INPUTX:2:3  (or INPUTX:2:1:2) is the crank speed v0
    TIMESTEP 0.0838 400      TIMESTEP:1  is the end time

The varied file is the original text with those words replaced, so it is read with
every check of :func:`~flexmbd.read_dat` and its errors name the file and line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

from ...errors import ArgumentError
from .reader import DatFile, dat_from_text, read_text
from .syntax import _COMMENT, DYNAMICS, KINEMATICS, parse_text

#: arguments that say what a line is about rather than hold a value to vary
_IDENTITIES = {"element", "node", "direction", "deformation"}
_WORD = re.compile(r"\S+")


class Slot(NamedTuple):
    """Where a named value sits: its line (from 1), its word on the line (the keyword is
    word 0) and the name of its argument."""

    line: int
    word: int
    argument: str


@dataclass(frozen=True)
class DatTemplate:
    """A SPACAR input file whose values are varied by name (see the module docstring).

    Calling it with ``{name: value}`` returns the :class:`~flexmbd.io.dat.DatFile` of the
    file with those values, so it serves as the ``build`` of :func:`flexmbd.sweep`;
    it holds the text, not the path, so it also builds on workers of other machines.

    Attributes:
        text: the file's text.
        path: its name, used in messages and as the model's name.
    """

    text: str
    path: str

    @classmethod
    def read(cls, path: str | Path) -> DatTemplate:
        """The template of the file at ``path``, read and checked as a whole once.

        Raises:
            InputFileError: the file cannot be read or is not a valid input file.
        """
        template = cls(read_text(path).removeprefix("\ufeff"), str(path))
        dat_from_text(template.text, template.path)
        return template

    def locate(self, name: str) -> Slot:
        """The place of the value ``name``.

        Raises:
            ArgumentError: the name is malformed, matches no line or several, points past
                the line's values or at a number that says what the line is about.
        """
        keyword, numbers, position = _split(name)
        statements = parse_text(self.text, self.path)
        if keyword not in KINEMATICS and keyword not in DYNAMICS:
            raise ArgumentError(name, f"{keyword} is not a keyword of SPACAR input files")
        # a keyword of both blocks (INPUTX: the classification, then the law) is the
        # line that has a value at the position
        index = len(numbers) + position - 1
        same = [(s, table) for block, table in ((statements.kinematics, KINEMATICS),
                                                (statements.dynamics, DYNAMICS))
                for s in block if s.keyword == keyword]
        matched = [(s, table) for s, table in same if s.values[:len(numbers)] == numbers]
        lines = [(s, table) for s, table in matched if index < len(s.values)]
        first = same[0][1] if same else DYNAMICS if keyword in DYNAMICS else KINEMATICS
        arguments = [a.name for a in (*first[keyword].required, *first[keyword].optional)]
        if not numbers and arguments and arguments[0] in _IDENTITIES:
            example = f"{keyword}:{same[0][0].values[0]}:1" if same else f"{keyword}:1:1"
            raise ArgumentError(name, f"{keyword} lines name their {arguments[0]} first: "
                                      f"write {keyword}:{arguments[0].upper()}:POSITION, "
                                      f"e.g. {example}")
        picked = " ".join([keyword, *map(str, numbers)])
        if not matched:
            raise ArgumentError(name, f"{self.path} has no {picked} line")
        if not lines:
            statement = matched[-1][0]
            raise ArgumentError(name, f"line {statement.line} of {self.path} has "
                                      f"{len(statement.values) - len(numbers)} value(s) after "
                                      f"{picked}, not {position}; write the value out in the "
                                      f"file to vary it")
        if len(lines) > 1:
            where = ", ".join(str(s.line) for s, _ in lines)
            example = ":".join([keyword, *map(str, lines[0][0].values[:len(numbers) + 1])])
            raise ArgumentError(name, f"{picked} matches lines {where} of {self.path}; add "
                                      f"the next number of the line to pick one, e.g. "
                                      f"{example}:1")
        statement, table = lines[0]
        syntax = table[keyword]
        arguments = [a.name for a in (*syntax.required, *syntax.optional)]
        argument = arguments[index] if index < len(arguments) or syntax.rest is None else \
            syntax.rest.name
        if argument in _IDENTITIES:
            raise ArgumentError(name, f"position {position} is the {argument} number of line "
                                      f"{statement.line}, which says what the line is about; "
                                      f"name a value after it")
        return Slot(statement.line, 1 + index, argument)

    def check(self, cases: list[dict[str, object]]) -> None:
        """Check a study's cases before any runs: every name located, every value a number.

        Raises:
            ArgumentError: see :meth:`locate` and :meth:`text_with`.
        """
        for name in cases[0]:
            self.locate(name)
            for case in cases:
                _number(name, case[name])

    def text_with(self, values: dict[str, float]) -> str:
        """The file's text with the named values replaced.

        Raises:
            ArgumentError: a name that :meth:`locate` refuses, a value that is not a number.
        """
        lines = self.text.splitlines(keepends=True)
        for name, value in values.items():
            _number(name, value)
            slot = self.locate(name)
            raw = lines[slot.line - 1]
            body = _COMMENT.split(raw, maxsplit=1)[0]
            word = list(_WORD.finditer(body))[slot.word]
            lines[slot.line - 1] = raw[:word.start()] + repr(value) + raw[word.end():]
        return "".join(lines)

    def __call__(self, **values: float) -> DatFile:
        """The model and settings of the file with ``values`` put in (``{name: value}``).

        Raises:
            ArgumentError: see :meth:`text_with`.
            InputFileError: the varied file is not valid (e.g. a negative stiffness).
        """
        return dat_from_text(self.text_with(values), self.path)


def _number(name: str, value) -> None:
    """Refuse a value of a file that is not a number (a bool, a string)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ArgumentError(name, f"takes a number, got {value!r}")


def _split(name: str) -> tuple[str, tuple[int, ...], int]:
    """``"ESTIFF:2:2"`` -> ``("ESTIFF", (2,), 2)``."""
    parts = str(name).split(":")
    try:
        numbers = tuple(int(p) for p in parts[1:])
    except ValueError:
        numbers = ()
    if len(parts) < 2 or len(numbers) != len(parts) - 1 or numbers[-1] < 1:
        raise ArgumentError(str(name), "a value of the file is named KEYWORD:NUMBER...:"
                                       "POSITION, e.g. ESTIFF:2:2 (element 2's second "
                                       "stiffness value) or TIMESTEP:1")
    return parts[0].upper(), numbers[:-1], numbers[-1]

