"""Text that comes from a student, made safe to show: in a report, a terminal, a table.

A student's file decides its error messages, the ``repr`` of what it returns, the hint of
its "not done" and its own file name. Shown as they are, they could move the cursor,
recolour or clear a lecturer's terminal (ANSI escapes), reverse text (bidirectional
controls) or start a new line that forges a "passed" verdict. :func:`one_line` keeps the
words and drops the rest.
"""

from __future__ import annotations

import re
import unicodedata

#: terminal escape sequences: CSI (``ESC [ ... letter``), OSC (``ESC ] ... BEL/ST``), and
#: two-character escapes
_ESCAPES = re.compile(r"\x1b\[[0-?]*[ -/]*[@-~]|\x1b\][^\x07\x1b]*(?:\x07|\x1b\\)?|\x1b.?"
                      r"|\x9b[0-?]*[ -/]*[@-~]")


def one_line(text: object, limit: int = 300) -> str:
    """``text`` as one line of at most ``limit`` characters: escape sequences removed,
    every control, format (bidirectional marks among them) and line or paragraph
    separator character replaced by a space, spaces collapsed."""
    text = _ESCAPES.sub("", str(text))
    text = "".join(" " if unicodedata.category(c) in ("Cc", "Cf", "Cs", "Co", "Cn", "Zl",
                                                       "Zp") else c for c in text)
    text = " ".join(text.split())
    return text if len(text) <= limit else text[:limit - 3] + "..."
