"""Observation encodings: the same ``MultiDiscrete`` integers in the form a learning library takes.

Every env (single, race, race-gym, vector envs) takes ``obs_encoding=``:

| ``obs_encoding``            | space                                   | an observation ``[x, y]`` on a 5x4 grid    |
|-----------------------------|-----------------------------------------|--------------------------------------------|
| ``"multidiscrete"`` default | ``MultiDiscrete(nvec)``, int64          | ``[3, 1]``                                 |
| ``"box"``                   | ``Box(0, nvec - 1)``, float32           | ``[3., 1.]``                               |
| ``"onehot"``                | ``Box(0, 1, (sum(nvec),))``, float32    | ``[0,0,0,1,0, 0,1,0,0]``: one 1 per entry |

``"box"`` suits libraries that only take ``Box`` spaces (SuperSuit's observation wrappers,
AgileRL, BenchMARL's MLPs, RLlib's default encoders); ``"onehot"`` is what a network learns
from fastest on a grid: entry ``i`` of value ``v`` becomes a 1 at ``sum(nvec[:i]) + v``.

``Encoder`` encodes any 1-d ``MultiDiscrete`` (so any observation mode of the race gets the
encodings too), over arrays of any leading shape: ``(L,)``, ``(n_agents, L)``, ``(n_envs, L)``.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from ..core.checks import check_choice

ENCODINGS = ("multidiscrete", "box", "onehot")

__all__ = ["ENCODINGS", "Encoder"]


class Encoder:
    """Encodes observations of ``MultiDiscrete(nvec)`` as ``encoding`` (see the module table)."""

    def __init__(self, nvec: np.ndarray | list[int], encoding: str = "multidiscrete"):
        self.encoding: str = check_choice(encoding, "obs_encoding", ENCODINGS)
        self.nvec = np.asarray(nvec, dtype=np.int64).reshape(-1)
        self.identity = self.encoding == "multidiscrete"
        if self.encoding == "multidiscrete":
            self.space: spaces.Space = spaces.MultiDiscrete(self.nvec)
        elif self.encoding == "box":
            self.space = spaces.Box(0.0, (self.nvec - 1).astype(np.float32), shape=self.nvec.shape, dtype=np.float32)
        else:
            self.space = spaces.Box(0.0, 1.0, shape=(int(self.nvec.sum()),), dtype=np.float32)
        # where each entry's one-hot block begins
        self._offsets = np.concatenate([[0], np.cumsum(self.nvec)[:-1]]).astype(np.int64)
        self._width = int(self.nvec.sum())

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        """``obs`` (..., L) integers -> the encoded array (..., L) or (..., sum(nvec)); a new array."""
        if self.identity:
            return obs
        if self.encoding == "box":
            return obs.astype(np.float32)
        lead = obs.shape[:-1]
        flat = obs.reshape(-1, obs.shape[-1])
        out = np.zeros((flat.shape[0], self._width), dtype=np.float32)
        rows = np.arange(flat.shape[0])[:, None]
        out[rows, flat + self._offsets] = 1.0
        return out.reshape(*lead, self._width)

    def decode(self, obs: np.ndarray) -> np.ndarray:
        """One encoded observation (1-d, of this encoding's length) back to its ``MultiDiscrete``
        integers: ``__call__`` undone; a ``ValueError`` for what no observation encodes to."""
        if self.encoding == "onehot":
            ones = np.flatnonzero(obs > 0.5)
            entry = np.searchsorted(self._offsets, ones, side="right") - 1  # the entry of each 1
            if len(ones) != len(self.nvec) or np.any(entry != np.arange(len(ones))):
                raise ValueError("obs: not an obs_encoding='onehot' observation (one 1 per entry)")
            return ones - self._offsets
        ints = np.rint(obs).astype(np.int64)
        if np.any(ints != obs) or np.any(ints < 0) or np.any(ints >= self.nvec):
            raise ValueError(f"obs: not an observation of this env (obs_encoding={self.encoding!r}): values off its space")
        return ints

    def __repr__(self) -> str:
        return f"Encoder({self.nvec.tolist()}, {self.encoding!r})"
