"""The SPACAR input format, planar and spatial: statements, blocks and the arguments of
each keyword.

A file is free format, one keyword per line followed by numbers; comments start
with ``#``, ``%`` or ``*`` and run to the end of the line; keywords are
case-insensitive. Block 1 (kinematics) ends with ``END`` then ``HALT``; block 2
(dynamics) ends with ``END``; the file ends with a second ``END``. Anything
after that (a ``VISUALIZATION`` trailer, say) is ignored. A kinematics-only file
may end right after block 1 with ``END END``. A file of SPACAR's transfer functions
(mode 9) ends block 2 with ``END HALT`` instead, and a third block of numbered inputs
and outputs (``INPUTF i n dir``, ``OUTX i n dir``, ``OUTXP i n dir``) follows before the
closing ``END END``.

Numbers may use a Fortran ``D`` exponent (``2.0D11``); integers may be written
with a zero fraction (``3.``).
"""

from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...elements import ELEMENT_TYPES
from ...errors import InputFileError

_COMMENT = re.compile(r"[#%*]")
#: node, element and step numbers above this are refused (they would not fit in memory)
LARGEST_INTEGER = 10**8


@dataclass(frozen=True)
class Argument:
    """One argument of a keyword: a name for messages and its type (int or float)."""

    name: str
    type: type


@dataclass(frozen=True)
class Syntax:
    """Arguments of a keyword: required ones, optional ones, then any number of ``rest``
    (at least ``min_rest``), and what the keyword means (the user guide's table of
    keywords is made from these)."""

    required: tuple[Argument, ...]
    optional: tuple[Argument, ...] = ()
    rest: Argument | None = None
    min_rest: int = 0
    meaning: str = ""

    def usage(self, keyword: str) -> str:
        words = [keyword, *(a.name for a in self.required),
                 *(f"[{a.name}]" for a in self.optional)]
        if self.rest is not None:
            words.append(f"{self.rest.name} ..." if self.min_rest else f"[{self.rest.name} ...]")
        return " ".join(words)


def _args(spec: str) -> tuple[Argument, ...]:
    """``"e:int p:int"`` -> arguments."""
    types = {"int": int, "float": float, "name": str}
    return tuple(Argument(name, types[kind]) for name, kind in
                 (word.split(":") for word in spec.split()))


def _syntax(required: str, optional: str = "", rest: str = "", min_rest: int = 0, *,
            meaning: str) -> Syntax:
    return Syntax(_args(required), _args(optional), _args(rest)[0] if rest else None, min_rest,
                  meaning)


def _element_meaning(etype) -> str:
    deformations = ", ".join(f"{k + 1} {name}" for k, name in enumerate(etype.deformation_names))
    data = [name for name in etype.element_data if name in LINE_DATA]
    given = f", then its {' and '.join(data)} vector" if data else ""
    return f"a {etype.name} element and its nodes{given}; deformations: {deformations}"


#: element data written on a spatial element's line after its nodes, in SPACAR's
#: spelling: a beam's orientation vector, a hinge's axis
LINE_DATA = {"orientation": ("ox", "oy", "oz"), "axis": ("ax", "ay", "az")}


def element_words(etype, optional: bool = False) -> list[str]:
    """The arguments of an element line: its number, its nodes, then its line data; with
    ``optional``, the line data it may leave off."""
    data = [f"{word}:float" for name in etype.element_data if name in LINE_DATA
            and (name in etype.optional_data) == optional for word in LINE_DATA[name]]
    return data if optional else ["element:int", *(f"{r.name}:int" for r in etype.roles),
                                  *data]


#: SPACAR's output level, which SPACAR users' files carry in either block
OUTLEVEL = _syntax("", rest="level:float", meaning="SPACAR's output level: read and ignored")

#: block 1: elements (their nodes as the element types name them), positions and the
#: classification of coordinates and deformations
KINEMATICS = {
    **{keyword: _syntax(" ".join(element_words(etype)),
                        " ".join(element_words(etype, optional=True)),
                        meaning=_element_meaning(etype))
       for keyword, etype in ELEMENT_TYPES.items() if not etype.automatic},
    "X": _syntax("node:int x:float y:float", "z:float",
                 meaning="initial position [m] of a translational node (z in a spatial file)"),
    "FIX": _syntax("node:int", rest="direction:int",
                   meaning="fixes coordinates of a node (all when no direction is given)"),
    "INPUTX": _syntax("node:int", rest="direction:int",
                      meaning="makes coordinates of a node kinematic inputs (prescribed)"),
    "DYNX": _syntax("node:int", rest="direction:int",
                    meaning="makes coordinates of a node dynamic degrees of freedom"),
    "INPUTE": _syntax("element:int", rest="deformation:int",
                      meaning="makes deformations of an element kinematic inputs (a driven "
                              "hinge, a prescribed elongation)"),
    "DYNE": _syntax("element:int", rest="deformation:int",
                    meaning="makes deformations of an element dynamic degrees of freedom "
                            "(flexible)"),
    "RLSE": _syntax("element:int", rest="deformation:int",
                    meaning="releases deformations of an element: calculated from the "
                            "coordinates, neither rigid nor a degree of freedom"),
    "OUTLEVEL": OUTLEVEL,
}

