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

from collections.abc import Callable, Sequence
from typing import NamedTuple

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
RING = 1.0  # the white ring round a best action's number, pixels
NUMBER_GAP = RING + 1.5  # pixels kept between an action value's box and an arrow (no pixel shared, ring included)
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
    numbers = q_labels(overlay.q_values, cs, labelled, exits, fmt) if overlay.q_values is not None else {}
    if overlay.arrows is not None:
        for y, x in zip(*np.nonzero(overlay.arrows[:, :, 1:].any(axis=2))):
            actions = [a for a in DIRECTIONS if overlay.arrows[y, x, a]]
            x0, y0, x1, y1 = arrow_region(cs, layout, (int(x), int(y)) in labelled)
            here = numbers.get((int(x), int(y)), [])
            if all(a in (Action.EAST, Action.WEST) for a in actions):  # clear of the robot's corner:
                if ROBOT_TOP * cs - y0 >= 0.4 * cs and not here:
                    y1 = min(y1, ROBOT_TOP * cs)  # above it, as long as ever (no value box, no numbers)
                else:
                    x0 = max(x0, ROBOT_RIGHT * cs)  # right of it (the W number is there anyway)
            region = (x * cs + x0, y * cs + y0, x * cs + x1, y * cs + y1)
            boxes = [(lb.action, lb.box(NUMBER_GAP if lb.action in actions else NUMBER_GAP - RING)) for lb in here]
            lanes = q_arrow_lanes(actions, region, boxes) if boxes else arrow_lanes(actions, region)
            for tx, ty, dx, dy, length in lanes:
                ops += arrow(tx, ty, dx, dy, length, theme)
    best = overlay.arrows
    for (x, y), labels in numbers.items():  # the best actions' numbers stand out (their arrows are short)
        ops += [op for lb in labels for op in lb.ops(theme, best is not None and bool(best[y, x, lb.action]))]
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


def arrow_sizes(length: float) -> tuple[float, float, float, float]:
    """An arrow's ``(edge, shaft width, head length, tip)`` in pixels for its ``length``."""
    edge = max(1.0, length * 0.06)
    head = max(3.0, min(length * 0.4, length - 2 * edge))
    return edge, max(2.0, length * 0.16), head, length - edge * 1.6  # the dark edge ends at ``length``


def arrow(tx: float, ty: float, dx: float, dy: float, length: float, theme: Theme) -> list[Op]:
    """An arrow ``length`` pixels long from its tail ``(tx, ty)`` pointing ``(dx, dy)``, white on a dark edge."""
    edge, w, head, tip = arrow_sizes(length)

    def shape(grow: float) -> Points:
        # along the arrow (a) and across it (b), east-pointing, then turned
        a0, a1, a2 = edge - grow, tip - head, tip + grow * 1.6
        b1, b2 = w / 2 + grow, head * 0.6 + grow
        pts = np.array([(a0, -b1), (a1, -b1), (a1, -b2), (a2, 0.0), (a1, b2), (a1, b1), (a0, b1)])
        return np.column_stack([tx + pts[:, 0] * dx - pts[:, 1] * dy, ty + pts[:, 0] * dy + pts[:, 1] * dx])

    return [Fill(shape(edge), theme.arrow_edge), Fill(shape(0.0), theme.arrow)]


def arrow_boxes(tx: float, ty: float, dx: float, dy: float, length: float) -> tuple[Box, Box]:
    """The rectangles round an arrow's shaft and its head (dark edge included), in pixels."""
    edge, w, head, tip = arrow_sizes(length)
    out = []
    for a0, a1, b in ((0.0, tip - head, w / 2 + edge), (tip - head, length, head * 0.6 + edge)):
        xs = (tx + a0 * dx, tx + a1 * dx) if dx else (tx - b, tx + b)
        ys = (ty + a0 * dy, ty + a1 * dy) if dy else (ty - b, ty + b)
        out.append((min(xs), min(ys), max(xs), max(ys)))
    return out[0], out[1]


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


class QLabel(NamedTuple):
    """An action value's number as drawn: its action, centre, box size (pixels), type size, text."""

    action: int
    cx: float
    cy: float
    w: float
    h: float
    size: int
    text: str

    def box(self, grow: float = 0.0) -> Box:
        return self.cx - self.w / 2 - grow, self.cy - self.h / 2 - grow, self.cx + self.w / 2 + grow, self.cy + self.h / 2 + grow

    def ops(self, theme: Theme, best: bool = False) -> list[Op]:
        """A dark box with light text; a best action's (one with an arrow) opaque in a ring of the
        arrow's white (``RING`` pixels, inside the gap kept to arrows), so the best numbers stand out
        where the arrows must stay short."""
        x0, y0, x1, y1 = self.box()
        if not best:
            return [Fill(round_rect(x0, y0, x1, y1, 2), theme.value_box, 0.6), self._text(theme.value_text)]
        ring = round_rect(x0 - RING, y0 - RING, x1 + RING, y1 + RING, 2 + RING)
        return [Fill(ring, theme.arrow), Fill(round_rect(x0, y0, x1, y1, 2), theme.value_box), self._text(theme.value_text)]

    def _text(self, colour: tuple[int, int, int]) -> Text:
        return Text(self.cx, self.cy, self.text, self.size, colour)


