"""Shapes inside one cell, in cell units (0..1, y down), shared by ``rgb_array`` and the live canvas.

Both renderers draw the same polygons: the numpy one rasterises them once per cell size
(``cell_mask``), the canvas scales them to pixels and fills them.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..core.actions import Action

Polygon = tuple[tuple[float, float], ...]

ROBOT_RADIUS = 0.34  # a robot is a disc of this radius about its cell's centre

# Where overlay text is centred: a state value low in its cell, free text high (the robot's disc between).
VALUE_TEXT_CENTRE = (0.5, 0.8)
CELL_TEXT_CENTRE = (0.5, 0.2)

# The four triangles of a cell, centre to edge, one per move (action values are drawn in them).
TRIANGLES: dict[int, Polygon] = {
    Action.NORTH: ((0.0, 0.0), (1.0, 0.0), (0.5, 0.5)),
    Action.EAST: ((1.0, 0.0), (1.0, 1.0), (0.5, 0.5)),
    Action.SOUTH: ((1.0, 1.0), (0.0, 1.0), (0.5, 0.5)),
    Action.WEST: ((0.0, 1.0), (0.0, 0.0), (0.5, 0.5)),
}

# An arrow from the centre towards the east edge; the others are this one turned.
_ARROW_EAST: Polygon = ((0.5, 0.44), (0.72, 0.44), (0.72, 0.34), (0.9, 0.5), (0.72, 0.66), (0.72, 0.56), (0.5, 0.56))
_TURNS = {Action.EAST: 0, Action.SOUTH: 1, Action.WEST: 2, Action.NORTH: 3}  # quarter turns clockwise (y down)


def _turn(p: tuple[float, float], quarters: int) -> tuple[float, float]:
    x, y = p
    for _ in range(quarters):
        x, y = 1.0 - y, x  # a quarter turn clockwise about the cell centre, y pointing down
    return (x, y)


ARROWS: dict[int, Polygon] = {a: tuple(_turn(p, q) for p in _ARROW_EAST) for a, q in _TURNS.items()}

# Where the number of an action value sits (the middle of its triangle), in cell units.
TRIANGLE_LABELS: dict[int, tuple[float, float]] = {
    Action.NORTH: (0.5, 0.2),
    Action.EAST: (0.8, 0.5),
    Action.SOUTH: (0.5, 0.8),
    Action.WEST: (0.2, 0.5),
}


@lru_cache(maxsize=64)
def cell_mask(polygon: Polygon, cell_size: int) -> np.ndarray:
    """``bool[cell_size, cell_size]``: the pixels whose centres lie inside ``polygon`` (even-odd rule)."""
    centres = (np.arange(cell_size) + 0.5) / cell_size
    px, py = np.meshgrid(centres, centres)  # px[row, col] = x of column col
    inside = np.zeros((cell_size, cell_size), dtype=bool)
    n = len(polygon)
    for k in range(n):
        (x0, y0), (x1, y1) = polygon[k], polygon[(k + 1) % n]
        crosses = (y0 > py) != (y1 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
        inside ^= crosses & (px < x_at)
    inside.setflags(write=False)
    return inside


def scaled(polygon: Polygon, x: int, y: int, cell_size: int) -> list[tuple[float, float]]:
    """``polygon`` in canvas pixels for the cell ``(x, y)``."""
    return [(float((x + u) * cell_size), float((y + v) * cell_size)) for u, v in polygon]
