"""The step of one robot, before robots interact: table look-ups and counter-based draws.

Two forms of the same function: ``move`` for one robot in pure Python (an env stepping one
robot spends less time in it than in one numpy call), and ``move_array`` over arrays of any
shape, e.g. ``(n_envs, n_robots)``, for batches. A test holds them to the same results.

A robot at cell ``c`` taking action ``a``:

1. ``a == STAY``: it stays (outcome STAYED). STAY never skids.
2. on a puddle, with probability ``1 - move_prob[c]`` it skids to one of the other open
   neighbours (uniformly; it stays if there are none) and the step ends (SKIDDED).
3. a move into a wall, a blocked cell or the border leaves it where it is (BUMPED).
4. a move through a glass wall fails with probability ``1 - glass_pass_prob`` (GLASS).
5. otherwise it reaches ``target[c, a]`` (MOVED).

The random numbers come from ``rng.uniform(key, counter)``, at the addresses of ``rng``'s slots.
"""

from __future__ import annotations

import numpy as np

from .rng import SLOT_GLASS, SLOT_SKID, SLOT_SKID_DIRECTION, uniform, uniform_array
from .table import Table, TableLists

MOVED, STAYED, BUMPED, SKIDDED, GLASS = range(5)  # MOVED and STAYED first: 'intended' is <= STAYED
OUTCOMES = ("moved", "stayed", "bumped", "skidded", "glass")


def move(t: TableLists, cell: int, action: int, key: int, count: int) -> tuple[int, int]:
    """One robot's next cell and outcome code; ``count`` is the address of its slot 0."""
    sure = t.sure[cell][action]
    if sure is not None:  # no puddle, no glass on the way: the table knows the answer
        return sure
    p = t.move_prob[cell]
    if p < 1.0 and uniform(key, count + SLOT_SKID) >= p:
        alts = t.skid[cell][action]
        if not alts:
            return cell, SKIDDED
        return alts[int(uniform(key, count + SLOT_SKID_DIRECTION) * len(alts))], SKIDDED
    dest = t.target[cell][action]
    if dest == cell:
        return cell, BUMPED
    if t.glass[cell][action] and uniform(key, count + SLOT_GLASS) >= t.glass_pass_prob:
        return cell, GLASS
    return dest, MOVED


def move_array(
    t: Table, cells: np.ndarray, actions: np.ndarray, keys: np.ndarray, counts: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``move`` over arrays: ``cells``, ``actions``, ``counts`` share a shape, ``keys`` broadcasts."""
    dest = t.target[cells, actions]
    outcome = np.where(actions == 0, STAYED, np.where(dest == cells, BUMPED, MOVED))
    on_glass = t.glass[cells, actions]
    if on_glass.any():
        fail = on_glass & (uniform_array(keys, counts + SLOT_GLASS) >= t.rules.glass_pass_prob)
        dest = np.where(fail, cells, dest)
        outcome = np.where(fail, GLASS, outcome)
    p = t.move_prob[cells]
    may_skid = (actions != 0) & (p < 1.0)
    if may_skid.any():
        skids = may_skid & (uniform_array(keys, counts + SLOT_SKID) >= p)
        n = t.n_skid[cells, actions]
        k = (uniform_array(keys, counts + SLOT_SKID_DIRECTION) * n).astype(np.int64)
        dest = np.where(skids, t.skid[cells, actions, np.minimum(k, t.skid.shape[2] - 1)], dest)
        outcome = np.where(skids, SKIDDED, outcome)
    return dest, outcome
