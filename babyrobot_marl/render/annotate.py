"""Overlays as pictures: value tints and boxes, policy arrows, action values, cell text.

Laid out so each reads at a glance, per cell (``cs`` pixels):

- a state value: the cell tinted by the theme's colour map, the number in a dark box with
  light text (the same contrast on every tint) at the top of the cell (under a START / EXIT
  label);
- arrows: white with a dark edge, at least a third of the cell long, in the space under the
  value box (the whole cell without values); tied actions are distinct arrows, each in its own
  lane (``arrow_lanes``), never drawn from one point; E and W arrows above the robot's corner
  (``ROBOT_TOP``), or right of it under a value box (``ROBOT_RIGHT``): none runs under it;
- action values: the four triangles tinted, each number centred in its own triangle, clear of
  the walls and the label; none in an exit (nothing is done there);
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
from .glyphs import cap_height, fit, text_width
from .overlay import Overlay, Scale, format_value
from .palette import Theme, colour_map
from .picture import label_band, wall_width
from .robot import CORNER
from .shapes import Fill, Op, Points, Text, rect, round_rect

DIRECTIONS = {Action.NORTH: (0.0, -1.0), Action.EAST: (1.0, 0.0), Action.SOUTH: (0.0, 1.0), Action.WEST: (-1.0, 0.0)}
_TRIANGLES = {  # centre-to-corner triangles, cell units
    Action.NORTH: ((0.0, 0.0), (1.0, 0.0), (0.5, 0.5)),
    Action.EAST: ((1.0, 0.0), (1.0, 1.0), (0.5, 0.5)),
    Action.SOUTH: ((1.0, 1.0), (0.0, 1.0), (0.5, 0.5)),
    Action.WEST: ((0.0, 1.0), (0.0, 0.0), (0.5, 0.5)),
}
TEXT_BAND = (0.76, 0.97)  # cell text, at the bottom
Box = tuple[float, float, float, float]  # x0, y0, x1, y1: pixels in a cell
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
            exits: frozenset = frozenset()) -> list[Op]:  # fmt: skip
    """Arrows, value boxes, action-value numbers and cell text, in that order (all under the robots).

    ``labelled``: the cells whose top band holds a START / EXIT label (the numbers go below it);
    ``exits``: the exit cells (no action values there).
    """
    ops: list[Op] = []
    scale = overlay.scale
    fmt = scale.format if scale is not None else format_value
    has_values = overlay.values is not None and bool(np.isfinite(overlay.values).any())
    layout = _box_layout(overlay.values, cs, fmt) if has_values else None  # type: ignore[arg-type]
    if overlay.arrows is not None:
        for y, x in zip(*np.nonzero(overlay.arrows[:, :, 1:].any(axis=2))):
            actions = [a for a in DIRECTIONS if overlay.arrows[y, x, a]]
            x0, y0, x1, y1 = arrow_region(cs, layout, (int(x), int(y)) in labelled)
            if all(a in (Action.EAST, Action.WEST) for a in actions):  # clear of the robot's corner:
                if ROBOT_TOP * cs - y0 >= 0.4 * cs:
                    y1 = min(y1, ROBOT_TOP * cs)  # above it, as long as ever (no value box)
                else:
                    x0 = max(x0, ROBOT_RIGHT * cs)  # right of it (under a value box)
            region = (x * cs + x0, y * cs + y0, x * cs + x1, y * cs + y1)
            for tx, ty, dx, dy, length in arrow_lanes(actions, region):
                ops += arrow(tx, ty, dx, dy, length, theme)
    if overlay.q_values is not None:
        ops += _q_numbers(overlay.q_values, cs, theme, labelled, exits, fmt)
    if layout is not None:
        ops += _value_boxes(overlay.values, cs, theme, layout, labelled, fmt)  # type: ignore[arg-type]
    for (x, y), s in overlay.text.items():
        ops += _cell_text(s, x, y, cs, theme)
    return ops


def arrow_region(cs: int, layout: tuple[int, float, float] | None, labelled: bool) -> Box:
    """The part of a cell the arrows use: under the value box, or under the label, or all of it."""
    m = wall_width(cs) / 2 + 2
    top = label_band(cs)[1] + 1 if labelled else m
    if layout is not None:
        top = box_centre(cs, layout, labelled) + layout[2] / 2 + 2
    return m, top, cs - m, cs - m


def arrow_lanes(actions: list[int], box: Box) -> list[tuple[float, float, float, float, float]]:
    """Where each of a cell's arrows goes in ``box``: ``(tail x, tail y, dx, dy, length)``.

    One arrow: centred. Ties: each in its own lane, so each reads as an arrow: two opposite
    ones side by side, a vertical and a horizontal one as an L with a gap at its corner, three
    or four from a hub with a gap in the middle.
    """
    x0, y0, x1, y1 = box
    w, h = x1 - x0, y1 - y0
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    vert = [a for a in actions if a in (Action.NORTH, Action.SOUTH)]
    horiz = [a for a in actions if a in (Action.EAST, Action.WEST)]

    def along(a: int, u: float, lo: float, hi: float) -> tuple[float, float, float, float, float]:
        """Arrow ``a`` at ``u`` across, from ``lo`` to ``hi`` along (tail at the far side from where it points)."""
        dx, dy = DIRECTIONS[a]  # type: ignore[index]
        if dx:
            return (lo if dx > 0 else hi), u, dx, dy, hi - lo
        return u, (lo if dy > 0 else hi), dx, dy, hi - lo

    if len(actions) == 1:
        if vert:
            length = min(0.86 * h, 1.3 * w)
            return [along(vert[0], cx, cy - length / 2, cy + length / 2)]
        length = min(0.8 * w, 1.6 * h)
        return [along(horiz[0], cy, cx - length / 2, cx + length / 2)]
    if len(actions) == 2 and len(vert) == 2:  # N and S side by side
        length = min(0.86 * h, 0.34 * w / 0.34)
        return [along(a, cx + s * w * 0.17, cy - length / 2, cy + length / 2) for a, s in zip(vert, (-1, 1))]
    if len(actions) == 2 and len(horiz) == 2:  # E and W one above the other, their heads clear of each other
        length = min(0.8 * w, 0.48 * h / 0.52)
        return [along(a, cy + s * h * 0.24, cx - length / 2, cx + length / 2) for a, s in zip(horiz, (1, -1))]
    if len(actions) == 2:  # an L: the vertical lane on the side the horizontal arrow leaves from
        v, hz = vert[0], horiz[0]
        xv = x0 + 0.2 * w if hz == Action.EAST else x1 - 0.2 * w
        yh = y0 + 0.3 * h if v == Action.SOUTH else y1 - 0.3 * h
        gap = 0.16 * w
        lo, hi = (xv + gap, x1 - 0.04 * w) if hz == Action.EAST else (x0 + 0.04 * w, xv - gap)
        return [along(v, xv, y0 + 0.06 * h, y1 - 0.06 * h), along(hz, yh, lo, hi)]
    gap = 0.1 * min(w, h)  # a hub: each arrow from a gap round the middle outwards
    out = []
    for a in actions:
        dx, dy = DIRECTIONS[a]  # type: ignore[index]
        reach = (w if dx else h) / 2 * 0.94
        out.append((cx + dx * gap, cy + dy * gap, dx, dy, reach - gap))
    return out


def arrow(tx: float, ty: float, dx: float, dy: float, length: float, theme: Theme) -> list[Op]:
    """An arrow ``length`` pixels long from its tail ``(tx, ty)`` pointing ``(dx, dy)``, white on a dark edge."""
    edge = max(1.0, length * 0.06)
    w = max(2.0, length * 0.16)
    head = max(3.0, min(length * 0.4, length - 2 * edge))
    tip = length - edge * 1.6  # the dark edge ends at ``length``

    def shape(grow: float) -> Points:
        # along the arrow (a) and across it (b), east-pointing, then turned
        a0, a1, a2 = edge - grow, tip - head, tip + grow * 1.6
        b1, b2 = w / 2 + grow, head * 0.6 + grow
        pts = np.array([(a0, -b1), (a1, -b1), (a1, -b2), (a2, 0.0), (a1, b2), (a1, b1), (a0, b1)])
        return np.column_stack([tx + pts[:, 0] * dx - pts[:, 1] * dy, ty + pts[:, 0] * dy + pts[:, 1] * dx])

    return [Fill(shape(edge), theme.arrow_edge), Fill(shape(0.0), theme.arrow)]


def _box_layout(values: np.ndarray, cs: int, fmt: Callable[[float], str] = format_value) -> tuple[int, float, float] | None:
    """``(type size, box width, box height)``: one box size for the whole grid (the widest
    number's), so the picture stays calm; None where not even the smallest type fits."""
    texts = [fmt(float(v)) for v in values[np.isfinite(values)]]
    inner = cs - 2 * wall_width(cs)
    widest = max(texts, key=lambda s: text_width(s, 20))
    size = fit(widest, inner * 0.84, cs * 0.17, largest=28, smallest=7)
    if size is None:
        return None
    cap = cap_height(size)[1]
    return size, text_width(widest, size) + cap * 0.9, cap * 1.9


def box_centre(cs: int, layout: tuple[int, float, float], labelled: bool) -> float:
    """The y of a value box's centre in its cell (pixels from the cell's top): at the top, under a label."""
    top = label_band(cs)[1] + 1 if labelled else wall_width(cs) / 2 + 2
    return top + layout[2] / 2


def _value_boxes(values: np.ndarray, cs: int, theme: Theme, layout: tuple[int, float, float] | None,
                 labelled: frozenset = frozenset(), fmt: Callable[[float], str] = format_value) -> list[Op]:  # fmt: skip
    if layout is None:
        return []
    size, bw, bh = layout
    texts = {c: fmt(float(values[c])) for c in zip(*np.nonzero(np.isfinite(values)))}
    ops: list[Op] = []
    for (y, x), s in texts.items():
        cx, cy = (x + 0.5) * cs, y * cs + box_centre(cs, layout, (int(x), int(y)) in labelled)
        ops.append(Fill(round_rect(cx - bw / 2, cy - bh / 2, cx + bw / 2, cy + bh / 2, bh * 0.3), theme.value_box, 0.86))
        ops.append(Text(cx, cy, s, size, theme.value_text))
    return ops


def q_label_position(action: int, x: int, y: int, cs: int, w: float, h: float, top: float = 0.0) -> tuple[float, float] | None:
    """Where an action value's number of ``w`` x ``h`` pixels sits: centred in its triangle (at
    the triangle's middle, a sixth of the cell from its edge), moved in just enough to clear the
    wall and ``top`` (pixels at the top of the cell kept for a START / EXIT label); None if it
    does not fit inside the triangle."""
    m = wall_width(cs) / 2 + 2
    if action in (Action.NORTH, Action.SOUTH):
        outer = max(m, top) if action == Action.NORTH else m
        d = max(cs / 6, outer + h / 2)  # the text's centre, from the triangle's edge
        if w > cs - 2 * (d + h / 2) - 2:  # the triangle at depth d is (cs - 2 d) wide
            return None
        return (x + 0.5) * cs, (y * cs + d if action == Action.NORTH else (y + 1) * cs - d)
    d = max(cs / 6, m + w / 2)
    if h > cs - 2 * (d + w / 2) - 2 or (top and (y + 0.5) * cs - h / 2 < y * cs + top):
        return None
    return (x * cs + d if action == Action.WEST else (x + 1) * cs - d), (y + 0.5) * cs


def _q_numbers(q: np.ndarray, cs: int, theme: Theme, labelled: frozenset = frozenset(), exits: frozenset = frozenset(),
               fmt: Callable[[float], str] = format_value) -> list[Op]:  # fmt: skip
    band = label_band(cs)[1] + 1
    ops: list[Op] = []
    for action in DIRECTIONS:
        for y, x in zip(*np.nonzero(np.isfinite(q[:, :, action]))):
            if (int(x), int(y)) in exits:
                continue
            s = fmt(float(q[y, x, action]))
            top = band if (int(x), int(y)) in labelled else 0.0
            for size in _sizes_down(min(22, max(7, int(cs * 0.16)))):
                cap = cap_height(size)[1]
                w, h = text_width(s, size) + 2, cap + 2
                at = q_label_position(action, int(x), int(y), cs, w, h, top)
                if at is not None:
                    ops.append(
                        Fill(round_rect(at[0] - w / 2, at[1] - h / 2, at[0] + w / 2, at[1] + h / 2, 2), theme.value_box, 0.6)
                    )
                    ops.append(Text(at[0], at[1], s, size, theme.value_text))
                    break
    return ops


def _sizes_down(largest: int) -> list[int]:
    from .glyphs import sizes

    return [s for s in reversed(sizes()) if 7 <= s <= largest]


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
