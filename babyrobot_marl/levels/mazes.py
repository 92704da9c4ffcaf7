"""A seeded maze generator: ``maze(w, h, seed)`` makes a perfect maze (randomized depth-first
search: one path between any two cells), start top left, exit bottom right."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..core.level import Level
from .checks import MAX_MAZE_SIDE, check_maze_seed, check_maze_size

__all__ = ["MAX_MAZE_SIDE", "maze"]


@lru_cache(maxsize=8)  # bounded: a 256x256 maze holds about 20 MB, and any size and seed may be asked for
def _maze(width: int, height: int, seed: int, name: str) -> Level:
    return maze(width, height, seed, name=name)


def maze(width: int, height: int, seed: int = 0, name: str = "") -> Level:
    """A perfect maze by randomized depth-first search: start top left, exit bottom right."""
    width, height = check_maze_size(width, "width"), check_maze_size(height, "height")
    seed = check_maze_seed(seed)
    if width * height < 2:
        raise ValueError(f"width, height: a maze needs at least 2 cells for a start and an exit, got {width}x{height}")
    rng = np.random.default_rng(seed)
    open_edges: set[tuple[tuple[int, int], tuple[int, int]]] = set()
    seen = {(0, 0)}
    stack = [(0, 0)]
    while stack:
        x, y = stack[-1]
        nbrs = [
            (nx, ny)
            for nx, ny in ((x, y - 1), (x + 1, y), (x, y + 1), (x - 1, y))
            if 0 <= nx < width and 0 <= ny < height and (nx, ny) not in seen
        ]
        if not nbrs:
            stack.pop()
            continue
        nxt = nbrs[int(rng.integers(len(nbrs)))]
        open_edges.add(((x, y), nxt) if (x, y) < nxt else (nxt, (x, y)))
        seen.add(nxt)
        stack.append(nxt)
    walls = set()
    for y in range(height):
        for x in range(width):
            for n in ((x + 1, y), (x, y + 1)):
                if n[0] < width and n[1] < height and ((x, y), n) not in open_edges:
                    walls.add(((x, y), n))
    return Level(
        width=width,
        height=height,
        walls=frozenset(walls),
        starts=((0, 0),),
        exits=frozenset({(width - 1, height - 1)}),
        name=name or f"maze-{width}x{height}" + (f"-s{seed}" if seed else ""),
    )
