"""Text for both renderers: one typeface (Liberation Sans Bold), measured and laid out here.

``rgb_array`` draws glyphs rasterised offline (``fontgen.py`` -> ``data/glyphs.npz``, about
300 KB: printable ASCII at the sizes in ``SIZES``) and blends them anti-aliased; the live
canvas asks the browser for the same font (``CSS_FONT``; Arial has the same metrics), placed
at the same pen positions. Characters outside printable ASCII are drawn as ``?``.
"""

from __future__ import annotations

from functools import cache, lru_cache

import numpy as np

from .memo import MB, byte_cached
from .shapes import Text

CSS_FAMILY = "'Liberation Sans', Arial, Helvetica, sans-serif"


@cache
def _atlas() -> tuple[dict[int, tuple[int, int, int]], dict[tuple[int, int], tuple[int, ...]], np.ndarray]:
    from importlib.resources import files

    with files(__package__).joinpath("data/glyphs.npz").open("rb") as f:
        data = np.load(f)
        bitmaps, table, metrics = data["bitmaps"], data["table"], data["metrics"]
    sizes = {int(s): (int(a), int(d), 0) for s, a, d in metrics}
    glyphs = {(int(r[0]), int(r[1])): tuple(int(v) for v in r[2:]) for r in table}
    for s in sizes:  # the cap height's top and height, from 'H'
        _, y0, _, h, _, _ = glyphs[(s, ord("H"))]
        a, d, _ = sizes[s]
        sizes[s] = (a, d, y0 * 1000 + h)
    return sizes, glyphs, bitmaps


def sizes() -> tuple[int, ...]:
    """The pixel sizes text can be drawn at, ascending."""
    return tuple(sorted(_atlas()[0]))


def size_at_most(size: float) -> int:
    """The largest size text is drawn at that is <= ``size`` (the atlas holds only ``sizes()``)."""
    drawable = [s for s in sizes() if s <= size]
    return drawable[-1] if drawable else sizes()[0]


def css_font(size: int) -> str:
    return f"bold {size}px {CSS_FAMILY}"


def _clean(text: str) -> str:
    return "".join(c if 32 <= ord(c) < 127 else "?" for c in text)


@lru_cache(maxsize=4096)
def text_width(text: str, size: int) -> float:
    """The advance width of ``text`` in pixels at ``size``."""
    glyphs = _atlas()[1]
    return sum(glyphs[(size, ord(c))][5] for c in _clean(text)) / 64.0


def advances(text: str, size: int) -> np.ndarray:
    """Each character's advance width in pixels at ``size`` (their sum is ``text_width``)."""
    glyphs = _atlas()[1]
    return np.array([glyphs[(size, ord(c))][5] for c in _clean(text)], dtype=np.float64) / 64.0


def cap_height(size: int) -> tuple[int, int]:
    """``(top, height)`` of a capital letter below the line's top, in pixels."""
    code = _atlas()[0][size][2]
    return code // 1000, code % 1000


def fit(text: str, max_width: float, max_height: float, largest: int = 64, smallest: int = 7) -> int | None:
    """The largest size (<= ``largest``) at which ``text``'s advance fits ``max_width`` and its
    cap height (digits, capitals) fits ``max_height``; None if not even ``smallest`` does."""
    for s in reversed(sizes()):
        if s > largest:
            continue
        if s < smallest:
            return None
        if text_width(text, s) <= max_width and cap_height(s)[1] <= max_height:
            return s
    return None


def origin(op: Text) -> tuple[float, float]:
    """Where the line's top-left corner goes for ``op``'s anchor and alignment (pixels)."""
    width = text_width(op.text, op.size)
    x = op.x - {"left": 0.0, "center": width / 2, "right": width}[op.align]
    top, h = cap_height(op.size)
    y = op.y - top if op.baseline == "top" else op.y - top - h / 2
    return x, y


def baseline_y(op: Text) -> float:
    """The alphabetic baseline of ``op``'s line (the canvas positions text by it)."""
    top, h = cap_height(op.size)
    return origin(op)[1] + top + h


def text_coverage(op: Text) -> tuple[np.ndarray, int, int] | None:
    """``(coverage float32[h, w], x, y)``: the pixels ``op`` covers, at whole-pixel ``(x, y)``."""
    run = _run(op.text, op.size)
    if run is None:
        return None
    cov, left, top = run
    x, y = origin(op)
    return cov, int(round(x)) + left, int(round(y)) + top


TEXT_BYTES = 8 * MB  # lines of text rasterised (a long panel line at a large size is a few hundred kB)


@byte_cached(TEXT_BYTES)
def _run(text: str, size: int) -> tuple[np.ndarray, int, int] | None:
    """A line's coverage and its offset from the line's top-left corner (the same wherever it goes)."""
    _, glyphs, bitmaps = _atlas()
    text = _clean(text)
    if not text.strip():
        return None
    parts, pen = [], 0.0
    for c in text:
        x0, y0, w, h, off, adv = glyphs[(size, ord(c))]
        if w:
            parts.append((int(round(pen)) + x0, y0, w, h, off))
        pen += adv / 64.0
    left = min(p[0] for p in parts)
    top = min(p[1] for p in parts)
    right = max(p[0] + p[2] for p in parts)
    bottom = max(p[1] + p[3] for p in parts)
    cov = np.zeros((bottom - top, right - left), dtype=np.float32)
    for gx, gy, w, h, off in parts:
        g = bitmaps[off : off + w * h].reshape(h, w)
        region = cov[gy - top : gy - top + h, gx - left : gx - left + w]
        np.maximum(region, g * np.float32(1 / 255), out=region)
    cov.setflags(write=False)
    return cov, left, top


def ink_box(op: Text) -> tuple[int, int, int, int] | None:
    """``(x0, y0, x1, y1)``: the bounding box of the pixels ``op`` inks (x1, y1 exclusive)."""
    box = text_coverage(op)
    if box is None:
        return None
    cov, x, y = box
    ys, xs = np.nonzero(cov > 0.02)
    if not len(xs):
        return None
    return x + int(xs.min()), y + int(ys.min()), x + int(xs.max()) + 1, y + int(ys.max()) + 1
