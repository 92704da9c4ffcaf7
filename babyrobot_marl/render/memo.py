"""Caches bounded by the bytes they hold, not by their number of entries.

The renderers keep what they drew (robots rasterised, cells with robots in them, panel strips,
lines of text) to draw it again for the price of a copy. An entry's size varies by thousands
between a 8-pixel and a 256-pixel cell, so a bound by count is no bound: every cache here is a
least-recently-used one bounded by ``max_bytes``, the arrays of its values counted. Their sum:
32 MB for the process (``paint.PATCH_BYTES``, ``sprites.SPRITE_BYTES``, ``glyphs.TEXT_BYTES``)
and 66 MB per ``RgbRenderer`` (``rgb.RENDERER_BYTES``).
"""

from __future__ import annotations

import functools
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

import numpy as np

__all__ = ["MB", "ByteCache", "byte_cached", "nbytes"]

MB = 1 << 20
ENTRY_BYTES = 256  # what an entry costs besides its arrays (its key, tuple and dict slot)

V = TypeVar("V")


def nbytes(value: Any) -> int:
    """The bytes of the numpy arrays in ``value`` (an array, a tuple or list of them, or an object
    whose fields are), each array counted by its own buffer; plus ``ENTRY_BYTES``."""
    total, todo, seen = ENTRY_BYTES, [value], set()
    while todo:
        v = todo.pop()
        if id(v) in seen:
            continue
        seen.add(id(v))
        if isinstance(v, np.ndarray):
            total += v.nbytes
        elif isinstance(v, (tuple, list)):
            todo.extend(v)
        elif hasattr(v, "__dict__") and not isinstance(v, type):
            todo.extend(vars(v).values())
    return total


class ByteCache(Generic[V]):
    """A least-recently-used map whose values hold at most ``max_bytes`` (``size(value)`` each,
    ``nbytes`` by default). A value larger than the whole bound is returned but not kept."""

    def __init__(self, max_bytes: int, size: Callable[[Any], int] = nbytes):
        self.max_bytes = int(max_bytes)
        self.size = size
        self.bytes = 0  # what the values held now count
        self._data: OrderedDict[Hashable, tuple[V, int]] = OrderedDict()

    def __len__(self) -> int:
        return len(self._data)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._data

    def get(self, key: Hashable) -> V | None:
        """The value kept for ``key`` (now the most recently used), or None."""
        hit = self._data.get(key)
        if hit is None:
            return None
        self._data.move_to_end(key)
        return hit[0]

    def put(self, key: Hashable, value: V) -> V:
        """Keep ``value`` for ``key``, dropping the least recently used values past the bound; returns it."""
        n = self.size(value)
        old = self._data.pop(key, None)
        if old is not None:
            self.bytes -= old[1]
        if n > self.max_bytes:
            return value
        self._data[key] = (value, n)
        self.bytes += n
        while self.bytes > self.max_bytes:
            _, (_, dropped) = self._data.popitem(last=False)
            self.bytes -= dropped
        return value

    def clear(self) -> None:
        self._data.clear()
        self.bytes = 0


def byte_cached(max_bytes: int, size: Callable[[Any], int] = nbytes) -> Callable[[Callable[..., V]], Callable[..., V]]:
    """``functools.lru_cache`` bounded by bytes: the function's results by its (hashable) arguments;
    ``f.cache`` is the ``ByteCache``."""

    def wrap(f: Callable[..., V]) -> Callable[..., V]:
        cache: ByteCache[V] = ByteCache(max_bytes, size)
        missing = object()

        @functools.wraps(f)
        def cached(*args: Any) -> V:
            hit = cache._data.get(args, missing)
            if hit is not missing:
                cache._data.move_to_end(args)
                return hit[0]  # type: ignore[index]
            return cache.put(args, f(*args))

        cached.cache = cache  # type: ignore[attr-defined]
        return cached

    return wrap
