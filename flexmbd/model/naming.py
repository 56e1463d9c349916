"""Close names for a label that names nothing: the labels a user most likely meant, from
the ones that exist, and the naming scheme in words.

A label is tried as it was written, in lower case, with the other tools' names for the
same thing (``v5.1`` for a velocity, ``sigma2.1`` for a stress), as a direction name with
a node number (``phi2``, ``y5``: MATLAB users' names for SPACAR's ``x2.1``, ``x5.2``), and
then by spelling (:func:`difflib.get_close_matches`).
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Mapping, Sequence

__all__ = ["SCHEME", "close_names", "suggestion"]

#: the naming scheme of coordinates, deformations and result columns, in words
SCHEME = ("coordinates are x<node>.<k> (k = 1, 2, 3 for x, y, z of a translational node; 1 "
          "for a planar rotational node's angle; 1 to 4 for a spatial one's Euler parameters "
          "lam0 to lam3), their rates xd<node>.<k> and accelerations xdd<node>.<k>; "
          "deformations are e<element>.<k>, with ed, edd and the stresses sig<element>.<k>")

#: other names of the prefixes of result columns
_PREFIXES = {"v": "xd", "vel": "xd", "velocity": "xd", "xdot": "xd", "dx": "xd",
             "a": "xdd", "acc": "xdd", "acceleration": "xdd", "xddot": "xdd", "ddx": "xdd",
             "p": "x", "pos": "x", "u": "x", "q": "x",
             "edot": "ed", "de": "ed", "eddot": "edd",
             "s": "sig", "sigma": "sig", "stress": "sig", "eps": "e", "strain": "e"}

_LABEL = re.compile(r"^\s*([a-z_]+?)\s*(\d+)(?:[._ ](\d+))?\s*$")


def close_names(given: str, candidates: Sequence[str],
                directions: Mapping[int, Sequence[str]] | None = None,
                count: int = 3) -> list[str]:
    """Up to ``count`` of ``candidates`` that ``given`` most likely meant, best first.

    Args:
        given: the label that names nothing.
        candidates: the labels that exist.
        directions: per node number, the names of its coordinates' directions in order
            (``{2: ("phi",), 5: ("x", "y")}``), for labels such as ``"phi2"``.
        count: at most this many.
    """
    known = list(dict.fromkeys(candidates))
    available = set(known)
    found: list[str] = []
    text = str(given).strip()
    lower = text.lower()
    match = _LABEL.match(lower)
    if lower in available:
        found.append(lower)
    if match:
        prefix, number, k = match.group(1), int(match.group(2)), match.group(3)
        for name in (prefix, _PREFIXES.get(prefix)):
            if name:
                found.append(f"{name}{number}.{k or 1}")
        for node, names in (directions or {}).items():
            if node == number and prefix in names:
                found.append(f"x{node}.{list(names).index(prefix) + 1}")
    found += difflib.get_close_matches(lower, known, n=count, cutoff=0.6)
    return [name for name in dict.fromkeys(found) if name in available][:count]


def suggestion(given: str, candidates: Sequence[str],
               directions: Mapping[int, Sequence[str]] | None = None) -> str:
    """``"; did you mean 'x2.1'?"`` (or nothing), then the naming scheme: the tail of an
    error message for a label that names nothing."""
    close = close_names(given, candidates, directions)
    meant = (f"; did you mean {' or '.join(repr(name) for name in close)}?" if close
             else "")
    return f"{meant} ({SCHEME})"
