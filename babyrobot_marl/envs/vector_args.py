"""Argument checks and resets of the batch vector envs (``envs/vector.py``): pure functions over
a ``BatchRace`` and the env counts, so the Gymnasium and SB3 shells share them."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.batch import BatchRace
from ..core.checks import check_batch, check_int
from .common import ACTION_HELP, check_seed


def check_envs(n_envs: object, what: str, n_robots: object = 1, observe: object = "global") -> int:
    """A vector env's env count, checked against the batch limits (``checks.check_batch``) before
    any env exists: the "global" rows' size follows from ``n_robots`` alone (the batch engine
    checks the other modes' once their observer is built)."""
    n = check_int(n_envs, what, lo=1)
    try:
        robots = check_int(n_robots, "n_robots", lo=1)
    except ValueError:
        robots = 1  # the race env names a bad n_robots itself
    check_batch(n, robots, 3 * robots - 1 if observe == "global" and robots > 1 else 2, what)
    return n


def check_actions(actions: Any, n_envs: int, n_robots: int) -> np.ndarray:
    """``(n_envs, n_robots)`` actions, or a ``ValueError`` naming ``actions`` (nothing changes)."""
    a = np.asarray(actions)
    if a.shape != (n_envs * n_robots,):
        raise ValueError(f"actions: expected an array of shape ({n_envs * n_robots},), one action per env, got shape {a.shape}")
    if a.dtype.kind not in "iu":
        raise ValueError(f"actions: expected integer actions ({ACTION_HELP}), got dtype {a.dtype}")
    # one comparison: as unsigned, negative actions are huge
    if np.count_nonzero(a.view(np.uint64) >= N_ACTIONS if a.dtype == np.int64 else (a < 0) | (a >= N_ACTIONS)):
        k = int(np.flatnonzero((a < 0) | (a >= N_ACTIONS))[0])
        raise ValueError(f"actions: must be integers in 0..{N_ACTIONS - 1} ({ACTION_HELP}), got {a[k]} at index {k}")
    return a.astype(np.intp, copy=False).reshape(n_envs, n_robots)


def seed_list(seed: object, n: int) -> list[int | None]:
    """One seed (or None) per env from ``reset``'s ``seed`` argument."""
    if seed is None or isinstance(seed, (bool, np.bool_, float, int, np.integer, np.floating)):
        s = check_seed(seed)
        return [None if s is None else s + i for i in range(n)]
    if isinstance(seed, (str, bytes)) or not isinstance(seed, Sequence):
        raise ValueError(f"seed: expected None, an int or a list of {n} ints, got {type(seed).__name__}")
    if len(seed) != n:
        raise ValueError(f"seed: a list of seeds needs one per env ({n}), got {len(seed)}")
    return [check_seed(s, "seed: each seed") for s in seed]


def mask_envs(reset_mask: object, n_envs: int, n_robots: int) -> np.ndarray:
    """The envs to reset: all, or those of ``options["reset_mask"]`` (checked as ``SyncVectorEnv`` does)."""
    if reset_mask is None:
        return np.arange(n_envs)
    if not isinstance(reset_mask, np.ndarray):
        raise TypeError(f"options['reset_mask']: must be a numpy array, got {type(reset_mask).__name__}")
    if reset_mask.shape != (n_envs * n_robots,):
        raise ValueError(f"options['reset_mask']: must have shape ({n_envs * n_robots},), got {reset_mask.shape}")
    if reset_mask.dtype != np.bool_:
        raise TypeError(f"options['reset_mask']: must have dtype bool, got {reset_mask.dtype}")
    if not reset_mask.any():
        raise ValueError("options['reset_mask']: must contain at least one True value")
    per_env = reset_mask.reshape(n_envs, n_robots)
    if not (per_env == per_env[:, :1]).all():
        raise ValueError("options['reset_mask']: the slots of one race are reset together; mask all or none of them")
    return np.flatnonzero(per_env[:, 0])


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


SINGLE_ARGS = ("num_envs", "level", "rules", "max_steps", "start", "render_mode", "cell_size", "theme", "obs_encoding",
                "autoreset_mode")  # fmt: skip
RACE_ARGS = ("n_envs", "level", "n_robots", "collisions", "max_cycles", "start", "rules", "render_mode", "cell_size",
              "theme", "observe", "view_radius", "k", "obs_encoding", "autoreset_mode")  # fmt: skip
