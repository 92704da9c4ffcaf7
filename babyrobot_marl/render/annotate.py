"""Overlays as pictures: value tints and boxes, policy arrows, action values, cell text.

Laid out so each reads at a glance, per cell (``cs`` pixels):

- a state value: the cell tinted by the theme's colour map, the number in a dark box with
  light text (the same contrast on every tint);
- arrows: white with a dark edge, from the cell's centre (several: ties) — under the value box
  when there are values, so the number is never covered;
- action values: the four triangles tinted, each number inside its own triangle;
- text: in a box at the bottom of the cell.

Every number is sized to the space it has (``glyphs.fit``) and dropped, never clipped, where
not even the smallest size fits (the tint still shows it). All of it lies under the robots.
"""

from __future__ import annotations

import numpy as np

from ..core.actions import Action
from .glyphs import cap_height, fit, text_width
from .overlay import Overlay, format_value
from .palette import Theme, colour_map
from .picture import wall_width
from .shapes import Fill, Op, Points, Text, rect, round_rect

DIRECTIONS = {Action.NORTH: (0.0, -1.0), Action.EAST: (1.0, 0.0), Action.SOUTH: (0.0, 1.0), Action.WEST: (-1.0, 0.0)}
_TRIANGLES = {  # centre-to-corner triangles, cell units
    Action.NORTH: ((0.0, 0.0), (1.0, 0.0), (0.5, 0.5)),
    Action.EAST: ((1.0, 0.0), (1.0, 1.0), (0.5, 0.5)),
    Action.SOUTH: ((1.0, 1.0), (0.0, 1.0), (0.5, 0.5)),
    Action.WEST: ((0.0, 1.0), (0.0, 0.0), (0.5, 0.5)),
}
VALUE_CENTRE = (0.5, 0.33)  # the value box, with values
TEXT_BAND = (0.76, 0.97)  # cell text, at the bottom


def value_range(overlay: Overlay) -> tuple[float, float] | None:
    """The range the colour map spans: the finite state values', else the action values'."""
    for arr in (overlay.values, None if overlay.q_values is None else overlay.q_values[:, :, 1:]):
        if arr is not None and np.isfinite(arr).any():
            return float(np.nanmin(arr)), float(np.nanmax(arr))
    return None


def tint_ops(overlay: Overlay, cs: int, theme: Theme) -> list[Op]:
    """The value tints: whole cells for state values, triangles for action values."""
    ops: list[Op] = []
    m = wall_width(cs) / 2
    if overlay.values is not None:
        lo, hi = value_range(overlay) or (0.0, 0.0)
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
                pts = (np.array(tri) * (cs - 2 * m) + (x * cs + m, y * cs + m)).astype(np.float64)
                ops.append(Fill(pts, tuple(colours[y, x, action - 1].tolist()), 0.82))
    return ops


def ink_ops(overlay: Overlay, cs: int, theme: Theme, labelled: frozenset = frozenset()) -> list[Op]:
    """Arrows, value boxes, action-value numbers and cell text, in that order (all under the robots).

    ``labelled``: the cells whose top band holds a START / EXIT label; their value box goes
    below it, so the label covers no number.
    """
    ops: list[Op] = []
    has_values = overlay.values is not None and bool(np.isfinite(overlay.values).any())
    layout = _box_layout(overlay.values, cs) if has_values else None
    if overlay.arrows is not None:
        bottom = cs - wall_width(cs) / 2 - 1
        for y, x in zip(*np.nonzero(overlay.arrows[:, :, 1:].any(axis=2))):
            if layout is not None:  # in the space under the value box
                top = box_centre(cs, layout, (int(x), int(y)) in labelled) + layout[2] / 2 + 1
                cy, length = (top + bottom) / 2, max(2.0, (bottom - top) / 2)
            else:
                cy, length = cs / 2, 0.36 * cs
            for action, (dx, dy) in DIRECTIONS.items():
                if overlay.arrows[y, x, action]:
                    ops += arrow((x + 0.5) * cs, y * cs + cy, dx, dy, length, theme)
    if overlay.q_values is not None:
        ops += _q_numbers(overlay.q_values, cs, theme, labelled)
    if layout is not None:
        ops += _value_boxes(overlay.values, cs, theme, layout, labelled)  # type: ignore[arg-type]
    for (x, y), s in overlay.text.items():
        ops += _cell_text(s, x, y, cs, theme)
    return ops