#: block 2: properties, loads, input laws, initial values and run settings
DYNAMICS = {
    "EM": _syntax("element:int rhoA:float", rest="inertia:float",
                  meaning="mass per length [kg/m] of an element, consistent; a planar "
                          "beam's rotary inertia rhoI [kg m] per length may follow (other "
                          "planar elements' must be 0), a spatial beam's section inertias "
                          "Jxx Jyy Jzz Jyz [kg m] per length follow, and a warping beam's "
                          "Jw [kg m^3]"),
    "EMLUMP": _syntax("element:int rhoA:float", rest="inertia:float",
                      meaning="flexmbd's own: mass per length [kg/m], lumped at the nodes, "
                              "then as EM"),
    "ESTIFF": _syntax("element:int", rest="stiffness:float",
                      meaning="stiffness values of an element in its type's order; none "
                              "given (as oopspa writes it) is as no line (a beam: "
                              "EA [N], EI [N m^2], optionally GA_s [N]; a spatial beam: EA "
                              "GIt EIy EIz [sy sz] with sy, sz [m^2]; a warping beam's "
                              "ECw [N m^4] follows)"),
    "EDAMP": _syntax("element:int", rest="damping:float", min_rest=1,
                     meaning="damping values of an element in its type's order"),
    "ESIG": _syntax("element:int", rest="sigma0:float", min_rest=1,
                    meaning="pre-stresses [N or N m] of an element's deformations, one per "
                            "deformation in order from the first (the rest are 0)"),
    "XM": _syntax("node:int", rest="inertia:float", min_rest=1,
                  meaning="a point mass [kg] on a translational node, a rotary inertia "
                          "[kg m^2] on a rotational one; in space the inertia tensor Ixx "
                          "Ixy Ixz Iyy Iyz Izz in the node's body frame"),
    "XF": _syntax("node:int", rest="load:float", min_rest=1,
                  meaning="constant load on a node: Fx Fy [N] or a moment [N m]; in space "
                          "Fx Fy Fz or a global moment Mx My Mz"),
    "GRAVITY": _syntax("gx:float gy:float", "gz:float",
                       meaning="gravitational acceleration [m/s^2]"),
    "OUTLEVEL": OUTLEVEL,
    "INPUTX": _syntax("node:int direction:int x0:float", "v0:float a0:float",
                      meaning="law x0 + v0 t + a0 t^2/2 of an input coordinate"),
    "INPUTE": _syntax("element:int deformation:int e0:float", "v0:float a0:float",
                      meaning="law e0 + v0 t + a0 t^2/2 of an input deformation"),
    "STARTDE": _syntax("element:int deformation:int e0:float", "edot0:float",
                       meaning="initial value and rate of a dynamic deformation"),
    "STARTDX": _syntax("node:int direction:int x0:float", "xdot0:float",
                       meaning="initial value and rate of a dynamic coordinate"),
    "TIMESTEP": _syntax("t_end:float steps:int",
                        meaning="end time [s] and number of output intervals (steps + 1 rows)"),
    # SPACAR's order: iteration limit, load steps, tolerance, then solver flags
    "USERSIG": _syntax("routine:name",
                       meaning="user routine of loads and stresses, routine(t, ne, le, e, ep, "
                               "nx, lnp, x, xp) -> (time, sig, f), in routine.py beside the "
                               "file"),
    "USERINP": _syntax("routine:name",
                       meaning="user routine of input motions, routine(t, is) -> (time, e, x), "
                               "in routine.py beside the file"),
    "ITERSTEP": _syntax("max_iterations:int", "load_steps:int tolerance:float", rest="flag:float",
                        meaning="Newton iteration limit, static load steps and position "
                                "tolerance [m, rad]; SPACAR's solver flags are not used"),
    "ERROR": _syntax("atol:float rtol:float",
                     meaning="absolute and relative tolerance of the integrator"),
    # static load steps and the linear model (SPACAR's modes 9 and 10)
    "DELXF": _syntax("node:int", rest="load:float", min_rest=1,
                     meaning="load increment over the static load steps, as XF"),
    "DELINPX": _syntax("node:int direction:int delta:float",
                       meaning="increment of an input coordinate over the load steps"),
    "DELINPE": _syntax("element:int deformation:int delta:float",
                       meaning="increment of an input deformation over the load steps"),
    "INPUTF": _syntax("node:int", rest="direction:int",
                      meaning="force inputs of the state-space model"),
    "OUTX": _syntax("node:int", rest="direction:int",
                    meaning="position outputs of the state-space model"),
    "OUTXP": _syntax("node:int", rest="direction:int",
                     meaning="velocity outputs of the state-space model"),
}

