"""Own goals (``goals="own"``) in a family policy's input: where the robot's target lies in its window and
the hint toward it, and the window's walls read the same on walled mazes and on grid maps.

A robot with its own target reads, beside its window, the window's target channel (``race_v0``'s: the
target's cell, or the border cell its offset projects to) as one unit of ``n_window``, and with the
hint the actions that shorten its way to its own target (``core.goals.goal_hints``). Both change with
the robot's cell and target, so they are part of its key (``goal_part``), not of its window's pattern.

``closed_edges``: a maze of this package walls cells off by edges; a grid map (``Level.from_grid``,
POGEMA's maps) by blocked cells. Read as they come, a policy trained on one never saw the other. So an
own-goals window marks an edge as a wall where the neighbour across it (within the window) is blocked,
and gives blocked cells walls on every side, as cells outside the grid already have: a move is open in
the input exactly when the robot could make it.
"""

from __future__ import annotations

from collections import deque
from functools import lru_cache

import numpy as np

from ...core.actions import N_ACTIONS
from ...core.goals import GoalDistances, reach
from ...core.observe import EDGE, LOCAL_FEATURES, TERRAIN
from ...core.table import Table

_TERRAIN = LOCAL_FEATURES.index("terrain")
_SIDES = tuple(LOCAL_FEATURES.index(s) for s in ("north", "east", "south", "west"))
_STEPS = ((0, -1), (1, 0), (0, 1), (-1, 0))  # the neighbour across each side, as (dx, dy)
_BLOCKED, _WALL, _OPEN = TERRAIN["blocked"], EDGE["wall"], EDGE["open"]
HINT_VALUES = 1 << N_ACTIONS  # the hint's bits as one number


@lru_cache(maxsize=16)
def _across(radius: int) -> np.ndarray:
    """``(n_window, 4)``: the window cell across each side of each window cell (-1 outside the window)."""
    side = 2 * radius + 1
    out = np.full((side * side, 4), -1, dtype=np.int64)
    for y in range(side):
        for x in range(side):
            for s, (dx, dy) in enumerate(_STEPS):
                if 0 <= x + dx < side and 0 <= y + dy < side:
                    out[y * side + x, s] = (y + dy) * side + x + dx
    return out


def closed_edges(feats: np.ndarray, radius: int) -> np.ndarray:
    """Window features ``(N, n_window, 6)`` with every open edge toward a blocked window cell made a wall,
    and every side of a blocked cell a wall (a copy)."""
    f = np.array(feats, dtype=np.int64, copy=True)
    across = _across(radius)
    blocked = f[:, :, _TERRAIN] == _BLOCKED  # (N, W)
    padded = np.concatenate([blocked, np.zeros((len(f), 1), dtype=bool)], axis=1)  # index -1: not blocked
    for s, column in enumerate(_SIDES):
        shut = padded[:, across[:, s]] | blocked
        f[:, :, column] = np.where(shut & (f[:, :, column] == _OPEN), _WALL, f[:, :, column])
    return f


def target_units(cells: np.ndarray, goals: np.ndarray, width: int, radius: int) -> np.ndarray:
    """The window cell of each robot's target channel: the target's offset, each of ``dx``, ``dy`` clamped
    to ``-r..r`` (cells of one grid ``width`` wide)."""
    side = 2 * radius + 1
    dx = np.clip(goals % width - cells % width, -radius, radius)
    dy = np.clip(goals // width - cells // width, -radius, radius)
    return (dy + radius) * side + dx + radius


class AtlasDistances(GoalDistances):
    """Moves to a goal cell from the cells of its own part of a level (an atlas's maze), one breadth-first
    search per goal the first time it is asked for: rows as long as the largest part, not the atlas
    (an atlas of 64 mazes has 64 times the cells of one; found rows are kept as ``GoalDistances`` keeps them)."""

    def __init__(self, table: Table):
        r = reach(table)
        self.table, self._neighbours = table, r.neighbours
        comp = r.component
        self.local = np.zeros(table.n_cells + 1, dtype=np.int64)  # a cell's index within its part
        size = 1
        for k in np.unique(comp[comp >= 0]).tolist():
            ids = np.flatnonzero(comp == k)
            self.local[ids] = np.arange(len(ids))
            size = max(size, len(ids))
        self.local[-1] = size  # a column that is never a cell's: -1 there
        self.row_of = np.full(table.n_cells, -1, dtype=np.int64)
        self.rows = self._store = np.zeros((0, size + 1), dtype=np.int32)

    def _search(self, goal: int) -> np.ndarray:
        dist = np.full(self.rows.shape[1], -1, dtype=np.int32)
        local, nb = self.local, self._neighbours
        dist[local[goal]] = 0
        todo = deque([goal])
        while todo:
            c = todo.popleft()
            d = dist[local[c]] + 1
            for e in nb[c]:
                if dist[local[e]] < 0:
                    dist[local[e]] = d
                    todo.append(e)
        return dist

    def hint_values(self, cells: np.ndarray, goals: np.ndarray) -> np.ndarray:
        """The goal hint's bits as one number per robot (bit ``a``: action ``a`` shortens the way), as
        ``core.goals.goal_hints`` gives them on each maze alone."""
        rows = self.rows_for(goals)
        here = self.rows[rows, self.local[cells]][..., None]
        ahead = self.rows[rows[..., None], self.local[self.table.target[cells]]]
        bits = (ahead == here - 1) & (here > 0)
        return bits.astype(np.int64) @ (1 << np.arange(N_ACTIONS))
