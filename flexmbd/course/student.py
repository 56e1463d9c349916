"""What a student's exercise file imports: the "not done yet" signal and a runner for the
file's own demonstration. Nothing here computes an answer."""

from __future__ import annotations

import sys


class NotDone(NotImplementedError):  # noqa: N818 - what the student reads
    """A part of an exercise that the student has not written yet."""

    def __init__(self, part: str, hint: str):
        super().__init__(f"part {part} not done yet: {hint}")
        self.part = part
        self.hint = hint


def not_done(part: str, hint: str):
    """Raise :class:`NotDone` for ``part`` (``"b"``) with a ``hint`` on where to start."""
    raise NotDone(part, hint)


def show(title: str, function, *args) -> object:
    """Call ``function(*args)`` and print its result under ``title``; a part that is not
    done (or fails) is reported and the demonstration goes on. Returns the result or
    ``None``."""
    try:
        result = function(*args)
    except NotDone as error:
        print(f"{title}: {error}")
        return None
    except Exception as error:  # the student's code: report it and go on
        print(f"{title}: {type(error).__name__}: {error}", file=sys.stderr)
        return None
    print(f"{title}:\n{result}")
    return result
