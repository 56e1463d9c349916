"""SPACAR95 (Delft) input files, read with their manual's meaning.

SPACAR95 (A.L. Schwab, J.P. Meijaard, *Manual SPACAR95*, TU Delft, November 2000) is the
Delft branch of SPACAR. Its input is one block of keywords ended by ``END``, with a
keyword set of its own: ``XY``, ``XYZ``, ``BETA``, ``LAMBDA`` nodes, ``MASS``,
``EMASS``, ``FORCE``, initial values ``XD``, ``ED``, ..., ``TIMESTEP n Tp`` (the
intervals first, then the period: the reverse of UT SPACAR's ``TIMESTEP T n``),
``*`` comment lines and solver settings (``HMAX``, ``EPSKIN``, ...).

A file is read as SPACAR95 when it uses a keyword only SPACAR95 has, and no keyword only
UT SPACAR has; a file that mixes them, or whose only sign is a ``TIMESTEP`` before the
first ``END`` (which either dialect could mean), is refused, naming what it holds. A
SPACAR95 file becomes the statements of the UT reader (:mod:`.reader`) at their own
lines: elements, nodes, classes and properties as the manual defines them; an input's
initial rate and acceleration (``XD``, ``XDD``, ``ED``, ``EDD``) its law ``x0 + v t + a
t^2/2`` from the drawn configuration; a dynamic degree of freedom's initial value and rate
its ``STARTDX`` or ``STARTDE``. The solver settings are noted, not used (flexmbd's
integrator and Newton tolerances are its own). A SPACAR95 keyword with no counterpart is
refused once, naming SPACAR95 and the keyword.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ...errors import InputFileError
from .syntax import DYNAMICS, KINEMATICS, DatText, Statement, _number, _statement

__all__ = ["is_spacar95", "parse_spacar95"]

#: keywords only SPACAR95 has: any of them makes a file SPACAR95
ONLY_SPACAR95 = {"XY", "XYZ", "BETA", "LAMBDA", "MASS", "EMASS", "FORCE", "TORQUEL",
                 "EDAMPP", "HMAX", "MAXITERAT", "EPSKIN", "EPSINT", "EPSIND", "FORCEMODE",
                 "ANIMATE", "MATASC", "JOBID", "RESTART", "EOF", "LINE", "ENHC", "TIME",
                 "DIR", "LGEOMY", "LENGTH0", "XD", "XDD", "E", "ED", "EDD", "BEAMNL",
                 "PLBEAMNL", "BEARING", "SURFACE", "L2MIN1", "PLBELT", "PLBEAR", "PLWHEEL"}
#: keywords only UT SPACAR has
ONLY_UT = {"HALT", "XM", "EM", "XF", "ESIG", "GRAVITY", "STARTDX", "STARTDE", "ITERSTEP",
           "ERROR", "DELXF", "DELINPX", "DELINPE", "USERSIG", "USERINP", "INPUTF", "OUTX",
           "OUTXP", "OUTLEVEL", "RBEAM", "BEAMW"}
#: SPACAR95 keywords without a counterpart in flexmbd, and why
NO_COUNTERPART = {
    **dict.fromkeys(("BEAMNL", "PLBEAMNL"), "beams with bending-corrected elongation"),
    **dict.fromkeys(("BEARING", "PLBEAR", "PLBELT", "PLWHEEL", "SURFACE"),
                    "this element type"),
    "L2MIN1": "an explicit Euler-parameter constraint (flexmbd adds it to every rotational "
              "node)",
    "TORQUEL": "a body-fixed torque",
    "LINE": "linearization parameters", "ENHC": "nonholonomic constraints",
    **dict.fromkeys(("DIR", "LGEOMY", "LENGTH0"),
                    "element geometry given apart from the nodes (a restart file's)"),
}
#: solver, output and restart settings: noted, not used
SETTINGS = ("HMAX", "MAXITERAT", "EPSKIN", "EPSINT", "EPSIND", "FORCEMODE", "ANIMATE",
            "MATASC", "JOBID", "RESTART")
#: SPACAR95's node keywords, read as ``X``
NODES = ("XY", "XYZ", "BETA", "LAMBDA")
#: kinematic keywords both dialects spell alike
SHARED_KINEMATICS = {"PLBEAM", "PLTRUSS", "PLHINGE", "BEAM", "TRUSS", "HINGE", "X", "FIX",
                     "INPUTX", "DYNX", "RLSE", "INPUTE", "DYNE"}


def _words(text: str) -> list[tuple[int, list[str]]]:
    """The keyword lines ``(line, words)``: ``*`` in the first column and ``#`` start
    comments."""
    out = []
    for number, line in enumerate(text.splitlines(), 1):
        if line.startswith("*"):
            continue
        words = line.split("#", 1)[0].split()
        if words:
            out.append((number, words))
    return out


def is_spacar95(text: str, path: str | Path | None = None) -> bool:
    """Whether ``text`` is a SPACAR95 file (module docstring).

    Raises:
        InputFileError: it mixes the dialects, or a ``TIMESTEP`` before the first ``END``
            is its only sign of either.
    """
    where = None if path is None else str(path)
    first: dict[str, tuple[int, str]] = {}
    timestep, ended = None, False
    for number, words in _words(text):
        keyword = words[0].upper()
        if keyword == "END":
            ended = True
        elif keyword == "TIMESTEP" and not ended and timestep is None:
            timestep = number
        for dialect, keywords in (("SPACAR95", ONLY_SPACAR95), ("UT SPACAR", ONLY_UT)):
            if keyword in keywords:
                first.setdefault(dialect, (number, keyword))
    if len(first) == 2:
        (a, ka), (b, kb) = first["SPACAR95"], first["UT SPACAR"]
        raise InputFileError(f"mixes SPACAR95 (Delft) keyword {ka} (line {a}) and UT SPACAR "
                             f"keyword {kb} (line {b}): write the file in one of them",
                             where, min(a, b))
    if first:
        return "SPACAR95" in first
    if timestep is not None:
        raise InputFileError("TIMESTEP before the first END: a SPACAR95 (Delft) file writes "
                             "TIMESTEP n Tp there (output intervals, then the period), a UT "
                             "SPACAR file writes TIMESTEP T n in the dynamics block after END "
                             "and HALT; the file holds nothing else that tells which it is: "
                             "move the line for UT SPACAR, or add SPACAR95's MASS or EMASS "
                             "lines", where, timestep)
    return False


@dataclass
class _Translation:
    """The UT statements of a SPACAR95 file, and what is known along the way."""

    path: str | None
    kinematics: list[Statement] = field(default_factory=list)
    dynamics: list[Statement] = field(default_factory=list)
    positions: dict[int, list[float]] = field(default_factory=dict)
    kinds: dict[int, str] = field(default_factory=dict)
    inputs: set[tuple[str, int, int | None]] = field(default_factory=set)
    dynamic: set[tuple[str, int, int | None]] = field(default_factory=set)
    #: initial values by (x or e, number, direction): {"value"|"rate"|"second": (v, line)}
    initial: dict[tuple[str, int, int], dict[str, tuple[float, int]]] = field(
        default_factory=dict)
    noted: dict[str, list[int]] = field(default_factory=dict)

    def fail(self, message: str, line: int):
        raise InputFileError(message, self.path, line)

    def add(self, block: str, keyword: str, words: list[str], line: int) -> None:
        table = KINEMATICS if block == "kinematics" else DYNAMICS
        getattr(self, block).append(_statement(keyword, words, table[keyword], self.path,
                                               line))


def parse_spacar95(text: str, path: str | Path | None = None) -> tuple[DatText, tuple[str, ...]]:
    """The statements of a SPACAR95 file for the UT reader, and the notes of what was
    read with another meaning or not used (module docstring).

    Raises:
        InputFileError: a keyword with no counterpart (naming SPACAR95), a wrong number
            of values, input after the first ``END``.
    """
    t = _Translation(None if path is None else str(path))
    end = 0
    for line, words in _words(text):
        keyword, rest = words[0].upper(), words[1:]
        if end:
            if keyword == "EOF":
                break
            t.fail(f"SPACAR95: input after the END on line {end} continues the analysis "
                   f"with changed input, which flexmbd does not do: run the parts as "
                   f"files of their own", line)
        if keyword == "EOF":
            t.fail("SPACAR95: EOF before the END that starts the analysis", line)
        if keyword == "END":
            end = line
            continue
        _translate(t, keyword, rest, line)
    if not end:
        t.fail("SPACAR95: the file ends without the END that starts the analysis",
               max(len(text.splitlines()), 1))
    _initial_values(t)
    notes = ["read as a SPACAR95 (Delft) file: TIMESTEP n Tp (intervals, then the period), "
             "MASS and EMASS as point masses and masses per length, initial rates of "
             "inputs as their laws"]
    notes += [f"SPACAR95's {keyword} on line{'s' if len(lines) > 1 else ''} "
              f"{', '.join(map(str, lines))}: read and not used (flexmbd's own solver "
              f"settings apply)" for keyword, lines in t.noted.items()]
    return DatText(tuple(t.kinematics), tuple(t.dynamics), t.path, end), tuple(notes)


def _translate(t: _Translation, keyword: str, rest: list[str], line: int) -> None:
    if keyword in NO_COUNTERPART:
        t.fail(f"SPACAR95 (Delft) keyword {keyword} has no counterpart in flexmbd: "
               f"{NO_COUNTERPART[keyword]}", line)
    if keyword in SETTINGS:
        t.noted.setdefault(keyword, []).append(line)
    elif keyword in NODES:
        _node(t, keyword, rest, line)
    elif keyword in SHARED_KINEMATICS:
        if keyword == "X" and rest:
            t.positions[_int(t, rest[0], keyword, line)] = [_float(t, w, keyword, line)
                                                           for w in rest[1:]]
        if keyword in ("INPUTX", "DYNX", "INPUTE", "DYNE"):
            _classify(t, keyword, rest, line)
        t.add("kinematics", keyword, rest, line)
    elif keyword == "MASS":
        t.add("dynamics", "XM", rest, line)
    elif keyword == "EMASS":
        if len(rest) > 2:
            t.fail("SPACAR95: EMASS takes e rhoA here (the belt's a1 a2 belong to PLBELT, "
                   "which flexmbd does not have)", line)
        t.add("dynamics", "EM", rest, line)
    elif keyword in ("ESTIFF", "EDAMPP"):
        t.add("dynamics", "ESTIFF" if keyword == "ESTIFF" else "EDAMP", rest, line)
    elif keyword == "FORCE":
        node = _int(t, rest[0], keyword, line) if rest else 0
        if t.kinds.get(node) == "LAMBDA":
            t.fail("SPACAR95: FORCE on a LAMBDA node gives forces on its Euler parameters; "
                   "flexmbd loads a rotational node with a global moment (XF n Mx My Mz)",
                   line)
        t.add("dynamics", "XF", rest, line)
    elif keyword == "TIMESTEP":
        if len(rest) != 2:
            t.fail(f"SPACAR95: TIMESTEP takes n Tp (output intervals, then the period), got "
                   f"{len(rest)} value(s)", line)
        t.add("dynamics", "TIMESTEP", [rest[1], rest[0]], line)
    elif keyword == "TIME":
        if len(rest) != 1 or _float(t, rest[0], keyword, line) != 0.0:
            t.fail("SPACAR95: TIME sets a start time other than 0 (a restart file's); "
                   "flexmbd starts at 0", line)
    elif keyword in ("XD", "XDD", "ED", "EDD", "E"):
        if len(rest) != 3:
            t.fail(f"SPACAR95: {keyword} takes a number, a direction and a value, got "
                   f"{len(rest)} value(s)", line)
        what = "x" if keyword.startswith("X") else "e"
        kind = {"XD": "rate", "ED": "rate", "XDD": "second", "EDD": "second",
                "E": "value"}[keyword]
        key = (what, _int(t, rest[0], keyword, line), _int(t, rest[1], keyword, line))
        t.initial.setdefault(key, {})[kind] = (_float(t, rest[2], keyword, line), line)
    else:
        t.fail(f"unknown SPACAR95 (Delft) keyword {keyword} (the file reads as SPACAR95: "
               f"its manual's keywords apply)", line)


def _node(t: _Translation, keyword: str, rest: list[str], line: int) -> None:
    sizes = {"XY": 2, "XYZ": 3, "BETA": 1, "LAMBDA": 4}
    if len(rest) != 1 + sizes[keyword]:
        t.fail(f"SPACAR95: {keyword} takes a node and {sizes[keyword]} value(s), got "
               f"{len(rest) - 1 if rest else 0}", line)
    node = _int(t, rest[0], keyword, line)
    t.kinds[node] = keyword
    t.positions[node] = [_float(t, w, keyword, line) for w in rest[1:]]
    t.add("kinematics", "X", rest, line)


def _classify(t: _Translation, keyword: str, rest: list[str], line: int) -> None:
    what = "x" if keyword.endswith("X") else "e"
    target = t.inputs if keyword.startswith("INPUT") else t.dynamic
    number = _int(t, rest[0], keyword, line) if rest else 0
    directions: list[int | None] = [_int(t, w, keyword, line) for w in rest[1:]] or [None]
    target.update((what, number, k) for k in directions)


def _initial_values(t: _Translation) -> None:
    """Initial values of inputs become their laws, of dynamic degrees of freedom their
    ``STARTDX``/``STARTDE``; an acceleration of a dynamic one follows from the equations
    and is noted."""
    for (what, number, k), given in sorted(t.initial.items()):
        line = min(at for _, at in given.values())
        value, rate, second = (given.get(name, (0.0, 0))[0]
                               for name in ("value", "rate", "second"))
        label = f"{what}{number}.{k}"
        if {(what, number, k), (what, number, None)} & t.inputs:
            keyword = "INPUTX" if what == "x" else "INPUTE"
            if what == "x" and "value" in given:
                t.fail(f"SPACAR95: a position of input {label} is given by its node's line",
                       line)
            t.add("dynamics", keyword, [str(number), str(k), repr(value), repr(rate),
                                        repr(second)], line)
        elif {(what, number, k), (what, number, None)} & t.dynamic:
            if "second" in given:
                t.noted.setdefault(f"{'XDD' if what == 'x' else 'EDD'} of a dynamic degree "
                                   f"of freedom", []).append(given["second"][1])
            if what == "x":
                drawn = t.positions.get(number, [])
                value = drawn[k - 1] if k <= len(drawn) else 0.0
            t.add("dynamics", "STARTDX" if what == "x" else "STARTDE",
                  [str(number), str(k), repr(value), repr(rate)], line)
        else:
            t.fail(f"SPACAR95: an initial value of {label}, which is neither an input nor a "
                   f"dynamic degree of freedom (its value follows from the others)", line)


def _int(t: _Translation, word: str, keyword: str, line: int) -> int:
    """A whole number of a SPACAR95 line, read as the UT reader reads its numbers."""
    return _number(word, int, "a node, element or direction number", keyword, t.path, line)


def _float(t: _Translation, word: str, keyword: str, line: int) -> float:
    """A number of a SPACAR95 line (``d`` exponents too), finite, as the UT reader reads
    its numbers."""
    return _number(word, float, "a value", keyword, t.path, line)
