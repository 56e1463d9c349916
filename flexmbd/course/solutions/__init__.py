"""The completed exercise files (``flexmbd exercise solution NAME``).

Each is a student's file as the course intends it: numpy formulas written out, the
given parts complete. ``flexmbd exercise start`` writes the same file with the
formulas between ``# BEGIN SOLUTION`` and ``# END SOLUTION`` replaced by a "not done
yet" with a hint. They compute everything themselves; flexmbd checks them.
"""
