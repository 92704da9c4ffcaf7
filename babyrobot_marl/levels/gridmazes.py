"""Grid mazes: mazes of blocked cells with loops and open patches, in the style of the maps that
multi-robot pathfinding benchmarks train and test on (POGEMA's maze generator, after PRIMAL2's).

``grid_maze(side, seed)`` grows wall segments from random posts (cells of even row and column): how
many posts follow from an obstacle density, each segment takes ``wall_components`` steps of two cells
and keeps its direction with probability ``go_straight``. The three are drawn per maze from the
maze's own seed (density 0..1, 1..8 components, 0.75..0.85), so a family mixes open rooms, long
corridors and dense mazes. Unlike ``mazes.maze`` (a perfect maze walled by edges), robots can pass
each other around loops; some cells may be cut off (own goals are drawn reachable from each start).
A grid maze has no exit: it is a level for ``goals="own"``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..core.level import Level
from .checks import check_maze_seed, check_maze_size

__all__ = ["grid_maze"]

_STEPS = ((0, -2), (2, 0), (0, 2), (-2, 0))  # a wall segment's steps: north, east, south, west


@lru_cache(maxsize=64)  # an atlas draws many; a 64x64 grid maze holds a few hundred kB
def grid_maze(side: int, seed: int = 0) -> Level:
    """A ``side`` x ``side`` grid maze of seed ``seed`` (no exit, no start)."""
    side, seed = check_maze_size(side, "side"), check_maze_seed(seed)
    rng = np.random.default_rng([seed, side])
    density, components, straight = rng.uniform(0.0, 1.0), int(rng.integers(1, 9)), rng.uniform(0.75, 0.85)
    n = side + 2  # with a blocked border, cropped at the end
    grid = np.zeros((n, n), dtype=bool)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = True
    for _ in range(int(n * n * density) // components):
        x, y = 2 * int(rng.integers(n // 2)), 2 * int(rng.integers(n // 2))
        grid[y, x] = True
        last = (0, 0)
        for _ in range(components):
            x, y, last = _grow(grid, x, y, last, straight, rng)
    ys, xs = np.nonzero(grid[1:-1, 1:-1])
    return Level(width=side, height=side, blocked=frozenset(zip(xs.tolist(), ys.tolist())), name=f"gridmaze-{side}-s{seed}")


def _grow(grid: np.ndarray, x: int, y: int, last: tuple[int, int], straight: float,
          rng: np.random.Generator) -> tuple[int, int, tuple[int, int]]:
    """One step of a wall segment from post ``(x, y)`` toward a post two cells away (straight on is
    ``straight`` likely against ``1 - straight`` for each turn): a free post is walled with the cell
    between and the segment goes on from it; a blocked one stops this step where it is."""
    n = grid.shape[0]
    steps = [(dx, dy) for dx, dy in _STEPS
             if (dx >= 0 or x > 1) and (dx <= 0 or x < n - 2) and (dy >= 0 or y > 1) and (dy <= 0 or y < n - 2)]
    weights = np.cumsum([straight if s == last else 1.0 - straight for s in steps])
    dx, dy = steps[int(np.searchsorted(weights, rng.random() * weights[-1], side="right"))]
    if grid[y + dy, x + dx]:
        return x, y, (dx, dy)
    grid[y + dy, x + dx] = grid[y + dy // 2, x + dx // 2] = True
    return x + dx, y + dy, (dx, dy)
