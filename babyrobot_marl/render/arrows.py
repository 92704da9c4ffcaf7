"""Policy arrows: their shape, and where a cell's arrows go among what else it holds.

An arrow is white with a dark edge, its shaft and head in proportion to its length. A cell's
arrows (one, or several tied ones) are laid out in the part of the cell they may use, clear of
everything kept out (numbers, a start's flag) and of each other: of the layouts tried, the one
whose shortest arrow is longest wins, so a tied arrow is never squeezed to a stub beside a
long one while there is room for both.
"""

from __future__ import annotations

import numpy as np

from ..core.actions import Action
from .cellgroups import overlap
from .palette import Theme
from .shapes import Fill, Op, Points

DIRECTIONS = {Action.NORTH: (0.0, -1.0), Action.EAST: (1.0, 0.0), Action.SOUTH: (0.0, 1.0), Action.WEST: (-1.0, 0.0)}
Box = tuple[float, float, float, float]  # x0, y0, x1, y1: pixels
Lane = tuple[float, float, float, float, float]  # an arrow: tail x, tail y, dx, dy, length
HUBS = (0.5, 0.38, 0.62, 0.26, 0.74)  # where tied arrows may meet, as parts of their region (the middle first)
ASIDE = {True: (0.3, 0.7), False: (0.7, 0.3)}  # a lone arrow with no room in the middle: a row above it (or
# below), a column right of it (or left; the robot stands bottom left), as parts of the region
APART = 1.5  # pixels kept between two arrows of one cell


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


def arrow_lanes(actions: list[int], box: Box) -> list[Lane]:
    """Where each of a cell's arrows goes in ``box`` with nothing else there.

    One arrow: centred. Ties: each in its own lane, so each reads as an arrow: two opposite
    ones side by side, a vertical and a horizontal one as an L with a gap at its corner, three
    or four from a hub with a gap in the middle.
    """
    x0, y0, x1, y1 = box
    w, h = x1 - x0, y1 - y0
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    vert = [a for a in actions if a in (Action.NORTH, Action.SOUTH)]
    horiz = [a for a in actions if a in (Action.EAST, Action.WEST)]
    if len(actions) == 1:
        if vert:
            length = min(0.86 * h, 1.3 * w)
            return [_along(vert[0], cx, cy - length / 2, cy + length / 2)]
        length = min(0.8 * w, 1.6 * h)
        return [_along(horiz[0], cy, cx - length / 2, cx + length / 2)]
    if len(actions) == 2 and len(vert) == 2:  # N and S side by side
        length = min(0.86 * h, w)
        return [_along(a, cx + s * w * 0.17, cy - length / 2, cy + length / 2) for a, s in zip(vert, (-1, 1))]
    if len(actions) == 2 and len(horiz) == 2:  # E and W one above the other, their heads clear of each other
        length = min(0.8 * w, 0.48 * h / 0.52)
        return [_along(a, cy + s * h * 0.24, cx - length / 2, cx + length / 2) for a, s in zip(horiz, (1, -1))]
    if len(actions) == 2:  # an L: the vertical lane on the side the horizontal arrow leaves from
        v, hz = vert[0], horiz[0]
        xv = x0 + 0.2 * w if hz == Action.EAST else x1 - 0.2 * w
        yh = y0 + 0.3 * h if v == Action.SOUTH else y1 - 0.3 * h
        gap = 0.16 * w
        lo, hi = (xv + gap, x1 - 0.04 * w) if hz == Action.EAST else (x0 + 0.04 * w, xv - gap)
        return [_along(v, xv, y0 + 0.06 * h, y1 - 0.06 * h), _along(hz, yh, lo, hi)]
    return _hub(actions, (cx, cy), box)


