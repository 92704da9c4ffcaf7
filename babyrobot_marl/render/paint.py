"""What both renderers draw: filled polygons and text, in pixels, and the numpy rasteriser.

A picture is a list of ``Fill`` and ``Text`` operations. The live canvas sends them to the
browser as canvas paths (``fill_styled_polygons``, ``fill_text``); ``rgb_array`` rasterises the
same list here, anti-aliased: each pixel is covered by the fraction ``0.5 - d`` (clipped to
0..1) where ``d`` is the signed distance in pixels from its centre to the polygon's outline.
Circles and curves are polygons with enough points to look round at their size, so one code
path (and one geometry) serves both renderers.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

Colour = tuple[int, int, int]
Points = np.ndarray  # float64[n, 2]: x, y in pixels (y down)


@dataclass(frozen=True, eq=False)
class Fill:
    """A filled polygon (even-odd rule) in one colour, ``alpha`` 0..1."""

    points: Points
    colour: Colour
    alpha: float = 1.0


@dataclass(frozen=True, eq=False)
class Text:
    """One line of text in the package's font (``render.glyphs``) at a size it holds.

    ``(x, y)`` is the anchor: ``align`` left/center/right, ``baseline`` "top" (the cap height's
    top at ``y``) or "middle" (the cap height centred on ``y``).
    """

    x: float
    y: float
    text: str
    size: int
    colour: Colour
    align: str = "center"
    baseline: str = "middle"
    alpha: float = 1.0


Op = Fill | Text


# ---------------------------------------------------------------------- shapes (pixels)
def rect(x0: float, y0: float, x1: float, y1: float) -> Points:
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=np.float64)


def ellipse(cx: float, cy: float, rx: float, ry: float, n: int = 0) -> Points:
    """An ellipse as a polygon; ``n`` points (0: enough for its size)."""
    n = n or max(12, min(64, int(2.2 * math.pi * max(rx, ry) ** 0.75 + 8)))
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.column_stack([cx + rx * np.cos(t), cy + ry * np.sin(t)])


def circle(cx: float, cy: float, r: float, n: int = 0) -> Points:
    return ellipse(cx, cy, r, r, n)


def round_rect(x0: float, y0: float, x1: float, y1: float, r: float) -> Points:
    """A rectangle with quarter-circle corners of radius ``r`` (clipped to fit)."""
    r = max(0.0, min(r, (x1 - x0) / 2, (y1 - y0) / 2))
    if r < 0.5:
        return rect(x0, y0, x1, y1)
    k = max(3, min(10, int(r)))
    pts = []
    for cx, cy, a0 in ((x1 - r, y0 + r, -90), (x1 - r, y1 - r, 0), (x0 + r, y1 - r, 90), (x0 + r, y0 + r, 180)):
        t = np.radians(np.linspace(a0, a0 + 90, k + 1))
        pts.append(np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)]))
    return np.concatenate(pts)


def blob(cx: float, cy: float, rx: float, ry: float, phase: float, wobble: float = 0.09) -> Points:
    """A puddle-like closed curve: an ellipse whose radius wobbles smoothly."""
    n = max(24, min(72, int(2.5 * math.pi * max(rx, ry) ** 0.75 + 12)))
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    k = 1.0 + wobble * np.sin(3 * t + phase) + 0.6 * wobble * np.sin(5 * t + 2.1 * phase)
    return np.column_stack([cx + rx * k * np.cos(t), cy + ry * k * np.sin(t)])


def segment(x0: float, y0: float, x1: float, y1: float, width: float) -> Points:
    """A straight stroke of ``width`` pixels from one point to the other, as a quad."""
    dx, dy = x1 - x0, y1 - y0
    length = math.hypot(dx, dy) or 1.0
    nx, ny = -dy / length * width / 2, dx / length * width / 2
    return np.array([(x0 + nx, y0 + ny), (x1 + nx, y1 + ny), (x1 - nx, y1 - ny), (x0 - nx, y0 - ny)])


def star(cx: float, cy: float, r_out: float, r_in: float, points: int = 5, turn: float = -90.0) -> Points:
    t = np.radians(turn + np.arange(2 * points) * 180.0 / points)
    r = np.where(np.arange(2 * points) % 2 == 0, r_out, r_in)
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def turned(points: Points, degrees: float, cx: float, cy: float) -> Points:
    """``points`` turned clockwise (y down) by ``degrees`` about ``(cx, cy)``."""
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    x, y = points[:, 0] - cx, points[:, 1] - cy
    return np.column_stack([cx + c * x - s * y, cy + s * x + c * y])


# ---------------------------------------------------------------------- rasteriser
def coverage(points: Points, x0: int, y0: int, w: int, h: int) -> np.ndarray:
    """``float32[h, w]``: how much of each pixel of the box at ``(x0, y0)`` the polygon covers."""
    if len(points) == 4 and _axis_aligned(points):  # rectangles (walls, lines, bars): exact, separable
        (ax, ay), (bx, by) = points.min(axis=0), points.max(axis=0)
        cx = np.clip(np.minimum(bx, np.arange(x0 + 1, x0 + w + 1)) - np.maximum(ax, np.arange(x0, x0 + w)), 0.0, 1.0)
        cy = np.clip(np.minimum(by, np.arange(y0 + 1, y0 + h + 1)) - np.maximum(ay, np.arange(y0, y0 + h)), 0.0, 1.0)
        return (cy[:, None] * cx[None, :]).astype(np.float32)
    px = (np.arange(x0, x0 + w, dtype=np.float32) + 0.5)[None, :]
    py = (np.arange(y0, y0 + h, dtype=np.float32) + 0.5)[:, None]
    pts = points.astype(np.float32)
    d2 = np.full((h, w), np.inf, dtype=np.float32)
    inside = np.zeros((h, w), dtype=bool)
    n = len(pts)
    for k in range(n):
        ax, ay = pts[k]
        bx, by = pts[(k + 1) % n]
        ex, ey = bx - ax, by - ay
        ll = ex * ex + ey * ey
        t = np.clip(((px - ax) * ex + (py - ay) * ey) / ll, 0.0, 1.0) if ll > 0 else np.zeros((h, w), np.float32)
        dx, dy = px - (ax + t * ex), py - (ay + t * ey)
        np.minimum(d2, dx * dx + dy * dy, out=d2)
        if ay != by:  # even-odd crossing test along +x
            crosses = (ay > py) != (by > py)
            x_at = ax + (py - ay) * (ex / (by - ay))
            inside ^= crosses & (px < x_at)
    d = np.sqrt(d2)
    return np.clip(np.where(inside, d + 0.5, 0.5 - d), 0.0, 1.0)


def _axis_aligned(points: Points) -> bool:
    xs, ys = points[:, 0], points[:, 1]
    return (xs[0] == xs[3] and xs[1] == xs[2] and ys[0] == ys[1] and ys[2] == ys[3]) or (
        xs[0] == xs[1] and xs[2] == xs[3] and ys[0] == ys[3] and ys[1] == ys[2]
    )


def paint(img: np.ndarray, ops: Iterable[Op], alpha: np.ndarray | None = None) -> None:
    """Draw ``ops`` in order onto ``img`` (``float32[H, W, 3]``, 0..255, in place).

    With ``alpha`` (``float32[H, W]``) the image is a layer with its own transparency: colours
    are kept premultiplied and ``alpha`` accumulates, so the layer can be composited later.
    """
    from .glyphs import text_coverage
    from .sprites import Stamp, blend, patch

    h, w = img.shape[:2]
    for op in ops:
        if isinstance(op, Stamp):
            p = patch(op.sprite, op.x, op.y)
            blend(img, p, op.x, op.y)
            if alpha is not None:  # the stamp's coverage joins the layer's
                a = np.zeros(img.shape[:2] + (1,), dtype=np.float32)
                blend(a, type(p)(p.alpha, p.alpha, p.dx, p.dy), op.x, op.y)
                alpha[:] = alpha + a[..., 0] * (1.0 - alpha)
            continue
        if isinstance(op, Text):
            box = text_coverage(op)
            if box is None:
                continue
            cov, bx, by = box
            cov = cov * op.alpha
        else:
            if not len(op.points):
                continue
            lo = np.floor(op.points.min(axis=0)).astype(int) - 1
            hi = np.ceil(op.points.max(axis=0)).astype(int) + 1
            bx, by = max(0, int(lo[0])), max(0, int(lo[1]))
            ex, ey = min(w, int(hi[0])), min(h, int(hi[1]))
            if ex <= bx or ey <= by:
                continue
            cov = coverage(op.points, bx, by, ex - bx, ey - by) * op.alpha
        ch, cw = cov.shape
        ex, ey = min(w, bx + cw), min(h, by + ch)
        if ex <= max(bx, 0) or ey <= max(by, 0):  # wholly outside the image
            continue
        if bx < 0 or by < 0:  # text may start left of or above the image: crop it
            cov = cov[max(0, -by) :, max(0, -bx) :]
            bx, by = max(0, bx), max(0, by)
        cov = cov[: ey - by, : ex - bx]
        region = img[by:ey, bx:ex]
        a = cov[..., None]
        region *= 1.0 - a
        region += a * np.asarray(op.colour, dtype=np.float32)
        if alpha is not None:
            ar = alpha[by:ey, bx:ex]
            ar *= 1.0 - cov
            ar += cov


def raster(ops: Sequence[Op], width: int, height: int, background: Colour) -> np.ndarray:
    """``uint8[height, width, 3]``: ``ops`` drawn on a ``background`` filled image."""
    img = np.empty((height, width, 3), dtype=np.float32)
    img[:] = background
    paint(img, ops)
    return to_uint8(img)


def to_uint8(img: np.ndarray) -> np.ndarray:
    return np.clip(img + 0.5, 0, 255).astype(np.uint8)


def shade(colour: Colour, k: float) -> Colour:
    """``colour`` darker (``k`` < 1) or lighter towards white (``k`` > 1)."""
    if k <= 1:
        return tuple(int(round(c * k)) for c in colour)  # type: ignore[return-value]
    t = min(1.0, k - 1)
    return tuple(int(round(c + (255 - c) * t)) for c in colour)  # type: ignore[return-value]


def mix(a: Colour, b: Colour, t: float) -> Colour:
    return tuple(int(round(x + (y - x) * t)) for x, y in zip(a, b))  # type: ignore[return-value]
