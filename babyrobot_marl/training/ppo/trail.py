"""A robot's trail: which of the four cells next to it it has stood on this episode, and in what order.

A memoryless robot in a maze cannot tell a corridor it has walked from one ahead. With a trail
(``PPOConfig.trail``, ``--trail``) the policy keeps, per robot and episode, the last step at which
the robot stood on each cell, and its net reads, for each of the four moves (north, east, south,
west), what its trail says of the cell it leads to: no move there (0), never stood on (1), or its
place among the cells next to it the robot has stood on, from the one it left longest ago (2) to
the one it left last (up to 5). That is what the vertex ant walk needs (Wagner, Lindenbaum and
Bruckstein 1998: always step to a cell never visited, else to the neighbour left longest ago): it
covers any connected graph, and in a perfect maze it is a depth-first search, so a robot that reads
its trail can learn to find any exit it cannot see, in a maze of any size.

The trail lives in the policy, not the env: the trainer keeps one beside the batch engine's cells
(``Trails``), a bound ``WindowPolicy`` one for its robot (``Trail``); both mark the robot's cell
before each decision, so the rows the trainer learns from are the rows the bound policy reads.
"""

from __future__ import annotations

from typing import Any

import numpy as np

MOVES = 4  # north, east, south, west: actions 1 to 4
NO_MOVE, NEVER, OLDEST = 0, 1, 2  # what the trail says of a move's cell; OLDEST + k: the (k+1)-th left longest ago
KINDS = OLDEST + MOVES
TRAIL_VALUES = KINDS**MOVES  # distinct trails: one number of base KINDS, north's digit first
TRAIL_UNITS = MOVES * (KINDS - 1)  # the net's units: one per move and kind but NO_MOVE


def trail_values(times: np.ndarray) -> np.ndarray:
    """``(...,)`` trail numbers from the last-visit times ``(..., 4)`` of the cells each robot's moves lead
    to (-1: no move there, 0: never stood on)."""
    t = np.asarray(times, dtype=np.int64)
    seen = t > 0
    older = (seen[..., None, :] & (t[..., None, :] < t[..., :, None])).sum(axis=-1)  # cells left before this one
    kind = np.where(t < 0, NO_MOVE, np.where(seen, OLDEST + older, NEVER))
    return kind @ (KINDS ** np.arange(MOVES))


def trail_kinds(values: np.ndarray) -> np.ndarray:
    """``(N, 4)`` kinds (``NO_MOVE``, ``NEVER``, ``OLDEST`` + k) of trail numbers ``(N,)``: ``trail_values``' digits."""
    v = np.asarray(values, dtype=np.int64).reshape(-1, 1)
    return (v // KINDS ** np.arange(MOVES)) % KINDS


def neighbours(target: np.ndarray) -> np.ndarray:
    """``(n_cells, 4)``: the cell each move (north, east, south, west) leads to from each cell, -1
    where it leads nowhere (a wall, a blocked cell, the border): a compiled table's ``target``."""
    nb = np.asarray(target)[:, 1 : 1 + MOVES]
    return np.where(nb == np.arange(len(nb))[:, None], -1, nb)


class Trails:
    """The trainer's trails: for ``n_envs`` envs of ``n_robots`` on an atlas (``Atlas``), the last step at
    which each robot stood on each cell of its env's level (``(E, R, cells of the largest level)``)."""

    def __init__(self, atlas: Any, n_envs: int, n_robots: int):
        w = atlas.level.width
        self.nb = neighbours(atlas.table.target)
        self.base = atlas.tops * w  # each level's first cell in the atlas
        self.size = int(max(lv.height for lv in atlas.levels)) * w
        self.times = np.zeros((n_envs, n_robots, self.size), dtype=np.int32)
        self._slot = (np.arange(n_envs * n_robots, dtype=np.int64) * self.size).reshape(n_envs, n_robots)

    def restart(self, envs: np.ndarray) -> None:
        """``envs`` start new episodes: their robots have stood nowhere."""
        self.times[envs] = 0

    def values(self, batch: Any) -> np.ndarray:
        """Every robot's trail number ``(E, R)`` now, after marking the cells the racing robots stand on
        with the step they stand there at (the env's step count + 1)."""
        cells, base = batch.cells, self.base[batch.pool][:, None]
        flat = self.times.reshape(-1)
        here = self._slot + (cells - base)
        flat[here[batch.racing]] = np.broadcast_to(batch.t[:, None] + 1, cells.shape)[batch.racing]
        nb = self.nb[cells]  # (E, R, 4)
        at = np.where(nb >= 0, self._slot[..., None] + (nb - base[..., None]), 0)
        return trail_values(np.where(nb >= 0, flat[at], -1))


class Trail:
    """One robot's trail in one episode, for a bound policy: the last step it stood on each cell."""

    def __init__(self) -> None:
        self.times: dict[int, int] = {}
        self.t = 0

    def value(self, cell: int, target: np.ndarray) -> int:
        """Mark ``cell`` with the next step and return the trail number of its neighbours (``target``:
        the level's compiled ``target`` table)."""
        self.t += 1
        self.times[cell] = self.t
        nb = target[cell, 1 : 1 + MOVES]
        times = [self.times.get(int(c), 0) if c != cell else -1 for c in nb]
        return int(trail_values(np.array(times)))
