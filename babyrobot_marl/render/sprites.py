"""Shapes drawn many times, made once: robots, rank badges, collision bursts.

A ``Sprite`` is a picture's operations about its centre at one pixel size, flattened into
arrays (the canvas sends all of a frame's sprites in one ``fill_styled_polygons`` call); the
numpy renderer rasterises each sprite once per quarter-pixel offset (``patch``). Both caches
are bounded.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .paint import Fill, Op, Text, circle, paint, star
from .palette import Theme, robot_colour
from .robot import robot

MEDALS = {1: (240, 190, 40), 2: (190, 196, 206), 3: (205, 130, 70)}  # gold, silver, bronze; then grey
OTHER_RANK = (150, 154, 166)


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


@lru_cache(maxsize=1024)
def robot_sprite(theme: Theme, number: int, heading: int, pose: str, numbered: bool, size: float) -> Sprite:
    """Baby Robot number ``number`` (its colour; its number on its chest when ``numbered``)."""
    return flatten(robot(0.0, 0.0, size, theme, robot_colour(theme, number), heading, pose, number if numbered else None))


@lru_cache(maxsize=256)
def badge(theme: Theme, rank: int, r: float) -> Sprite:
    """A round rank badge of radius ``r``: gold, silver, bronze, then grey, with the rank."""
    from .glyphs import fit

    fill = MEDALS.get(rank, OTHER_RANK)
    ops: list[Op] = [Fill(circle(0.0, 0.0, r + max(1.0, r * 0.15)), theme.robot_ink), Fill(circle(0.0, 0.0, r), fill)]
    s = fit(str(rank), r * 1.5, r * 1.1, largest=30, smallest=6)
    if s is not None:
        ops.append(Text(0.0, 0.0, str(rank), s, (20, 20, 24)))
    return flatten(ops)


@lru_cache(maxsize=64)
def burst(theme: Theme, r: float) -> Sprite:
    """The mark where a robot was stopped by another: an eight-pointed burst."""
    return flatten(
        [
            Fill(star(0.0, 0.0, r * 1.12, r * 0.58, 8, -90 + 22.5), theme.robot_ink),
            Fill(star(0.0, 0.0, r, r * 0.48, 8, -90 + 22.5), theme.mark),
            Fill(star(0.0, 0.0, r * 0.5, r * 0.26, 8, -90), (255, 226, 90)),
        ]
    )


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


_PATCHES: OrderedDict[tuple[int, int, int], tuple[Sprite, Patch]] = OrderedDict()
MAX_PATCHES = 1024


def patch(sprite: Sprite, cx: float, cy: float) -> Patch:
    """``sprite`` rasterised at the sub-pixel offset of ``(cx, cy)`` (to a quarter pixel), cached."""
    fx, fy = int(round((cx % 1) * 4)) % 4, int(round((cy % 1) * 4)) % 4
    key = (id(sprite), fx, fy)
    hit = _PATCHES.get(key)
    if hit is not None and hit[0] is sprite:
        _PATCHES.move_to_end(key)
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
    _PATCHES[key] = (sprite, out)  # the sprite kept alive with it: its id stays its own
    if len(_PATCHES) > MAX_PATCHES:
        _PATCHES.popitem(last=False)
    return out


def blend(img: np.ndarray, p: Patch, cx: float, cy: float) -> None:
    """Composite patch ``p`` centred on ``(cx, cy)`` onto ``img`` (uint8 or float32, in place)."""
    x0, y0 = int(np.floor(cx + 1e-9)) + p.dx, int(np.floor(cy + 1e-9)) + p.dy
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
