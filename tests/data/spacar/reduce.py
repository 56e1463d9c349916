"""Make this folder's reference numbers from SPACAR's own output files.

    python tests/data/spacar/reduce.py DIR

``DIR`` holds the public files named in SOURCE.md (``crosshinge.dat``, ``.sbd``, ``.sbm``,
``crosshinge_3.dat``, ``.sbd``, ``.sbm``, ``beamw.dat``, ``.sbd``, ``.sbm``, ``.ltv``,
``moment.dat``, ``.sbd``: the last two renamed from their repositories' names). Written
here: the models as flexmbd writes them (read from SPACAR Light's files and written back
by :func:`flexmbd.write_dat`), and per group (``crosshinge``, ``beamw``, ``moment``) a
``GROUP.npz`` of the records of SPACAR's output that the tests compare with, each as
``NAME.KIND.RECORD`` (``crosshinge_3.sbm.G0``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import flexmbd as fm

HERE = Path(__file__).resolve().parent
#: the records kept, by model and file kind
RECORDS = {
    "crosshinge": {"sbd": ("NX", "NE", "NDOF", "NDDO", "LNP", "LE", "LN", "IT", "T", "X", "XD",
                           "E", "DX", "DE", "FX", "FXT", "STIF"),
                   "sbm": ("M0", "K0", "N0", "G0")},
    # BEAMW elements in mode 9: their tables and the mode's records
    "beamw": {"sbd": ("NXP", "NEP", "LE", "IT", "RL0", "RXYZ", "RQ", "STIF"),
              "sbm": ("NDOF", "NKDO", "NNOM", "B0"),
              "ltv": ("NX", "NU", "NY", "NNOM", "NYS", "DFT", "X0", "C", "D", "U0", "Y0")},
    # a moment on a rotational node: SPACAR's FX on its Euler parameters
    "moment": {"sbd": ("LNP", "X", "FX", "FXT")},
}
RECORDS["crosshinge_3"] = RECORDS["crosshinge"]
#: the models of each group's file
GROUPS = {"crosshinge": ("crosshinge", "crosshinge_3"), "beamw": ("beamw",),
          "moment": ("moment",)}


def main(source: Path) -> None:
    for group, names in GROUPS.items():
        arrays = {}
        for name in names:
            model, run = fm.read_dat(source / f"{name}.dat")
            fm.write_dat(model, HERE / f"{name}.dat", run)
            for kind, records in RECORDS[name].items():
                spacar = fm.read_sbd(source / f"{name}.{kind}")
                for record in records:
                    if record in spacar:
                        arrays[f"{name}.{kind}.{record}"] = np.asarray(spacar[record])
        np.savez_compressed(HERE / f"{group}.npz", **arrays)
        print(f"wrote {len(arrays)} records to {HERE / f'{group}.npz'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
