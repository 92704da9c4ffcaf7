"""What both renderers draw: filled polygons and text, in pixels, and the numpy rasteriser.

A picture is a list of ``Fill`` and ``Text`` operations. The live canvas sends them to the
browser as canvas paths (``fill_styled_polygons``, ``fill_text``); ``rgb_array`` rasterises the
same list here, anti-aliased: each pixel is covered by the fraction ``0.5 - d`` (clipped to
0..1) where ``d`` is the signed distance in pixels from its centre to the polygon's outline.
Circles and curves are polygons with enough points to look round at their size, so one code
path (and one geometry) serves both renderers.

The shapes themselves are in ``shapes``. Sprites (``Sprite``, ``Stamp``: shapes drawn many times,
made once) are rasterised here too: ``paint`` stamps a sprite with ``patch``, and ``patch``
rasterises it with ``paint``, once per quarter-pixel offset (a cache of ``PATCH_BYTES``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from .glyphs import text_coverage
from .memo import MB, ByteCache
from .shapes import Colour, Fill, Op, Points, Text

__all__ = [
    "PATCH_BYTES", "Colour", "Fill", "Op", "Patch", "Points", "Sprite", "Stamp", "Text",
    "blend", "coverage", "flatten", "paint", "patch", "raster", "to_uint8",
]


@dataclass(frozen=True, eq=False)
class Sprite:
    """Operations about ``(0, 0)``: ``points`` float64[N, 2], ``counts`` (points per polygon),
    ``colours`` uint8[P, 3], ``alphas`` float64[P], and ``texts`` (drawn after the polygons)."""

    points: np.ndarray
    counts: np.ndarray
    colours: np.ndarray
    alphas: np.ndarray
    texts: tuple[Text, ...]

    def ops(self, cx: float, cy: float) -> list[Op]:
        """The operations centred on ``(cx, cy)`` (pixels), in drawing order."""
        out: list[Op] = []
        start = 0
        for k, n in enumerate(self.counts.tolist()):
            out.append(Fill(self.points[start : start + n] + (cx, cy), tuple(self.colours[k].tolist()), float(self.alphas[k])))
            start += n
        out += [Text(t.x + cx, t.y + cy, t.text, t.size, t.colour, t.align, t.baseline, t.alpha) for t in self.texts]
        return out


@dataclass(frozen=True, eq=False)
class Stamp:
    """A sprite placed at ``(x, y)``: an operation both renderers draw from their caches."""

    sprite: Sprite
    x: float
    y: float


def flatten(ops: Sequence[Op]) -> Sprite:
    fills = [op for op in ops if isinstance(op, Fill)]
    return Sprite(
        np.concatenate([f.points for f in fills]) if fills else np.zeros((0, 2)),
        np.array([len(f.points) for f in fills], dtype=np.int64),
        np.array([f.colour for f in fills], dtype=np.uint8).reshape(-1, 3),
        np.array([f.alpha for f in fills], dtype=np.float64),
        tuple(op for op in ops if isinstance(op, Text)),
    )


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


# ---------------------------------------------------------------------- rasterised, for rgb_array
@dataclass(frozen=True, eq=False)
class Patch:
    """A rasterised sprite: premultiplied colour and coverage, and its top-left corner relative
    to the whole pixel its centre falls in; ``inv`` and ``rgb16`` are the same in 8.8 fixed
    point for blending onto uint8 frames."""

    rgb: np.ndarray  # float32[h, w, 3]
    alpha: np.ndarray  # float32[h, w, 1]
    dx: int
    dy: int

    def __post_init__(self) -> None:
        object.__setattr__(self, "inv", np.rint((1.0 - self.alpha) * 256).astype(np.uint16))
        object.__setattr__(self, "rgb16", np.rint(self.rgb * 256).astype(np.uint16))
        object.__setattr__(self, "serial", next(_SERIALS))  # never reused: caches key by it, not by id()

    @property
    def nbytes(self) -> int:
        return self.rgb.nbytes + self.alpha.nbytes + self.inv.nbytes + self.rgb16.nbytes  # type: ignore[attr-defined]


_SERIALS = itertools.count()
PATCH_BYTES = 16 * MB  # the rasterised sprites (each kept with its sprite)
_PATCHES: ByteCache[tuple[Sprite, Patch]] = ByteCache(PATCH_BYTES)


def patch(sprite: Sprite, cx: float, cy: float) -> Patch:
    """``sprite`` rasterised at the sub-pixel offset of ``(cx, cy)`` (to a quarter pixel), cached."""
    fx, fy = int(round((cx % 1) * 4)) % 4, int(round((cy % 1) * 4)) % 4
    key = (id(sprite), fx, fy)
    hit = _PATCHES.get(key)
    if hit is not None and hit[0] is sprite:
        return hit[1]
    m = 3 + max((t.size for t in sprite.texts), default=0) // 2
    pts = sprite.points if len(sprite.points) else np.zeros((1, 2))
    lo = np.floor(pts.min(axis=0)).astype(int) - m
    hi = np.ceil(pts.max(axis=0)).astype(int) + m
    w, h = int(hi[0] - lo[0]), int(hi[1] - lo[1])
    rgb = np.zeros((h, w, 3), dtype=np.float32)
    alpha = np.zeros((h, w), dtype=np.float32)
    paint(rgb, sprite.ops(-lo[0] + fx / 4, -lo[1] + fy / 4), alpha)
    ys, xs = np.nonzero(alpha > 0)  # trim to the inked pixels
    if len(xs):
        y0, y1, x0, x1 = int(ys.min()), int(ys.max()) + 1, int(xs.min()), int(xs.max()) + 1
        rgb, alpha, lo = rgb[y0:y1, x0:x1], alpha[y0:y1, x0:x1], lo + (x0, y0)
    out = Patch(np.ascontiguousarray(rgb), np.ascontiguousarray(alpha)[..., None], int(lo[0]), int(lo[1]))
    _PATCHES.put(key, (sprite, out))  # the sprite kept alive with it: its id stays its own
    return out


def blend(img: np.ndarray, p: Patch, cx: float, cy: float) -> None:
    """Composite patch ``p`` centred on ``(cx, cy)`` onto ``img`` (uint8 or float32, in place)."""
    x0, y0 = math.floor(cx + 1e-9) + p.dx, math.floor(cy + 1e-9) + p.dy  # math: a numpy scalar is slower
    h, w = p.rgb.shape[:2]
    gx0, gy0 = max(0, x0), max(0, y0)
    gx1, gy1 = min(img.shape[1], x0 + w), min(img.shape[0], y0 + h)
    if gx1 <= gx0 or gy1 <= gy0:
        return
    sl = (slice(gy0 - y0, gy1 - y0), slice(gx0 - x0, gx1 - x0))
    region = img[gy0:gy1, gx0:gx1]
    if img.dtype == np.uint8:  # fixed point: (under * (1 - a) + premultiplied colour), rounded
        region[:] = ((region * p.inv[sl] + p.rgb16[sl] + 128) >> 8).astype(np.uint8)
    else:
        region[:] = region * (1.0 - p.alpha[sl]) + p.rgb[sl]
