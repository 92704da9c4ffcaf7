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

from .actions import N_ACTIONS
from .outcomes import BUMPED, GLASS, MOVED, OUTCOMES, SKIDDED, STAYED
from .rng import SLOT_GLASS, SLOT_SKID, SLOT_SKID_DIRECTION, uniform, uniform_array
from .table import Table, TableLists

__all__ = ["BUMPED", "GLASS", "MOVED", "OUTCOMES", "SKIDDED", "STAYED", "move", "move_array", "move_drawn"]

_SLOT_COLUMN = np.array([[SLOT_SKID], [SLOT_SKID_DIRECTION], [SLOT_GLASS]], dtype=np.uint64)  # row i: slot i


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
    """``move`` over arrays: ``cells``, ``actions``, ``counts`` share a shape, ``keys`` broadcasts.

    Outcomes that need no draw come from one look-up in ``t.sure_flat``; the rest (robots on
    puddles or at glass walls) are drawn by ``move_drawn``, on those elements only.
    """
    idx = cells * N_ACTIONS + actions
    sure_next, sure_code = t.sure_flat
    dest, outcome = sure_next.take(idx), sure_code.take(idx)
    draw = dest < 0
    if np.count_nonzero(draw):  # (count_nonzero costs a fraction of .any() on short arrays)
        k = np.nonzero(draw)
        dest[k], outcome[k] = move_drawn(t, idx[k], cells[k], np.broadcast_to(keys, cells.shape)[k], counts[k])
    return dest, outcome


def move_drawn(
    t: Table, idx: np.ndarray, cells: np.ndarray, keys: np.ndarray, counts: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``move`` over 1-D arrays of robots whose step may draw (``idx = cell * 5 + action``)."""
    f = t.flat
    # the three numbers a step may read, drawn in one call (rows: skid, skid direction, glass)
    u = uniform_array(keys, counts + _SLOT_COLUMN)
    dest, outcome = f.target.take(idx), f.code.take(idx)
    skids = u[SLOT_SKID] >= f.move_prob.take(idx)  # never where move_prob is 1
    fail = f.glass.take(idx) & (u[SLOT_GLASS] >= t.rules.glass_pass_prob) & ~skids
    if np.count_nonzero(fail):
        dest[fail] = cells[fail]
        outcome[fail] = GLASS
    if np.count_nonzero(skids):
        s = idx[skids]
        k = (u[SLOT_SKID_DIRECTION, skids] * f.n_skid.take(s)).astype(np.int64)
        dest[skids] = f.skid[s, np.minimum(k, f.skid.shape[1] - 1)]  # no open neighbour: padded with the cell
        outcome[skids] = SKIDDED
    return dest, outcome
