"""SPACAR input files (``.dat``), planar and spatial: reading, writing, the format."""

from .reader import DatFile, dat_from_text, read_dat
from .writer import dat_text, write_dat

__all__ = ["DatFile", "dat_from_text", "dat_text", "read_dat", "write_dat"]
