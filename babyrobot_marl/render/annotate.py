"""Overlays as pictures: value tints and boxes, policy arrows, action values, cell text.

Laid out so each reads at a glance, per cell (``cs`` pixels):

- a state value: the cell tinted by the theme's colour map, the number in a dark box with
  light text (the same contrast on every tint) at the top of the cell (under a START / EXIT
  label);
- arrows: white with a dark edge, in the space under the value box (the whole cell without
  values), laid out by ``arrows.place_arrows``: tied actions are distinct arrows, each in its
  own lane, the shortest as long as the room allows; E and W arrows above the robot's corner
  (``ROBOT_TOP``), or right of it under a value box (``ROBOT_RIGHT``): none runs under it, nor
  over a start's flag, nor within ``GAP`` pixels of a number;
- action values: the four triangles tinted, each number centred in its own triangle, ``GAP``
  pixels clear of the walls and the label (``qlabels``); none in an exit (nothing is done there);
- text: in a box at the bottom of the cell.

Every number of one overlay has the same format (``Overlay.scale``), sized to the space it has
(``glyphs.fit``) and dropped, never clipped, where not even the smallest size fits (the tint
still shows it). All of it lies under the robots, which stand small in a corner while an
overlay is on (``robot.CORNER``), clear of every number.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..core.actions import Action
from .arrows import DIRECTIONS, Box, Lane, arrow, grow, place_arrows
from .glyphs import cap_height, fit, text_width
from .overlay import Overlay, Scale, format_value
from .palette import Theme, colour_map
from .picture import border_depths, corner_icon_bounds, wall_width
from .qlabels import GAP, RING, QLabel, cell_gap, clearance, q_labels
from .robot import CORNER
from .shapes import Fill, Op, Text, rect, round_rect

_TRIANGLES = {  # centre-to-corner triangles, cell units
    Action.NORTH: ((0.0, 0.0), (1.0, 0.0), (0.5, 0.5)),
    Action.EAST: ((1.0, 0.0), (1.0, 1.0), (0.5, 0.5)),
    Action.SOUTH: ((1.0, 1.0), (0.0, 1.0), (0.5, 0.5)),
    Action.WEST: ((0.0, 1.0), (0.0, 0.0), (0.5, 0.5)),
}
TEXT_BAND = (0.76, 0.97)  # cell text, at the bottom
ROBOT_RIGHT = CORNER[1] + 0.36 * CORNER[0]  # the right edge of a robot in its corner (arms out), cell units
ROBOT_TOP = CORNER[2] - 0.54 * CORNER[0]  # and its top (the antenna's tip)


def value_range(overlay: Overlay) -> Scale | None:
    """What the colour bar shows: the range the colour map spans, its label, the number format."""
    return overlay.scale


def tint_ops(overlay: Overlay, cs: int, theme: Theme, exits: frozenset = frozenset()) -> list[Op]:
    """The value tints: whole cells for state values, triangles for action values (none in ``exits``)."""
    ops: list[Op] = []
    m = wall_width(cs) / 2
    if overlay.values is not None:
        lo, hi = (value_range(overlay) or (0.0, 0.0))[:2]
        colours = colour_map(overlay.values, theme.colour_map, lo, hi)
        for y, x in zip(*np.nonzero(np.isfinite(overlay.values))):
            ops.append(
                Fill(rect(x * cs + m, y * cs + m, (x + 1) * cs - m, (y + 1) * cs - m), tuple(colours[y, x].tolist()), 0.82)
            )
    if overlay.q_values is not None:
        q = overlay.q_values[:, :, 1:]
        finite = q[np.isfinite(q)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
        colours = colour_map(q, theme.colour_map, lo, hi)
        for action, tri in _TRIANGLES.items():
            for y, x in zip(*np.nonzero(np.isfinite(overlay.q_values[:, :, action]))):
                if (int(x), int(y)) in exits:
                    continue
                pts = (np.array(tri) * (cs - 2 * m) + (x * cs + m, y * cs + m)).astype(np.float64)
                ops.append(Fill(pts, tuple(colours[y, x, action - 1].tolist()), 0.82))
    return ops


def ink_ops(overlay: Overlay, cs: int, theme: Theme, labelled: frozenset = frozenset(),
            exits: frozenset = frozenset(), icons: frozenset = frozenset(),
            depths: np.ndarray | None = None) -> list[Op]:  # fmt: skip
    """Arrows, value boxes, action-value numbers and cell text, in that order (all under the robots).

    ``labelled``: the cells whose top band holds a START / EXIT label (the numbers go below it);
    ``exits``: the exit cells (no action values there); ``icons``: the cells whose flag stands
    in their bottom right corner (no arrow covers it); ``depths``: how far walls reach into each
    cell (``picture.edge_depths``; by default a grid's without glass panes).
    """
    ops: list[Op] = []
    scale = overlay.scale
    fmt = scale.format if scale is not None else format_value
    shapes = [a.shape[:2] for a in (overlay.values, overlay.q_values, overlay.arrows) if a is not None]
    if depths is None:
        depths = border_depths(shapes[0] if shapes else (0, 0), cs)
    has_values = overlay.values is not None and bool(np.isfinite(overlay.values).any())
    layout = _box_layout(overlay.values, cs, fmt) if has_values else None  # type: ignore[arg-type]
    numbers = q_labels(overlay.q_values, cs, labelled, exits, fmt, depths) if overlay.q_values is not None else {}
    if overlay.arrows is not None:
        for y, x in zip(*np.nonzero(overlay.arrows[:, :, 1:].any(axis=2))):
            cell = (int(x), int(y))
            actions = [a for a in DIRECTIONS if overlay.arrows[y, x, a]]
            for tx, ty, dx, dy, length in _cell_arrows(actions, cell, depths, cs, layout, labelled, icons, numbers.get(cell, [])):
                ops += arrow(tx, ty, dx, dy, length, theme)
    best = overlay.arrows
    for (x, y), labels in numbers.items():  # the best actions' numbers stand out (their arrows are short)
        ops += [op for lb in labels for op in lb.ops(theme, best is not None and bool(best[y, x, lb.action]))]
    if layout is not None:
        ops += _value_boxes(overlay.values, cs, theme, layout, depths, labelled, fmt)  # type: ignore[arg-type]
    for (x, y), s in overlay.text.items():
        ops += _cell_text(s, x, y, cs, theme)
    return ops


def _cell_arrows(actions: list[int], cell: tuple[int, int], depths: np.ndarray, cs: int,
                 layout: tuple[int, float, float] | None, labelled: frozenset, icons: frozenset,
                 here: list[QLabel]) -> list[Lane]:  # fmt: skip
    """The lanes of one cell's arrows: in ``arrow_region``, clear of the robot's corner, of the
    numbers ``here`` (``GAP`` pixels from each, ring included) and of the flag in ``icons`` cells
    where there is room for it."""
    x, y = cell
    x0, y0, x1, y1 = arrow_region(cs, layout, cell in labelled, clearance(x, y, depths, cs, cell in labelled))
    if all(a in (Action.EAST, Action.WEST) for a in actions):  # clear of the robot's corner:
        if ROBOT_TOP * cs - y0 >= 0.4 * cs and not here:
            y1 = min(y1, ROBOT_TOP * cs)  # above it, as long as ever (no value box, no numbers)
        else:
            x0 = max(x0, ROBOT_RIGHT * cs)  # right of it (the W number is there anyway)
    ox, oy = x * cs, y * cs
    region = (ox + x0, oy + y0, ox + x1, oy + y1)
    gap = max(1.5, cell_gap(cs))  # from a number (its ring included): 2 pixels where they can be spared
    keep_out = [lb.box(gap + (RING if lb.action in actions else 0.0)) for lb in here]
    mx0, my0, mx1, my1 = region
    for lb in here:  # the middle the numbers leave free
        bx0, by0, bx1, by1 = lb.box(gap + RING)
        mx0, my0 = (max(mx0, bx1) if lb.action == Action.WEST else mx0), (max(my0, by1) if lb.action == Action.NORTH else my0)
        mx1, my1 = (min(mx1, bx0) if lb.action == Action.EAST else mx1), (min(my1, by0) if lb.action == Action.SOUTH else my1)
    if cell in icons:  # the flag, bottom right: beside it, unless that leaves an arrow a stub (small cells)
        flag = grow(corner_icon_bounds(cell, cs), GAP)
        lanes = place_arrows(actions, region, [*keep_out, flag], (mx0, my0, mx1, my1), settle=1.0)
        if lanes and min(lane[4] for lane in lanes) >= max(10.0, cs / 6):
            return lanes
    return place_arrows(actions, region, keep_out, (mx0, my0, mx1, my1))


def arrow_region(cs: int, layout: tuple[int, float, float] | None, labelled: bool, clear: Box | None = None) -> Box:
    """The part of a cell the arrows use, inside ``clear`` (``qlabels.clearance``; by default an
    inner cell's): under the value box, or under the label, or all of it."""
    left, top, right, bottom = clear if clear is not None else clearance(1, 1, border_depths((3, 3), cs), cs, labelled)
    if layout is not None:
        top = box_centre(top, layout) + layout[2] / 2 + GAP
    return left, top, cs - right, cs - bottom


def _box_layout(values: np.ndarray, cs: int, fmt: Callable[[float], str] = format_value) -> tuple[int, float, float] | None:
    """``(type size, box width, box height)``: one box size for the whole grid (the widest
    number's), so the picture stays calm; None where not even the smallest type fits (the box
    keeps ``GAP`` pixels from the grid's border)."""
    texts = [fmt(float(v)) for v in values[np.isfinite(values)]]
    inner = cs - 2 * wall_width(cs)
    room = cs - 2 * (wall_width(cs) + GAP)
    widest = max(texts, key=lambda s: text_width(s, 20))
    largest = 28
    while (size := fit(widest, inner * 0.84, cs * 0.17, largest=largest, smallest=7)) is not None:
        cap = cap_height(size)[1]
        width = text_width(widest, size) + cap * 0.9
        if width <= room:
            return size, width, cap * 1.9
        largest = size - 1
    return None


def box_centre(top: float, layout: tuple[int, float, float]) -> float:
    """The y of a value box's centre in its cell (pixels from the cell's top), ``top`` being
    the pixels kept free at the top (``qlabels.clearance``: the wall, or a label, and a gap)."""
    return top + layout[2] / 2


def _value_boxes(values: np.ndarray, cs: int, theme: Theme, layout: tuple[int, float, float] | None, depths: np.ndarray,
                 labelled: frozenset = frozenset(), fmt: Callable[[float], str] = format_value) -> list[Op]:  # fmt: skip
    if layout is None:
        return []
    size, bw, bh = layout
    texts = {c: fmt(float(values[c])) for c in zip(*np.nonzero(np.isfinite(values)))}
    ops: list[Op] = []
    for (y, x), s in texts.items():
        top = clearance(int(x), int(y), depths, cs, (int(x), int(y)) in labelled)[1]
        cx, cy = (x + 0.5) * cs, y * cs + box_centre(top, layout)
        ops.append(Fill(round_rect(cx - bw / 2, cy - bh / 2, cx + bw / 2, cy + bh / 2, bh * 0.3), theme.value_box, 0.86))
        ops.append(Text(cx, cy, s, size, theme.value_text))
    return ops


def _cell_text(s: str, x: int, y: int, cs: int, theme: Theme) -> list[Op]:
    top, bottom = TEXT_BAND
    inner = cs - 2 * wall_width(cs)
    size = fit(s, inner - 4, (bottom - top) * cs * 0.6, largest=22, smallest=7)
    if size is None:
        return []
    cap = cap_height(size)[1]
    w, h = text_width(s, size) + cap, cap * 1.8
    cx, cy = (x + 0.5) * cs, (y + (top + bottom) / 2) * cs - 1
    return [
        Fill(round_rect(cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2, h * 0.3), theme.value_box, 0.8),
        Text(cx, cy, s, size, theme.value_text),
    ]
