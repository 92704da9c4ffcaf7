"""The shortest-path robot: Dijkstra from the exits over the compiled table, ignoring skids.

A move's cost is one step, or ``1 / glass_pass_prob`` through a glass wall (the expected
number of tries). Ties go to the lowest action number, so the policy is deterministic.
"""

from __future__ import annotations

import heapq
from functools import lru_cache

import numpy as np

from ..core.actions import N_ACTIONS, Action
from ..core.table import Table


def distances(t: Table) -> np.ndarray:
    """Expected steps from each cell to the nearest exit (``inf`` where none is reachable)."""
    p = t.rules.glass_pass_prob
    glass_cost = 1.0 / p if p > 0 else np.inf
    into: list[list[tuple[int, float]]] = [[] for _ in range(t.n_cells)]  # reverse edges
    for c in range(t.n_cells):
        for a in range(1, N_ACTIONS):
            n = int(t.target[c, a])
            if n != c:
                into[n].append((c, glass_cost if t.glass[c, a] else 1.0))
    dist = np.full(t.n_cells, np.inf)
    heap = [(0.0, int(c)) for c in np.flatnonzero(t.is_exit)]
    for _, c in heap:
        dist[c] = 0.0
    while heap:
        d, c = heapq.heappop(heap)
        if d > dist[c]:
            continue
        for prev, cost in into[c]:
            if d + cost < dist[prev]:
                dist[prev] = d + cost
                heapq.heappush(heap, (d + cost, prev))
    return dist


def shortest_path_actions(t: Table) -> np.ndarray:
    """The action of the shortest-path robot in each cell (STAY on exits and dead ends)."""
    dist = distances(t)
    p = t.rules.glass_pass_prob
    glass_cost = 1.0 / p if p > 0 else np.inf
    cost = np.where(t.glass, glass_cost, 1.0) + dist[t.target]  # cost[c, a]
    cost[:, 0] = np.inf
    cost[t.target == np.arange(t.n_cells)[:, None]] = np.inf  # bumping never helps
    best = np.argmin(cost, axis=1)
    best[~np.isfinite(cost.min(axis=1)) | t.is_exit] = Action.STAY
    return best.astype(np.int64)


@lru_cache(maxsize=16)
def _shared_actions(t: Table) -> tuple[np.ndarray, list[int]]:
    """One search from the exits per table, shared by every shortest-path robot on it (read-only)."""
    actions = shortest_path_actions(t)
    actions.setflags(write=False)
    return actions, actions.tolist()


class ShortestPathPolicy:
    """Acts on an observation whose first two entries are the robot's own ``[x, y]``.

    Robots on one table share its action table: one Dijkstra from the exits for all of them."""

    name = "shortest"

    def __init__(self, table: Table):
        self.width = table.width
        self.actions, self._by_cell = _shared_actions(table)

    def __call__(self, obs) -> int:
        return self._by_cell[int(obs[1]) * self.width + int(obs[0])]

    act = __call__
