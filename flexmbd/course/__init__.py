"""Course mode: the course's four exercises, part by part (``flexmbd exercise``).

:mod:`flexmbd.course.catalogue` lists the exercises and their lettered parts, each with
the function a student writes and what it returns. The catalogue loads on first use:
importing the helper a student's file imports (:mod:`flexmbd.course.student`) loads no
exercise and no answer.
"""

__all__ = ["EXERCISES", "Exercise", "Part", "exercise"]


def __getattr__(name: str):
    if name in __all__:
        from . import catalogue

        return getattr(catalogue, name)
    raise AttributeError(f"module 'flexmbd.course' has no attribute {name!r}")
