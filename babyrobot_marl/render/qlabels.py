"""Action values' numbers: one per triangle of a cell, all in one type size, clear of walls and labels.

Each number sits centred in its triangle (a sixth of the cell from its edge, moved in just
enough to keep ``GAP`` pixels between its ring and the wall, glass pane or START / EXIT label
beside it), in the largest type in which every number fits its triangle.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np

from ..core.actions import Action
from .arrows import DIRECTIONS, Box
from .glyphs import cap_height, text_width
from .overlay import format_value
from .palette import Theme
from .picture import border_depths, label_band, wall_width
from .shapes import Fill, Op, Text, round_rect

RING = 1.0  # the white ring round a best action's number, pixels
GAP = 2.0  # pixels kept clear between a number (its ring included) and a wall, a label or an arrow
LARGEST = 0.16  # the largest type an action value is drawn in, in cells (the arrows need the rest)


def cell_gap(cs: int) -> float:
    """``GAP``, in cells of 80 pixels and more (a browser's at twice the resolution: 40 on the
    page); in smaller ones a number would not fit beside a wall, and touches it."""
    return GAP if cs >= 80 else 0.0


def clearance(x: int, y: int, depths: np.ndarray, cs: int, labelled: bool = False) -> Box:
    """The pixels kept free at each side of cell ``(x, y)``: ``(left, top, right, bottom)`` from
    the cell's edges: ``GAP`` pixels past its walls, panes or the grid's border (``depths``:
    ``picture.edge_depths``), the tint's edge where there is no wall, and in a ``labelled`` cell
    ``GAP`` pixels past the START / EXIT pill at the top."""
    inset, gap = wall_width(cs) / 2, cell_gap(cs)  # where the tints stop: an open edge needs no gap
    left, top, right, bottom = (float(d) + gap if d else inset for d in depths[y, x])
    if labelled:
        top = label_band(cs)[1] + 1 + gap  # the pill's outline is 1 px wide
    return left, top, right, bottom


def q_label_position(action: int, x: int, y: int, cs: int, w: float, h: float, clear: Box) -> tuple[float, float] | None:
    """Where an action value's number of ``w`` x ``h`` pixels sits: centred in its triangle (at
    the triangle's middle, a sixth of the cell from its edge), moved in just enough that its ring
    keeps ``clear`` (``clearance``); None if it does not fit inside the triangle."""
    left, top, right, bottom = (c + RING for c in clear)
    if action in (Action.NORTH, Action.SOUTH):
        d = max(cs / 6, (top if action == Action.NORTH else bottom) + h / 2)  # the text's centre, from the triangle's edge
        if w > cs - 2 * (d + h / 2) - 2:  # the triangle at depth d is (cs - 2 d) wide
            return None
        return (x + 0.5) * cs, (y * cs + d if action == Action.NORTH else (y + 1) * cs - d)
    d = max(cs / 6, (left if action == Action.WEST else right) + w / 2)
    if h > cs - 2 * (d + w / 2) - 2 or cs / 2 - h / 2 < top or cs / 2 + h / 2 > cs - bottom:
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
        arrow's white (``RING`` pixels), so the best numbers stand out where arrows are short."""
        x0, y0, x1, y1 = self.box()
        if not best:
            return [Fill(round_rect(x0, y0, x1, y1, 2), theme.value_box, 0.6), self._text(theme.value_text)]
        ring = round_rect(x0 - RING, y0 - RING, x1 + RING, y1 + RING, 2 + RING)
        return [Fill(ring, theme.arrow), Fill(round_rect(x0, y0, x1, y1, 2), theme.value_box), self._text(theme.value_text)]

    def _text(self, colour: tuple[int, int, int]) -> Text:
        return Text(self.cx, self.cy, self.text, self.size, colour)


def q_labels(q: np.ndarray, cs: int, labelled: frozenset = frozenset(), exits: frozenset = frozenset(),
             fmt: Callable[[float], str] = format_value,
             depths: np.ndarray | None = None) -> dict[tuple[int, int], list[QLabel]]:  # fmt: skip
    """Each cell's action-value numbers by cell ``(x, y)``, all in one type size: the largest in
    which every number fits its triangle (under a START / EXIT label a number may be smaller,
    or left out). None at all if not even the smallest type fits: a picture with numbers in
    some cells and not in others reads as a mistake. ``depths``: ``picture.edge_depths`` (by
    default a grid's with no glass panes)."""
    depths = border_depths(q.shape[:2], cs) if depths is None else depths
    wanted = [(int(action), (int(x), int(y)), fmt(float(q[y, x, action]))) for action in DIRECTIONS
              for y, x in zip(*np.nonzero(np.isfinite(q[:, :, action]))) if (int(x), int(y)) not in exits]  # fmt: skip
    sizes = _sizes_down(max(7, int(cs * LARGEST)))
    for k, size in enumerate(sizes):
        out: dict[tuple[int, int], list[QLabel]] = {}
        for action, c, s in wanted:
            under_label = c in labelled
            clear = clearance(c[0], c[1], depths, cs, under_label)
            label = _q_label(action, c, s, cs, sizes[k:] if under_label else (size,), clear)
            if label is not None:
                out.setdefault(c, []).append(label)
            elif not under_label:
                break  # too big for this cell: a smaller type for all
        else:
            return out
    return {}


def _q_label(action: int, cell: tuple[int, int], text: str, cs: int, sizes: Sequence[int], clear: Box) -> QLabel | None:
    """The action value ``text`` in the first of ``sizes`` that fits its triangle (``q_label_position``), or None."""
    for size in sizes:
        w, h = text_width(text, size) + 2, cap_height(size)[1] + 2
        at = q_label_position(action, cell[0], cell[1], cs, w, h, clear)
        if at is not None:
            return QLabel(action, at[0], at[1], w, h, size, text)
    return None


def _sizes_down(largest: int) -> list[int]:
    from .glyphs import sizes

    return [s for s in reversed(sizes()) if 7 <= s <= largest]
