"""The level as a picture: floor tiles, puddles, blocks, walls, glass panes, start and exit.

``level_ops`` is the bottom layer (drawn once per level, cell size and theme); ``label_ops``
are the START / EXIT labels, drawn on the top layer so that no robot or arrow hides them. A
label is a word in a pill at the top of its cell when the word fits, else the cell keeps its
icon (a flag for a start, a door for an exit). Positions are pixels at ``cs`` pixels a cell.
"""

from __future__ import annotations

import numpy as np

from ..core.level import Cell, Level
from .glyphs import cap_height, fit, text_width
from .palette import Theme, robot_colour, tile_edge
from .shapes import Colour, Fill, Op, Text, blob, ellipse, rect, round_rect, segment, shade


def wall_width(cs: int) -> float:
    """Walls are an even number of pixels thick, centred on the cell edges: crisp at every size."""
    return float(max(2, 2 * round(cs * 0.045)))


def pane_width(cs: int) -> float:
    """Glass panes are wider than walls, whole pixels: the frame stays crisp."""
    return float(max(6, 2 * round(cs * 0.08)))


def border_depths(grid: tuple[int, int], cs: int) -> np.ndarray:
    """``edge_depths`` of a ``(height, width)`` grid with its border only."""
    depths = np.zeros((*grid, 4))
    depths[:, 0, 0] = depths[0, :, 1] = depths[:, -1, 2] = depths[-1, :, 3] = wall_width(cs)
    return depths


def edge_depths(level: Level, cs: int) -> np.ndarray:
    """``float64[H, W, 4]``: how far into each cell a wall reaches from its left, top, right and
    bottom edges, in pixels: the grid's border a whole wall width (it lies inside the image), an
    inner wall half its width, a glass pane half its own; 0 where the edge is open."""
    depths = border_depths((level.height, level.width), cs)
    for edges, depth in ((level.walls, wall_width(cs) / 2), (level.glass, pane_width(cs) / 2)):
        for a, b in edges:
            (x0, y0), (x1, y1) = sorted((a, b))
            sides = (2, 0) if y0 == y1 else (3, 1)  # the first cell's right (bottom) edge, the second's left (top)
            depths[y0, x0, sides[0]] = depths[y1, x1, sides[1]] = depth
    return depths


def level_ops(level: Level, cs: int, theme: Theme) -> list[Op]:
    """Everything of the level except its labels, bottom to top (the floor is the background)."""
    return floor_ops(level, cs, theme) + feature_ops(level, cs, theme)


def floor_ops(level: Level, cs: int, theme: Theme) -> list[Op]:
    """Tile lines, start and exit tiles: what value tints may cover (their flag and door are features)."""
    ops: list[Op] = []
    w, h = level.width * cs, level.height * cs
    line = max(1.0, cs / 48)
    for x in range(1, level.width):
        ops.append(Fill(rect(x * cs - line / 2, 0, x * cs + line / 2, h), theme.floor_line))
    for y in range(1, level.height):
        ops.append(Fill(rect(0, y * cs - line / 2, w, y * cs + line / 2), theme.floor_line))
    for cell in level.starts:
        ops += _tile(cell, cs, theme.start, tile_edge(theme, theme.start_ink))
    for cell in level.exits:
        ops += _tile(cell, cs, theme.exit, tile_edge(theme, theme.exit_ink))
    return ops


ICON_CORNER = 0.42  # with an overlay, a start's flag and an exit's door: this part of the cell, bottom right


def feature_ops(level: Level, cs: int, theme: Theme, corner: bool = False) -> list[Op]:
    """Start flags, exit doors, puddles, blocks, glass panes and walls: drawn over value tints, so
    they always show; ``corner``: the flags and doors small in their cells' bottom right corner
    (an overlay's numbers and arrows use the rest)."""
    ops: list[Op] = []
    w, h = level.width * cs, level.height * cs
    race = len(level.starts) > 1
    s = ICON_CORNER * cs if corner else float(cs)
    for i, cell in enumerate(level.starts):
        ops += _flag(*_icon_box(cell, cs, s), theme, robot_colour(theme, i) if race else None)
    for cell in level.exits:
        ops += _door(*_icon_box(cell, cs, s), theme)
    for cell in level.small_puddles:
        ops += _puddle(cell, cs, theme, large=False)
    for cell in level.large_puddles:
        ops += _puddle(cell, cs, theme, large=True)
    for cell in level.blocked:
        ops += _block(cell, cs, theme)
    t = wall_width(cs)
    for a, b in level.glass:
        ops += _pane(a, b, cs, theme)
    for a, b in level.walls:
        ops.append(Fill(_edge_rect(a, b, cs, t, t / 2), theme.wall))
    ops += [  # the outer border, inside the image
        Fill(rect(0, 0, w, t), theme.wall),
        Fill(rect(0, h - t, w, h), theme.wall),
        Fill(rect(0, 0, t, h), theme.wall),
        Fill(rect(w - t, 0, w, h), theme.wall),
    ]
    return ops