def _along(a: int, u: float, lo: float, hi: float) -> Lane:
    """Arrow ``a`` at ``u`` across, from ``lo`` to ``hi`` along (tail at the far side from where it points)."""
    dx, dy = DIRECTIONS[a]  # type: ignore[index]
    if dx:
        return (lo if dx > 0 else hi), u, dx, dy, hi - lo
    return u, (lo if dy > 0 else hi), dx, dy, hi - lo


def _hub(actions: list[int], at: tuple[float, float], box: Box) -> list[Lane]:
    """Each arrow from a small gap round ``at`` outwards to the edge of ``box`` (an L for two, a star for more)."""
    x0, y0, x1, y1 = box
    gap = max(2.0, 0.1 * min(x1 - x0, y1 - y0))
    out = []
    for a in actions:
        dx, dy = DIRECTIONS[a]  # type: ignore[index]
        reach = (x1 - at[0] if dx > 0 else at[0] - x0) if dx else (y1 - at[1] if dy > 0 else at[1] - y0)
        out.append((at[0] + dx * gap, at[1] + dy * gap, dx, dy, reach - gap))
    return out


def _through(a: int, at: tuple[float, float], box: Box) -> Lane:
    """One arrow centred on ``at``, as long as ``box`` allows on both sides of it (at most 0.86 of the box)."""
    x0, y0, x1, y1 = box
    dx, _ = DIRECTIONS[a]  # type: ignore[index]
    lo, hi, c = (x0, x1, at[0]) if dx else (y0, y1, at[1])
    half = min(c - lo, hi - c, 0.43 * (hi - lo))
    return _along(a, at[1] if dx else at[0], c - half, c + half)


def _span(a: int, middle: Box, region: Box) -> Lane:
    """One arrow across the whole of ``middle`` (centred), at most 0.86 of ``region`` long."""
    dx, _ = DIRECTIONS[a]  # type: ignore[index]
    lo, hi, rlo, rhi = (middle[0], middle[2], region[0], region[2]) if dx else (middle[1], middle[3], region[1], region[3])
    half = min(hi - lo, 0.86 * (rhi - rlo)) / 2
    c = (lo + hi) / 2
    return _along(a, (middle[1] + middle[3]) / 2 if dx else (middle[0] + middle[2]) / 2, c - half, c + half)


def _through_all(a: int, points: list[tuple[float, float]], box: Box) -> list[list[Lane]]:
    """A one-arrow layout ``_through`` each of ``points`` (parts of ``box``)."""
    x0, y0, x1, y1 = box
    return [[_through(a, (x0 + fx * (x1 - x0), y0 + fy * (y1 - y0)), box)] for fx, fy in points]


def place_arrows(actions: list[int], region: Box, keep_out: list[Box], middle: Box | None = None,
                 settle: float = 1 / 3) -> list[Lane]:  # fmt: skip
    """The lanes of a cell's ``actions`` inside ``region``, clear of every ``keep_out`` box and
    of each other. Tried in turn: ``arrow_lanes`` in ``middle`` (the part the numbers leave
    free), then in the whole region, then lanes through (one arrow) or from (ties) points of the
    region; a later layout wins only if its shortest arrow is clearly longer (the picture stays
    calm: a lone arrow leaves the middle, for the same row or column in every cell, only when
    what is there leaves it under ``settle`` of the region). Empty if not every arrow fits (6
    pixels at least)."""
    x0, y0, x1, y1 = region
    boxes = [box for box in (middle, region) if box is not None and box[2] > box[0] and box[3] > box[1]]
    first = [arrow_lanes(actions, box) for box in boxes]
    if len(actions) == 1 and middle in boxes:  # all of the middle, as long as 0.86 of the region
        first.insert(0, [_span(actions[0], middle, region)])  # type: ignore[arg-type]
    best, shortest = _best(first, region, keep_out, [], 0.0, apart=False)  # their lanes are apart by design
    if len(actions) == 1:
        dx, _ = DIRECTIONS[actions[0]]  # type: ignore[index]
        span = min(x1 - x0, y1 - y0)
        if shortest < span * settle:
            aside = [(0.5, f) if dx else (f, 0.5) for f in ASIDE[bool(dx)]]
            best, shortest = _best(_through_all(actions[0], aside, region), region, keep_out, best, shortest)
        if shortest < span / 5:  # all but hidden (by a flag): anywhere in the region
            grid = [(fx, fy) for fy in HUBS for fx in HUBS]
            best, shortest = _best(_through_all(actions[0], grid, region), region, keep_out, best, shortest)
        return best
    if len(actions) == 2 and sum(DIRECTIONS[a][0] for a in actions) == sum(DIRECTIONS[a][1] for a in actions) == 0:  # type: ignore[index]
        return best  # two opposite arrows from one point would read as one line
    layouts = [_hub(actions, (x0 + fx * (x1 - x0), y0 + fy * (y1 - y0)), region) for fy in HUBS for fx in HUBS]
    return _best(layouts, region, keep_out, best, shortest)[0]


