"""The policy and the critic as tables over the inputs while the weights stay fixed: actions sampled per key in a rollout."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ...core.actions import N_ACTIONS
from ..deps import torch_module
from .inputs import Inputs
from .net import log_softmax

TABLE_LIMIT = 4096  # inputs up to which the net runs on every possible key instead of searching for the distinct ones


class PerKey:
    """``fn`` (the critic's values, or a policy's probabilities, on rows of input indices) per key, the
    net run once per distinct key: while the weights stay fixed, inputs that repeat cost nothing."""

    def __init__(self, inputs: Inputs, fn: Callable[[Any], Any]):
        self.inputs, self.fn = inputs, fn
        self.table = None
        if inputs.n_keys <= TABLE_LIMIT:
            self.table = self.run(np.arange(inputs.n_keys))

    def run(self, keys: np.ndarray) -> np.ndarray:
        torch = torch_module()
        with torch.no_grad():
            return self.fn(torch.from_numpy(self.inputs.rows(keys))).numpy()

    def __call__(self, keys: np.ndarray) -> np.ndarray:
        if self.table is not None:
            return self.table[keys]
        uniq, inv = np.unique(keys.reshape(-1), return_inverse=True)
        return self.run(uniq)[inv.reshape(keys.shape)]


class Remembered(PerKey):
    """``PerKey`` that keeps what it computed: over a rollout (the weights fixed) each key's values are computed
    the first time a robot meets it, not at every step it recurs."""

    def __init__(self, inputs: Inputs, fn: Callable[[Any], Any]):
        super().__init__(inputs, fn)
        self.known = np.zeros(0, dtype=np.int64)  # the keys computed so far, sorted
        self.slot = np.zeros(0, dtype=np.int64)  # each one's row of values
        self.values: np.ndarray | None = None  # rows past ``filled``: room for the next keys' values
        self.filled = 0

    def __call__(self, keys: np.ndarray) -> np.ndarray:
        if self.table is not None:
            return self.table[keys]
        uniq, inv = np.unique(keys.reshape(-1), return_inverse=True)
        at = np.minimum(np.searchsorted(self.known, uniq), max(len(self.known) - 1, 0))
        new = uniq if not len(self.known) else uniq[self.known[at] != uniq]
        if len(new):
            self._keep(new, self.run(new))
            at = np.searchsorted(self.known, uniq)
        return self.values[self.slot[at]][inv.reshape(keys.shape)]

    def _keep(self, new: np.ndarray, values: np.ndarray) -> None:
        """Keep ``values``, those of the sorted keys ``new`` (none known yet): their rows follow the last kept, and
        the keys go where they sort (each step adds a few to many: no growing copy or sort of all of them)."""
        start = self.filled
        if self.values is None or start + len(new) > len(self.values):  # room doubles: copying stays linear
            room = np.empty((2 * (start + len(new)), *values.shape[1:]), dtype=values.dtype)
            if self.values is not None:
                room[:start] = self.values[:start]
            self.values = room
        self.values[start : start + len(new)] = values
        self.filled = start + len(new)
        where = np.searchsorted(self.known, new)
        self.known = np.insert(self.known, where, new)
        self.slot = np.insert(self.slot, where, start + np.arange(len(new)))


class Sampler(PerKey):
    """Actions sampled from the actor's probabilities per key (a rollout)."""

    def __init__(self, inputs: Inputs, net: Any):
        super().__init__(inputs, lambda rows: log_softmax(net.actor(rows)))
        self.cdf = None if self.table is None else np.cumsum(np.exp(self.table), axis=1)

    def sample(self, keys: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """One action per key by inverse-CDF sampling (one uniform number each)."""
        if self.table is not None:
            cdf, at = self.cdf, keys
        else:
            uniq, at = np.unique(keys, return_inverse=True)
            cdf = np.cumsum(np.exp(self.run(uniq)), axis=1)
        u = rng.random((keys.size, 1))
        return np.minimum((u >= cdf[at]).sum(axis=1), N_ACTIONS - 1)


def sample_actions(p: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """One action per row of action probabilities ``p`` by inverse-CDF sampling (one uniform number each)."""
    return np.minimum((rng.random((len(p), 1)) >= np.cumsum(p, axis=1)).sum(axis=1), N_ACTIONS - 1)


def distinct_rows(inputs: Inputs, keys: np.ndarray) -> tuple[Any, Any]:
    """The distinct inputs among ``keys`` as the net's rows, and each key's row."""
    torch = torch_module()
    if inputs.n_keys <= 4 * keys.size + 65536:  # a map over every possible key: no sort
        uniq, inv = distinct_below(keys, inputs.n_keys)
    else:
        uniq, inv = np.unique(keys, return_inverse=True)
    return torch.from_numpy(inputs.rows(uniq)), torch.from_numpy(inv.reshape(-1))


def distinct_below(keys: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(keys, return_inverse=True)`` for keys below ``n``: a mark per number, no sort."""
    present = np.zeros(n, dtype=bool)
    present[keys] = True
    return np.flatnonzero(present), (np.cumsum(present) - 1)[keys]
