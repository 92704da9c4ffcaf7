"""The random robot: a uniformly random action each step, from its own seeded generator."""

from __future__ import annotations

import numpy as np

from ..core.actions import N_ACTIONS


class RandomPolicy:
    """Uniform over the five actions (STAY included); ``seed`` makes it repeatable."""

    name = "random"

    def __init__(self, seed: int | None | np.random.Generator = None):
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)

    def __call__(self, obs=None) -> int:
        return int(self.rng.integers(N_ACTIONS))

    act = __call__
