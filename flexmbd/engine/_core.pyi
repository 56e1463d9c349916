# The compiled core (csrc/module.c), seen by type checkers: its names are typed Any.
from typing import Any

def __getattr__(name: str) -> Any: ...
