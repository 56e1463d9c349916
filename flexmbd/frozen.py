"""A mapping that cannot change and that pickles: the tables of a model and of run settings.

``types.MappingProxyType`` gives a read-only view, but it cannot be pickled, so a model
holding one could not be sent to a Dask worker or saved with its results.
:class:`FrozenMap` holds its own copy of the items and offers only the ``Mapping``
interface (reading, iterating, ``len``, ``==`` with any mapping).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import TypeVar

K = TypeVar("K")
V = TypeVar("V")


class FrozenMap(Mapping[K, V]):
    """An immutable mapping of a copy of ``items`` (a mapping or key-value pairs)."""

    __slots__ = ("_items",)
    _items: dict[K, V]

    def __init__(self, items=()) -> None:
        object.__setattr__(self, "_items", dict(items))

    def __getitem__(self, key: K) -> V:
        return self._items[key]

    def __iter__(self) -> Iterator[K]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __setattr__(self, name: str, value) -> None:
        raise AttributeError("a FrozenMap cannot change")

    def __reduce__(self):
        return type(self), (self._items,)

    def __repr__(self) -> str:
        return f"FrozenMap({self._items!r})"
