"""A robot's trail: which of the four cells next to it it has stood on this episode, and in what order.

A memoryless robot in a maze cannot tell a corridor it has walked from one ahead. With a trail
(``PPOConfig.trail``, ``--trail``) the policy keeps, per robot and episode, the last step at which
the robot stood on each cell, and its net reads, for each of the four moves (north, east, south,
west), what its trail says of the cell it leads to: no move there (0), never stood on (1), or its
place among the cells next to it the robot has stood on, from the one it left longest ago (2) to
the one it left last (up to 5); and how many steps it has stood still (0 to 3: a robot pressing
into a wall or a robot sees its input change, so its choice can). That is what the vertex ant walk needs (Wagner, Lindenbaum and
Bruckstein 1998: always step to a cell never visited, else to the neighbour left longest ago): it
covers any connected graph, and in a perfect maze it is a depth-first search, so a robot that reads
its trail can learn to find any exit it cannot see, in a maze of any size.

The trail lives in the policy, not the env: the trainer keeps one beside the batch engine's cells
(``Trails``), a bound ``WindowPolicy`` one for its robot (``Trail``); both read the trail as it
stands with the robot's cell marked at this step, so the rows the trainer learns from are the rows the
bound policy reads.
"""

from __future__ import annotations

from typing import Any

import numpy as np

MOVES = 4  # north, east, south, west: actions 1 to 4
NO_MOVE, NEVER, OLDEST = 0, 1, 2  # what the trail says of a move's cell; OLDEST + k: the (k+1)-th left longest ago
KINDS = OLDEST + MOVES
STILL = 4  # steps stood still, 0 to 3 (3: three or more)
TRAIL_VALUES = KINDS**MOVES * STILL  # distinct trails: digits of base KINDS, north's first, then the steps stood still
TRAIL_UNITS = MOVES * (KINDS - 1) + STILL - 1  # the net's units: one per move and kind but NO_MOVE, one per still > 0


def trail_values(times: np.ndarray, still: np.ndarray | int = 0) -> np.ndarray:
    """``(...,)`` trail numbers from the last-visit times ``(..., 4)`` of the cells each robot's moves lead
    to (-1: no move there, 0: never stood on) and the steps each robot has stood ``still`` (capped at 3)."""
    t = np.asarray(times, dtype=np.int64)
    seen = t > 0
    older = (seen[..., None, :] & (t[..., None, :] < t[..., :, None])).sum(axis=-1)  # cells left before this one
    kind = np.where(t < 0, NO_MOVE, np.where(seen, OLDEST + older, NEVER))
    return kind @ (KINDS ** np.arange(MOVES)) + np.minimum(still, STILL - 1) * KINDS**MOVES


def trail_kinds(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``trail_values``' digits: the kinds ``(N, 4)`` (``NO_MOVE``, ``NEVER``, ``OLDEST`` + k) and the steps
    stood still ``(N,)`` of trail numbers ``(N,)``."""
    v = np.asarray(values, dtype=np.int64).reshape(-1, 1)
    return (v // KINDS ** np.arange(MOVES)) % KINDS, v[:, 0] // KINDS**MOVES


def neighbours(target: np.ndarray) -> np.ndarray:
    """``(n_cells, 4)``: the cell each move (north, east, south, west) leads to from each cell, -1
    where it leads nowhere (a wall, a blocked cell, the border): a compiled table's ``target``."""
    nb = np.asarray(target)[:, 1 : 1 + MOVES]
    return np.where(nb == np.arange(len(nb))[:, None], -1, nb)


class Trails:
    """The trainer's trails: for ``n_envs`` envs of ``n_robots`` on an atlas (``Atlas``), the last step at
    which each robot stood on each cell of its env's level (``(E, R, cells of the largest level)``), and
    how long each has stood still."""

    def __init__(self, atlas: Any, n_envs: int, n_robots: int):
        w = atlas.level.width
        self.nb = neighbours(atlas.table.target)
        self.base = atlas.tops * w  # each level's first cell in the atlas
        self.size = int(max(lv.height for lv in atlas.levels)) * w
        self.times = np.zeros((n_envs, n_robots, self.size), dtype=np.int32)
        self._slot = (np.arange(n_envs * n_robots, dtype=np.int64) * self.size).reshape(n_envs, n_robots)
        self.cell = np.full((n_envs, n_robots), -1, dtype=np.int64)  # where each robot stood at the last step read
        self.still = np.zeros((n_envs, n_robots), dtype=np.int64)
        self.step = np.zeros(n_envs, dtype=np.int64)  # the step last read, per env (0: none this episode)

    def restart(self, envs: np.ndarray) -> None:
        """``envs`` start new episodes: their robots have stood nowhere."""
        self.times[envs], self.cell[envs], self.still[envs], self.step[envs] = 0, -1, 0, 0

    def values(self, batch: Any) -> np.ndarray:
        """Every robot's trail number ``(E, R)`` now, the cells the racing robots stand on marked with the
        step they stand there at (the env's step count + 1); reading the same step again changes nothing."""
        cells, base, now = batch.cells, self.base[batch.pool][:, None], batch.t + 1
        new = (now != self.step)[:, None]
        self.still = np.where(new, np.where(cells == self.cell, np.minimum(self.still + 1, STILL - 1), 0), self.still)
        self.cell, self.step = np.where(new, cells, self.cell), now
        flat = self.times.reshape(-1)
        here = self._slot + (cells - base)
        flat[here[batch.racing]] = np.broadcast_to(now[:, None], cells.shape)[batch.racing]
        nb = self.nb[cells]  # (E, R, 4)
        at = np.where(nb >= 0, self._slot[..., None] + (nb - base[..., None]), 0)
        return trail_values(np.where(nb >= 0, flat[at], -1), self.still)


class Trail:
    """One robot's trail in one episode, for a bound policy: the last step it stood on each cell, and how
    long it has stood still. ``peek`` reads it as it would be with the robot's cell marked; ``mark`` marks
    that cell, once per step (reading changes nothing)."""

    def __init__(self) -> None:
        self.times: dict[int, int] = {}
        self.t, self.cell, self.still = 0, -1, 0
        self.here = -1  # the cell ``peek`` read last: ``mark`` marks it

    def _still(self, cell: int) -> int:
        return min(self.still + 1, STILL - 1) if cell == self.cell else 0

    def peek(self, x: int, y: int, table: Any) -> int:
        """The trail number of a robot at ``(x, y)`` on ``table`` (the level's compiled ``Table``)."""
        cell = self.here = int(y) * table.width + int(x)
        nb = table.target[cell, 1 : 1 + MOVES]
        times = [self.times.get(int(c), 0) if c != cell else -1 for c in nb]
        return int(trail_values(np.array(times), self._still(cell)))

    def mark(self) -> None:
        """The robot stands at this step on the cell ``peek`` read."""
        cell = self.here
        self.still, self.cell = self._still(cell), cell
        self.t += 1
        self.times[cell] = self.t
