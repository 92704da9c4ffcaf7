"""The batch engine beside the envs it copies, for tests that step both alike."""

from __future__ import annotations

from typing import Any


def batch_beside(envs: list[Any], seed0: int) -> Any:
    """A batch engine of ``len(envs)`` races of ``envs[0]``'s kind; its race ``i`` and ``envs[i]`` reset with seed
    ``seed0 + i``, so that the same actions play the same races."""
    batch = envs[0].batch(len(envs))
    batch.seed([seed0 + i for i in range(len(envs))])
    batch.reset_envs(range(len(envs)))
    for i, env in enumerate(envs):
        env.reset(seed=seed0 + i)
    return batch
