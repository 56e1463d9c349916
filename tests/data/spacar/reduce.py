"""Make this folder's reference numbers from SPACAR's own output files.

    python tests/data/spacar/reduce.py DIR

``DIR`` holds the public files named in SOURCE.md (``crosshinge.dat``, ``.sbd``, ``.sbm``,
``crosshinge_3.dat``, ``.sbd``, ``.sbm``). Written here: the two models as flexmbd writes
them (``crosshinge.dat``, ``crosshinge_3.dat``, read from SPACAR Light's files and written
back by :func:`flexmbd.write_dat`), and ``crosshinge.npz``, the records of SPACAR's output
that the tests compare with, each as ``NAME.KIND.RECORD`` (``crosshinge_3.sbm.G0``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import flexmbd as fm

HERE = Path(__file__).resolve().parent
#: the records kept, by file kind
RECORDS = {"sbd": ("NX", "NE", "NDOF", "NDDO", "LNP", "LE", "LN", "IT", "T", "X", "XD", "E",
                   "DX", "DE", "FX", "FXT", "STIF"),
           "sbm": ("M0", "K0", "N0", "G0")}


def main(source: Path) -> None:
    arrays = {}
    for name in ("crosshinge", "crosshinge_3"):
        model, run = fm.read_dat(source / f"{name}.dat")
        fm.write_dat(model, HERE / f"{name}.dat", run)
        for kind, records in RECORDS.items():
            spacar = fm.read_sbd(source / f"{name}.{kind}")
            for record in records:
                if record in spacar:
                    arrays[f"{name}.{kind}.{record}"] = np.asarray(spacar[record])
    np.savez_compressed(HERE / "crosshinge.npz", **arrays)
    print(f"wrote {len(arrays)} records to {HERE / 'crosshinge.npz'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