#: block 3 of a transfer-function file (SPACAR's mode 9): inputs and outputs, each line
#: starting with its number among the inputs or the outputs
TRANSFER = {
    "INPUTF": _syntax("number:int node:int direction:int",
                      meaning="input number i of the state-space model: a force on a "
                              "coordinate of a node"),
    "OUTX": _syntax("number:int node:int direction:int",
                    meaning="output number i of the state-space model: a coordinate of a "
                            "node"),
    "OUTXP": _syntax("number:int node:int direction:int",
                     meaning="output number i of the state-space model: the rate of a "
                             "coordinate of a node"),
}

#: keywords of SPACAR that flexmbd does not read
#: SPACAR keywords flexmbd refuses with what to use instead: the nominal-trajectory and
#: reference-deformation keywords of SPACAR's inverse dynamics, whose meaning SPACAR's
#: public documentation does not give
INSTEAD = {
    **{keyword: "prescribe the motion with INPUTX and INPUTE (or USERINP) and run flexmbd "
                "run --mode inverse (flexmbd spacar 2)"
       for keyword in ("NOMS", "NOMF", "REFE", "REFEP", "REFEDP")},
}

UNSUPPORTED = {"PINBAR", "CYLINDER", "PLATE", "SBEAM", "CONTACT", "WHEEL", "BELT",
               "SPRING", "RNODE", "XSTIFF", "XDAMP", "PINBODY", "PLPINBODY", "TUBE",
               "PLTUBE", "SCREW"} - set(KINEMATICS)


@dataclass(frozen=True)
class Statement:
    """One keyword line: the keyword (upper case), its converted arguments (ints and floats
    as the keyword's syntax has them, :data:`KINEMATICS` and :data:`DYNAMICS`), its line."""

    keyword: str
    values: tuple[Any, ...]
    line: int


@dataclass(frozen=True)
class DatText:
    """The statements of both blocks of a file."""

    kinematics: tuple[Statement, ...]
    dynamics: tuple[Statement, ...]
    path: str | None
    #: the line of the END that closes the kinematics block
    kinematics_end: int = 0
    #: block 3 of a transfer-function file: its numbered inputs and outputs
    transfer: tuple[Statement, ...] = ()


#: a routine's name: a Python identifier, so that it names a module beside the file
_ROUTINE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def _number(word: str, kind: type, what: str, keyword: str, path, line):
    if kind is str:
        if not _ROUTINE.fullmatch(word) or len(word) > 64:
            raise InputFileError(f"{keyword}: {what} must be a routine name (letters, digits "
                                 f"and _, not starting with a digit), got {word!r}",
                                 path, line)
        return word
    try:
        value = float(word.replace("d", "e").replace("D", "E"))
    except ValueError:
        raise InputFileError(f"{keyword}: {what} must be a number, got {word!r}",
                             path, line) from None
    if not math.isfinite(value):
        raise InputFileError(f"{keyword}: {what} must be a finite number, got {word!r}",
                             path, line)
    if kind is int:
        if not value.is_integer():
            raise InputFileError(f"{keyword}: {what} must be a whole number, got {word!r}",
                                 path, line)
        if abs(value) > LARGEST_INTEGER:
            raise InputFileError(f"{keyword}: {what} {word} is larger than {LARGEST_INTEGER}",
                                 path, line)
        return int(value)
    return value


