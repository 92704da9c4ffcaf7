"""A mapping that keeps the entries used last: a window policy's cache of action probabilities."""

from __future__ import annotations

from collections import OrderedDict
from typing import Any


class LastUsed:
    """A mapping of at most ``size`` entries that drops the least recently used one: memory stays flat
    however many distinct inputs a long evaluation shows."""

    def __init__(self, size: int):
        self.size, self._data = size, OrderedDict()

    def __len__(self) -> int:
        return len(self._data)

    def get(self, key: bytes) -> Any:
        value = self._data.get(key)
        if value is not None:
            self._data.move_to_end(key)
        return value

    def put(self, key: bytes, value: Any) -> None:
        self._data[key] = value
        if len(self._data) > self.size:
            self._data.popitem(last=False)
