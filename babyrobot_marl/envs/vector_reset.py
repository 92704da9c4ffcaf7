"""Resets of the batch vector envs (``vector.py``, ``sb3.py``): pure functions over a ``BatchRace``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core.batch import BatchRace


def restart(b: BatchRace, envs: np.ndarray | Sequence[int], starts: Sequence[tuple[int, ...] | None] | None) -> None:
    """New episodes in ``envs``; ``starts[k]``, when given, are env ``envs[k]``'s start cells.

    Given starts draw only the episode key, as the single envs' start options do: the batch
    is briefly told to use those cells as fixed level starts.
    """
    if starts is None or all(s is None for s in starts):
        b.reset_envs(envs)
        return
    envs = np.asarray(envs)
    for s in set(starts):
        group = envs[[k for k, t in enumerate(starts) if t == s]]
        if s is None:
            b.reset_envs(group)
            continue
        saved = b.start, b.fixed
        b.start, b.fixed = "level", np.array(s, dtype=np.int64)
        try:
            b.reset_envs(group)
        finally:
            b.start, b.fixed = saved


def seed_envs(b: BatchRace, seeds: Sequence[tuple[int, int | None]]) -> None:
    """Give env ``i`` the generator ``reset(seed=s)`` gives a single env (``None``: keep it)."""
    for i, s in seeds:
        if s is not None:
            b.generators[i] = np.random.default_rng(s)
