"""SPACAR's binary result files: ``.sbd`` (the run's tables and steps), ``.sbm`` and
``.ltv`` (the linearized equations per step), read and written in SPACAR's layout and
numbering."""

from .binary import SpacarFile, read_records, write_records
from .linear import write_ltv, write_sbm
from .records import write_sbd


def read_sbd(path) -> SpacarFile:
    """Read a SPACAR binary result file, ``.sbd``, ``.sbm`` or ``.ltv``, written by SPACAR
    or by flexmbd.

    Returns:
        :class:`SpacarFile`, a mapping from record name to values: tables ``(rows, cols)``
        (``f["LNP"]``), per-step records ``(n_steps, rows, cols)`` (``f["X"]``), and
        ``f.step("X", k)`` for step ``k`` (1-based). Names are matched as SPACAR's
        ``getfrsbf`` matches them: any case, first four characters.

    A file that ends inside its steps (a run stopped while writing it) gives its whole
    steps, with a :class:`~flexmbd.ResultFileWarning` naming the step it ends in.

    Raises:
        InputFileError: the file cannot be read or is not such a file; names the byte.
    """
    return read_records(path)


__all__ = ["SpacarFile", "read_records", "read_sbd", "write_ltv", "write_records", "write_sbd",
           "write_sbm"]
