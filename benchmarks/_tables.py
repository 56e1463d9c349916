"""The benchmarks' Markdown table, for pasting into ``RESULTS.md``."""

from __future__ import annotations


def table(rows: list[dict]) -> str:
    """Rows (dicts with the same keys) as a Markdown table; floats to 3 digits."""
    keys = list(rows[0])
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for row in rows:
        cells = [f"{v:.3g}" if isinstance(v, float) else str(v) for v in row.values()]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
