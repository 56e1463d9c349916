"""SPACAR input files (``.dat``), planar subset: reading, writing, the format."""

from .reader import model_from_text, read_dat
from .writer import dat_text, write_dat

__all__ = ["dat_text", "model_from_text", "read_dat", "write_dat"]
