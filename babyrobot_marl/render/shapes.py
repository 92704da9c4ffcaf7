"""What a picture is made of: filled polygons (``Fill``) and text (``Text``), in pixels, and the
shapes that make polygons (rectangles, ellipses, stars, segments) and colours (``shade``, ``mix``).

Both renderers draw these: the live canvas sends them to the browser, ``rgb_array`` rasterises them
(``paint``). Circles and curves are polygons with enough points to look round at their size.
"""

from __future__ import annotations

import math
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


def shade(colour: Colour, k: float) -> Colour:
    """``colour`` darker (``k`` < 1) or lighter towards white (``k`` > 1)."""
    if k <= 1:
        return tuple(int(round(c * k)) for c in colour)  # type: ignore[return-value]
    t = min(1.0, k - 1)
    return tuple(int(round(c + (255 - c) * t)) for c in colour)  # type: ignore[return-value]


def mix(a: Colour, b: Colour, t: float) -> Colour:
    return tuple(int(round(x + (y - x) * t)) for x, y in zip(a, b))  # type: ignore[return-value]
