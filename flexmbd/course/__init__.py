"""Course mode: the course's four exercises, part by part (``flexmbd exercise``).

:mod:`flexmbd.course.catalogue` lists the exercises and their lettered parts, each with
the function a student writes and what it returns.
"""

from .catalogue import EXERCISES, Exercise, Part, exercise

__all__ = ["EXERCISES", "Exercise", "Part", "exercise"]