def _best(layouts: list[list[Lane]], region: Box, keep_out: list[Box], best: list[Lane],
          shortest: float, apart: bool = True) -> tuple[list[Lane], float]:  # fmt: skip
    """Of ``best`` and ``layouts`` (each fitted, in turn, each arrow ``APART`` from the ones
    before it if ``apart``), the one whose shortest arrow is longest by a clear margin (a fifth),
    and that length."""
    for lanes in layouts:
        placed: list[Lane] = []
        kept = list(keep_out)
        for lane in lanes:
            fitted = fit_lane(lane, region, kept)
            if fitted is None:
                break
            placed.append(fitted)
            kept += [grow(b, APART) for b in arrow_boxes(*fitted)] if apart else []
        else:
            length = min(lane[4] for lane in placed)
            if length > 1.2 * shortest + 0.5:
                best, shortest = placed, length
    return best, shortest


def fit_lane(lane: Lane, region: Box, keep_out: list[Box]) -> Lane | None:
    """The lane shortened (about its middle, or from its tip, or its tail, or about a point
    between: whichever keeps most) until its arrow (shaft, head, dark edge) is inside ``region`` and clear of every
    ``keep_out`` box; None if not even a 6-pixel arrow fits."""
    tx, ty, dx, dy, length = lane
    best = None
    for keep in (0.5, 0.0, 1.0, 0.25, 0.75):  # the point of the lane that stays: its middle, tail, tip, or between
        fitted = _shorten(lane, region, keep_out, tx + dx * length * keep, ty + dy * length * keep, keep)
        if fitted is not None and (best is None or fitted[4] > best[4] + 0.5):
            best = fitted
        if best is not None and best[4] >= length:  # whole: nothing to gain
            break
    return best


def _shorten(lane: Lane, region: Box, keep_out: list[Box], kx: float, ky: float, keep: float) -> Lane | None:
    """``fit_lane`` with the point ``(kx, ky)``, ``keep`` of the way from tail to tip, fixed."""
    _, _, dx, dy, length = lane

    def at(n: float) -> Lane:
        return kx - dx * n * keep, ky - dy * n * keep, dx, dy, n

    def fits(n: float) -> bool:
        shaft, head = arrow_boxes(*at(n))
        if not (_within(shaft, region) and _within(head, region)):
            return False
        return not any(overlap(shaft, k) or overlap(head, k) for k in keep_out)

    if length < 6.0 or not fits(6.0):
        return None
    if fits(length):
        return at(length)
    lo, hi = 6.0, length  # a shorter arrow about the same point lies inside a longer one
    while hi - lo > 0.25:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if fits(mid) else (lo, mid)
    return at(lo)


def grow(b: Box, by: float) -> Box:
    return b[0] - by, b[1] - by, b[2] + by, b[3] + by


def _within(a: Box, b: Box) -> bool:
    return b[0] - 0.01 <= a[0] and a[2] <= b[2] + 0.01 and b[1] - 0.01 <= a[1] and a[3] <= b[3] + 0.01