def _statement(keyword: str, words: list[str], syntax: Syntax, path, line) -> Statement:
    need, optional = len(syntax.required), len(syntax.optional)
    top = None if syntax.rest is not None else need + optional
    if len(words) < need + syntax.min_rest or (top is not None and len(words) > top):
        raise InputFileError(f"{keyword} takes {syntax.usage(keyword)}; got {len(words)} "
                             f"value(s)", path, line)
    # beyond the required and optional arguments the words are rest's (the count is checked)
    arguments = [*syntax.required, *syntax.optional, *([syntax.rest] if syntax.rest else [])]
    values = []
    for i, word in enumerate(words):
        argument = arguments[min(i, len(arguments) - 1)]
        values.append(_number(word, argument.type, argument.name, keyword, path, line))
    return Statement(keyword, tuple(values), line)


def parse_text(text: str, path: str | Path | None = None) -> DatText:
    """Split a SPACAR input text into the statements of its two blocks.

    Raises:
        InputFileError: an unknown or spatial keyword, a word where a number
            belongs, a wrong number of values, or a missing ``END``/``HALT``.
    """
    path = None if path is None else str(path)
    blocks: dict[str, list[Statement]] = {"kinematics": [], "dynamics": [], "transfer": []}
    tables = {"kinematics": KINEMATICS, "dynamics": DYNAMICS, "transfer": TRANSFER}
    # what END and HALT lead to from each state
    after_end = {"kinematics": "after kinematics", "after kinematics": "done",
                 "dynamics": "after dynamics", "after dynamics": "done",
                 "transfer": "after transfer", "after transfer": "done"}
    after_halt = {"after kinematics": "dynamics", "after dynamics": "transfer"}
    state, kinematics_end = "kinematics", 0
    lines = text.removeprefix("\ufeff").splitlines()  # a byte-order mark is not a keyword
    for number, raw in enumerate(lines, start=1):
        words = _COMMENT.split(raw, maxsplit=1)[0].split()
        if not words:
            continue
        keyword, rest = words[0].upper(), words[1:]
        if state == "done":
            break
        if keyword == "END" and state == "kinematics":
            kinematics_end = number
        if keyword == "END":
            state = after_end[state]
            continue
        if keyword == "HALT":
            if state not in after_halt:
                raise InputFileError("HALT belongs right after the END of the kinematics "
                                     "block (or of the dynamics block of a transfer-function "
                                     "file)", path, number)
            state = after_halt[state]
            continue
        if state.startswith("after "):
            expected = "END" if state == "after transfer" else "HALT or END"
            raise InputFileError(f"expected {expected} after the END of the {state[6:]} block, "
                                 f"got {keyword}", path, number)
        if keyword not in tables[state]:
            raise InputFileError(_unknown(keyword, state), path, number)
        blocks[state].append(_statement(keyword, rest, tables[state][keyword], path, number))
    if state != "done":
        missing = {"kinematics": "END ending the kinematics block",
                   "after kinematics": "the final END (or HALT and a dynamics block)",
                   "dynamics": "END ending the dynamics block",
                   "after dynamics": "the final END",
                   "transfer": "END ending the block of inputs and outputs",
                   "after transfer": "the final END"}[state]
        empty = not any(_COMMENT.split(line, maxsplit=1)[0].strip() for line in lines)
        what = "the file is empty," if empty else "the file ends"
        raise InputFileError(f"{what} without {missing}", path, max(len(lines), 1))
    return DatText(tuple(blocks["kinematics"]), tuple(blocks["dynamics"]), path, kinematics_end,
                   tuple(blocks["transfer"]))


def _unknown(keyword: str, block: str) -> str:
    if keyword in INSTEAD:
        return f"SPACAR's keyword {keyword} is not supported by flexmbd: {INSTEAD[keyword]}"
    if keyword in UNSUPPORTED or (block == "transfer" and keyword in {*KINEMATICS, *DYNAMICS}):
        return f"SPACAR's element or keyword {keyword} is not supported by flexmbd" + (
            " in the block of inputs and outputs (INPUTF, OUTX and OUTXP are)"
            if block == "transfer" else "")
    other = DYNAMICS if block == "kinematics" else KINEMATICS
    if keyword in other:
        where = "dynamics block (after END and HALT)" if block == "kinematics" else \
            "kinematics block (before the first END)"
        return f"{keyword} belongs in the {where}"
    if not keyword.isprintable() or not keyword.isascii():
        keyword = ascii(keyword)  # show invisible and look-alike characters
    known = TRANSFER if block == "transfer" else {*KINEMATICS, *DYNAMICS}
    close = difflib.get_close_matches(keyword.upper(), sorted(known), n=3, cutoff=0.6)
    meant = f"; did you mean {' or '.join(close)}?" if close else ""
    return (f"unknown keyword {keyword} in the {block} block{meant} (known: "
            f"{', '.join(sorted(known))})")