def _edge_rect(a: Cell, b: Cell, cs: int, thickness: float, overhang: float):
    """The strip along the edge between neighbour cells ``a`` and ``b``."""
    if a[1] == b[1]:  # side by side: a vertical strip at the right cell's left edge
        x = max(a[0], b[0]) * cs
        return rect(x - thickness / 2, a[1] * cs - overhang, x + thickness / 2, (a[1] + 1) * cs + overhang)
    y = max(a[1], b[1]) * cs
    return rect(a[0] * cs - overhang, y - thickness / 2, (a[0] + 1) * cs + overhang, y + thickness / 2)


def _pane(a: Cell, b: Cell, cs: int, theme: Theme) -> list[Op]:
    """A glass pane: a pale strip wider than a wall, framed, with a glint; it stops short of the corners."""
    t = pane_width(cs)
    frame = float(max(1, round(cs / 32)))
    inset = -wall_width(cs) / 2 - max(1.0, cs * 0.06)
    ops: list[Op] = [Fill(_edge_rect(a, b, cs, t, inset), theme.glass_frame)]
    ops.append(Fill(_edge_rect(a, b, cs, t - 2 * frame, inset - frame), theme.glass))
    # two short diagonal glints across the pane
    if a[1] == b[1]:
        x, y0 = max(a[0], b[0]) * cs, a[1] * cs
        for f in (0.3, 0.42):
            ops.append(
                Fill(segment(x - t / 2 + frame, y0 + (f + 0.1) * cs, x + t / 2 - frame, y0 + f * cs, frame), (255, 255, 255))
            )
    else:
        x0, y = a[0] * cs, max(a[1], b[1]) * cs
        for f in (0.3, 0.42):
            ops.append(
                Fill(segment(x0 + f * cs, y + t / 2 - frame, x0 + (f + 0.1) * cs, y - t / 2 + frame, frame), (255, 255, 255))
            )
    return ops


def _puddle(cell: Cell, cs: int, theme: Theme, large: bool) -> list[Op]:
    x, y = cell[0] * cs, cell[1] * cs
    phase = (cell[0] * 7 + cell[1] * 13) % 6
    if large:
        ops: list[Op] = [
            Fill(blob(x + 0.5 * cs, y + 0.54 * cs, 0.4 * cs, 0.3 * cs, phase), theme.large_puddle),
            Fill(blob(x + 0.78 * cs, y + 0.24 * cs, 0.1 * cs, 0.07 * cs, phase + 1), theme.large_puddle),
        ]
        ripples = ((0.4, 0.46, 0.14), (0.62, 0.66, 0.1))
    else:
        ops = [Fill(blob(x + 0.5 * cs, y + 0.6 * cs, 0.25 * cs, 0.16 * cs, phase), theme.small_puddle)]
        ripples = ((0.44, 0.56, 0.08),)
    for u, v, r in ripples:  # light ripples on the water
        ops.append(Fill(ellipse(x + u * cs, y + v * cs, r * cs, r * cs * 0.38), (255, 255, 255), 0.45))
    return ops


def _block(cell: Cell, cs: int, theme: Theme) -> list[Op]:
    x, y = cell[0] * cs, cell[1] * cs
    m, r = 0.07 * cs, 0.08 * cs
    edge = shade(theme.blocked, 0.7)
    ops: list[Op] = [
        Fill(round_rect(x + m, y + m, x + cs - m, y + cs - m, r), edge),
        Fill(round_rect(x + m * 1.6, y + m * 1.6, x + cs - m * 1.6, y + cs - m * 1.6, r * 0.7), theme.blocked),
        Fill(round_rect(x + 0.26 * cs, y + 0.26 * cs, x + 0.74 * cs, y + 0.74 * cs, r * 0.5), shade(theme.blocked, 1.12)),
    ]
    k = max(1.0, cs * 0.04)
    ops.append(Fill(segment(x + 0.26 * cs, y + 0.26 * cs, x + 0.74 * cs, y + 0.74 * cs, k), edge))
    ops.append(Fill(segment(x + 0.74 * cs, y + 0.26 * cs, x + 0.26 * cs, y + 0.74 * cs, k), edge))
    return ops


def tile_line(cs: int) -> float:
    """The width of the line round a start or exit tile: whole pixels, so it stays crisp."""
    return float(max(1, round(cs * 0.04)))


def _tile(cell: Cell, cs: int, colour: Colour, edge: Colour) -> list[Op]:
    """A start or exit tile, outlined in ``edge``: a pale tile still stands out from the floor."""
    m, e, r = max(1.0, cs * 0.03), tile_line(cs), cs * 0.08
    x0, y0, x1, y1 = cell[0] * cs + m, cell[1] * cs + m, (cell[0] + 1) * cs - m, (cell[1] + 1) * cs - m
    return [Fill(round_rect(x0, y0, x1, y1, r), edge), Fill(round_rect(x0 + e, y0 + e, x1 - e, y1 - e, max(0.0, r - e)), colour)]