def arrow(cx: float, cy: float, dx: float, dy: float, length: float, theme: Theme) -> list[Op]:
    """An arrow from near ``(cx, cy)`` pointing ``(dx, dy)``, white on a dark edge."""
    w = max(1.6, length * 0.2)
    head = max(3.0, length * 0.42)
    start = max(1.0, length * 0.12)
    edge = max(1.0, length * 0.07)
    tip = length - edge * 1.6  # the dark edge ends at ``length``

    def shape(grow: float) -> Points:
        # along the arrow (a) and across it (b), east-pointing, then turned
        a0, a1, a2 = start - grow, tip - head, tip + grow * 1.6
        b1, b2 = w / 2 + grow, head * 0.62 + grow
        pts = np.array([(a0, -b1), (a1, -b1), (a1, -b2), (a2, 0.0), (a1, b2), (a1, b1), (a0, b1)])
        return np.column_stack([cx + pts[:, 0] * dx - pts[:, 1] * dy, cy + pts[:, 0] * dy + pts[:, 1] * dx])

    return [Fill(shape(edge), theme.arrow_edge), Fill(shape(0.0), theme.arrow)]


def _box_layout(values: np.ndarray, cs: int) -> tuple[int, float, float] | None:
    """``(type size, box width, box height)``: one box size for the whole grid (the widest
    number's), so the picture stays calm; None where not even the smallest type fits."""
    texts = [format_value(float(v)) for v in values[np.isfinite(values)]]
    inner = cs - 2 * wall_width(cs)
    widest = max(texts, key=lambda s: text_width(s, 20))
    size = fit(widest, inner * 0.84, cs * 0.17, largest=28, smallest=7)
    if size is None:
        return None
    cap = cap_height(size)[1]
    return size, text_width(widest, size) + cap * 0.9, cap * 1.9


def box_centre(cs: int, layout: tuple[int, float, float], labelled: bool) -> float:
    """The y of a value box's centre in its cell (pixels from the cell's top)."""
    from .picture import label_band

    y = VALUE_CENTRE[1] * cs
    return max(y, label_band(cs)[1] + 1 + layout[2] / 2) if labelled else y


def _value_boxes(values: np.ndarray, cs: int, theme: Theme, layout: tuple[int, float, float] | None,
                 labelled: frozenset = frozenset()) -> list[Op]:  # fmt: skip
    if layout is None:
        return []
    size, bw, bh = layout
    texts = {c: format_value(float(values[c])) for c in zip(*np.nonzero(np.isfinite(values)))}
    ops: list[Op] = []
    for (y, x), s in texts.items():
        cx, cy = (x + VALUE_CENTRE[0]) * cs, y * cs + box_centre(cs, layout, (int(x), int(y)) in labelled)
        ops.append(Fill(round_rect(cx - bw / 2, cy - bh / 2, cx + bw / 2, cy + bh / 2, bh * 0.3), theme.value_box, 0.86))
        ops.append(Text(cx, cy, s, size, theme.value_text))
    return ops


def q_label_position(action: int, x: int, y: int, cs: int, w: float, h: float, top: float = 0.0) -> tuple[float, float] | None:
    """Where an action value's number of ``w`` x ``h`` pixels sits inside its triangle, or None if
    it cannot; ``top``: pixels at the top of the cell to keep clear (a START / EXIT label)."""
    m = wall_width(cs) / 2 + 1
    if action in (Action.NORTH, Action.SOUTH):
        # the triangle at depth d from its edge is (cs - 2 d) wide: the text's inner side must fit
        outer = max(m, top) if action == Action.NORTH else m
        d = outer + h  # the inner side of the text
        if w > cs - 2 * d - 2:
            return None
        cy = y * cs + outer + h / 2 if action == Action.NORTH else (y + 1) * cs - m - h / 2
        return (x + 0.5) * cs, cy
    d = m + w
    if h > cs - 2 * d - 2:
        return None
    cx = x * cs + m + w / 2 if action == Action.WEST else (x + 1) * cs - m - w / 2
    return cx, (y + 0.5) * cs


def _q_numbers(q: np.ndarray, cs: int, theme: Theme, labelled: frozenset = frozenset()) -> list[Op]:
    from .picture import label_band

    band = label_band(cs)[1] + 1
    ops: list[Op] = []
    for action in DIRECTIONS:
        for y, x in zip(*np.nonzero(np.isfinite(q[:, :, action]))):
            s = format_value(float(q[y, x, action]))
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