def q_labels(q: np.ndarray, cs: int, labelled: frozenset = frozenset(), exits: frozenset = frozenset(),
             fmt: Callable[[float], str] = format_value) -> dict[tuple[int, int], list[QLabel]]:  # fmt: skip
    """Each cell's action-value numbers by cell ``(x, y)``, all in one type size: the largest in
    which every number fits its triangle (under a START / EXIT label a number may be smaller,
    or left out). None at all if not even the smallest type fits: a picture with numbers in
    some cells and not in others reads as a mistake."""
    band = label_band(cs)[1] + 1
    wanted = [(int(action), (int(x), int(y)), fmt(float(q[y, x, action]))) for action in DIRECTIONS
              for y, x in zip(*np.nonzero(np.isfinite(q[:, :, action]))) if (int(x), int(y)) not in exits]  # fmt: skip
    sizes = _sizes_down(min(22, max(7, int(cs * 0.16))))
    for k, size in enumerate(sizes):
        out: dict[tuple[int, int], list[QLabel]] = {}
        for action, c, s in wanted:
            under_label = c in labelled
            label = _q_label(action, c, s, cs, sizes[k:] if under_label else (size,), band if under_label else 0.0)
            if label is not None:
                out.setdefault(c, []).append(label)
            elif not under_label:
                break  # too big for this cell: a smaller type for all
        else:
            return out
    return {}


def _q_label(action: int, cell: tuple[int, int], text: str, cs: int, sizes: Sequence[int], top: float) -> QLabel | None:
    """The action value ``text`` in the first of ``sizes`` that fits its triangle (``q_label_position``), or None."""
    for size in sizes:
        w, h = text_width(text, size) + 2, cap_height(size)[1] + 2
        at = q_label_position(action, cell[0], cell[1], cs, w, h, top)
        if at is not None:
            return QLabel(action, at[0], at[1], w, h, size, text)
    return None


Lane = tuple[float, float, float, float, float]  # an arrow: tail x, tail y, dx, dy, length


def q_arrow_lanes(actions: list[int], region: Box, numbers: list[tuple[int, Box]]) -> list[Lane]:
    """Arrows in a cell with action values, clear of every number's box (``numbers``: by action,
    grown by the gap to keep): in the middle the numbers leave free, each as long as fits.

    The E and W numbers sit on the cell's middle row, so a horizontal arrow has only the gap
    between them (short at 48 px; the best numbers are highlighted for that). One arrow: centred;
    E and W tied: one above the other; a horizontal and a vertical one: the horizontal one
    centred, the vertical one from past its head outwards; other ties: from a hub in the middle.
    """
    x0, y0, x1, y1 = region
    for action, (bx0, by0, bx1, by1) in numbers:  # the middle the numbers leave free
        if action == Action.NORTH:
            y0 = max(y0, by1)
        elif action == Action.SOUTH:
            y1 = min(y1, by0)
        elif action == Action.WEST:
            x0 = max(x0, bx1)
        else:
            x1 = min(x1, bx0)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    if len(actions) == 1:
        dx, dy = DIRECTIONS[actions[0]]  # type: ignore[index]
        reach = min(x1 - x0, 0.86 * (region[2] - region[0])) if dx else min(y1 - y0, 0.86 * (region[3] - region[1]))
        lanes = [(cx - dx * reach / 2, cy - dy * reach / 2, dx, dy, reach)]
    elif sorted(actions) == [Action.EAST, Action.WEST]:
        lanes = arrow_lanes(actions, (x0, y0, x1, y1))
    elif len(actions) == 2 and any(a in (Action.EAST, Action.WEST) for a in actions):  # an L: --> with ^ above it
        hz, v = sorted(actions, key=lambda a: a not in (Action.EAST, Action.WEST))
        first = q_arrow_lanes([hz], region, numbers)
        if not first:
            return q_arrow_lanes([v], region, numbers)
        edge, _, head, _ = arrow_sizes(first[0][4])
        clear = head * 0.6 + edge + 1.5  # from the middle row to past the horizontal arrow's head
        _, dy = DIRECTIONS[v]  # type: ignore[index]
        far = y0 if dy < 0 else y1
        lanes = [first[0], (cx, cy + dy * clear, 0.0, dy, abs(far - cy) - clear)]
    else:
        gap = 0.1 * min(x1 - x0, y1 - y0)
        lanes = []
        for a in actions:
            dx, dy = DIRECTIONS[a]  # type: ignore[index]
            reach = (x1 - cx if dx > 0 else cx - x0) if dx else (y1 - cy if dy > 0 else cy - y0)
            lanes.append((cx + dx * gap, cy + dy * gap, dx, dy, reach - gap))
    fitted = [_fit_lane(lane, region, [b for _, b in numbers]) for lane in lanes]
    return [lane for lane in fitted if lane is not None]


def _fit_lane(lane: Lane, region: Box, keep_out: list[Box]) -> Lane | None:
    """The lane shortened about its middle until its arrow (shaft, head, dark edge) is inside
    ``region`` and clear of every ``keep_out`` box; None if not even a 6-pixel arrow fits (its
    number, highlighted, still shows the best action)."""
    tx, ty, dx, dy, length = lane
    mx, my = tx + dx * length / 2, ty + dy * length / 2
    while length >= 6.0:
        tx, ty = mx - dx * length / 2, my - dy * length / 2
        parts = arrow_boxes(tx, ty, dx, dy, length)
        inside = all(_within(p, region) for p in parts)
        if inside and not any(_overlap(p, k) for p in parts for k in keep_out):
            return tx, ty, dx, dy, length
        length -= 0.5
    return None


def _within(a: Box, b: Box) -> bool:
    return b[0] - 0.01 <= a[0] and a[2] <= b[2] + 0.01 and b[1] - 0.01 <= a[1] and a[3] <= b[3] + 0.01


def _overlap(a: Box, b: Box) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


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