def _icon_box(cell: Cell, cs: int, s: float) -> tuple[float, float, float]:
    """The top left corner and size of a cell's icon: the whole cell, or ``s`` pixels in its bottom right corner."""
    if s >= cs:
        return cell[0] * cs, cell[1] * cs, float(cs)
    m = wall_width(cs) / 2
    return (cell[0] + 1) * cs - m - s, (cell[1] + 1) * cs - m - s, s


def corner_icon_bounds(cell: Cell, cs: int) -> tuple[float, float, float, float]:
    """The pixels ``(x0, y0, x1, y1)`` a start's flag or an exit's door covers in its cell's
    corner (under an overlay): what an arrow must keep clear of."""
    x, y, s = _icon_box(cell, cs, ICON_CORNER * cs)
    return x + 0.32 * s, y + 0.3 * s, x + 0.68 * s, y + 0.88 * s


def _flag(x: float, y: float, cs: float, theme: Theme, colour: Colour | None) -> list[Op]:
    """A start's flag (in the robot's colour in a race) in the ``cs``-pixel box at ``(x, y)``."""
    flag = colour or theme.start_ink
    pole = max(1.0, cs * 0.04)
    # low in the box: a robot standing on its start (under the START label) hides all of it
    return [
        Fill(rect(x + 0.36 * cs, y + 0.42 * cs, x + 0.36 * cs + pole, y + 0.86 * cs), theme.start_ink),
        Fill(rect(x + 0.33 * cs, y + 0.84 * cs, x + 0.5 * cs, y + 0.88 * cs), theme.start_ink),
        Fill(rect(x + 0.36 * cs, y + 0.42 * cs, x + 0.68 * cs, y + 0.6 * cs), flag),
    ]


def _door(x: float, y: float, cs: float, theme: Theme) -> list[Op]:
    """An exit's open door in the ``cs``-pixel box at ``(x, y)``."""
    ink = theme.exit_ink
    return [
        Fill(round_rect(x + 0.32 * cs, y + 0.3 * cs, x + 0.68 * cs, y + 0.84 * cs, 0.06 * cs), ink),
        Fill(rect(x + 0.37 * cs, y + 0.35 * cs, x + 0.63 * cs, y + 0.84 * cs), shade(theme.exit, 1.35)),
        Fill(ellipse(x + 0.57 * cs, y + 0.6 * cs, 0.03 * cs, 0.03 * cs), ink),
    ]


def label_band(cs: int) -> tuple[float, float]:
    """The top band of a cell that labels use (pixels from the cell's top), inside the walls."""
    top = wall_width(cs) / 2 + 2
    return top, top + max(11.0, 0.22 * cs)


def label_ops(level: Level, cs: int, theme: Theme) -> list[Op]:
    """START / EXIT words in pills at the top of their cells, where they fit (else nothing: the icon shows)."""
    ops: list[Op] = []
    race = len(level.starts) > 1
    for i, cell in enumerate(level.starts):
        words = (f"START {i}", str(i)) if race else ("START",)
        ops += _pill(cell, cs, words, theme.label_bg if not race else robot_colour(theme, i), theme.label_text, theme)
    for cell in level.exits:
        ops += _pill(cell, cs, ("EXIT",), theme.label_bg, theme.label_text, theme)
    return ops


def _pill(cell: Cell, cs: int, words: tuple[str, ...], bg: Colour, fg: Colour, theme: Theme) -> list[Op]:
    top, bottom = label_band(cs)
    height = bottom - top
    for word in words:
        size = fit(word, cs - wall_width(cs) - 8, 0.6 * height, largest=22, smallest=7)
        if size is None:
            continue
        if len(word) <= 2 and size < 9:  # a lone digit this small is not worth a pill
            continue
        w = text_width(word, size) + 0.7 * cap_height(size)[1] * 2
        cx, cy = (cell[0] + 0.5) * cs, cell[1] * cs + (top + bottom) / 2
        w = min(w, cs - wall_width(cs) - 4)
        ink = theme.robot_ink if bg != theme.label_bg else fg
        text_colour = fg if bg == theme.label_bg else _readable_on(bg)
        return [
            Fill(round_rect(cx - w / 2 - 1, cy - height / 2 - 1, cx + w / 2 + 1, cy + height / 2 + 1, height / 2 + 1), ink),
            Fill(round_rect(cx - w / 2, cy - height / 2, cx + w / 2, cy + height / 2, height / 2), bg),
            Text(cx, cy, word, size, text_colour),
        ]
    return []


def _readable_on(bg: Colour) -> Colour:
    """Black or white, whichever reads better on ``bg``."""
    from .palette import contrast_ratio

    return (0, 0, 0) if contrast_ratio(bg, (0, 0, 0)) >= contrast_ratio(bg, (255, 255, 255)) else (255, 255, 255)
