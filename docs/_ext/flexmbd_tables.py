"""Tables of the user guide made from the library's own definitions, so they cannot go stale.

* ``flexmbd-keywords`` with ``:block: kinematics``, ``dynamics`` or ``transfer``: every keyword the
  ``.dat`` reader takes, its arguments and meaning (:mod:`flexmbd.io.dat.syntax`).
* ``flexmbd-elements``: every element type, its nodes, deformations and values
  (:data:`flexmbd.elements.ELEMENT_TYPES`).

The tables are built as docutils nodes, so they read the same from Markdown and
reStructuredText pages. A cell is a list of pieces; a piece in backticks is code.
"""

from __future__ import annotations

import re
from typing import ClassVar

from docutils import nodes
from docutils.parsers.rst import directives
from sphinx.util.docutils import SphinxDirective

from flexmbd.elements import ELEMENT_TYPES
from flexmbd.io.dat import syntax


def _cell(text: str) -> nodes.entry:
    paragraph = nodes.paragraph()
    for k, piece in enumerate(re.split(r"`([^`]*)`", text)):
        if piece:
            paragraph += nodes.literal(piece, piece) if k % 2 else nodes.Text(piece)
    return nodes.entry("", paragraph)


def _table(header: list[str], rows: list[list[str]], widths: list[int]) -> nodes.table:
    group = nodes.tgroup(cols=len(header))
    for width in widths:
        group += nodes.colspec(colwidth=width)
    head, body = nodes.thead(), nodes.tbody()
    head += nodes.row("", *(_cell(h) for h in header))
    for row in rows:
        body += nodes.row("", *(_cell(c) for c in row))
    group += head
    group += body
    return nodes.table("", group)


class KeywordTable(SphinxDirective):
    """The keywords of one block of a SPACAR file."""

    option_spec: ClassVar[dict] = {
        "block": lambda value: directives.choice(value, ("kinematics", "dynamics",
                                                          "transfer"))}

    def run(self):
        table = {"kinematics": syntax.KINEMATICS, "dynamics": syntax.DYNAMICS,
                 "transfer": syntax.TRANSFER}[self.options["block"]]
        rows = []
        for keyword, spec in table.items():
            if not spec.meaning:
                raise self.error(f"{keyword} has no meaning in flexmbd.io.dat.syntax")
            rows.append([f"`{keyword}`", f"`{spec.usage(keyword)}`", spec.meaning])
        return [_table(["keyword", "line", "meaning"], rows, [12, 40, 48])]


class ElementTable(SphinxDirective):
    """The element types, their nodes, deformations, stiffness and damping values."""

    def run(self):
        rows = []
        for keyword, etype in ELEMENT_TYPES.items():
            nodes_ = ", ".join(f"{r.name} ({r.kind})" for r in etype.roles)
            deformations = ", ".join(
                f"{k + 1} {name} [{unit}]" for k, (name, unit) in
                enumerate(zip(etype.deformation_names, etype.deformation_units, strict=True)))
            values = "; ".join(f"`{kind}`: " + ", ".join(
                f"{v.symbol} [{v.unit}] (`{v.name}=`)" for v in getattr(etype, attr))
                for kind, attr in (("ESTIFF", "stiffness_values"), ("EDAMP", "damping_values"))
                if getattr(etype, attr))
            rows.append([f"`{keyword}`", f"`fm.{etype.__name__}`", nodes_, deformations, values,
                         "yes" if etype.has_mass else "no"])
        return [_table(["keyword", "class", "nodes", "deformations", "values", "EM"], rows,
                       [10, 12, 20, 24, 28, 6])]


def setup(app):
    app.add_directive("flexmbd-keywords", KeywordTable)
    app.add_directive("flexmbd-elements", ElementTable)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
