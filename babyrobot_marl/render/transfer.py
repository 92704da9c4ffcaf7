"""A picture sent to a browser's canvas, pixel for pixel: as PNG, or as rectangles of one colour.

ipycanvas sends a picture (``put_image_data``) as PNG, and the browser decodes it in its own
time: a canvas put on the page before the decode ends shows nothing for a frame or more.
Rectangles (``fill_styled_rects``) are drawn as their message is handled, before the page can
show the canvas. Each rectangle covers whole pixels in one opaque colour, so nothing is blended:
the browser shows exactly the pixels of the picture.

Rectangles pay while they are few: a level's flat floor is a few a cell, but anti-aliased edges,
numbers and arrows are a pixel high, and each rectangle is 19 bytes sent (four int32 and a
colour). The rule: a canvas the browser may show empty gets its picture as rectangles when they
are at most ``MAX_RECTS`` (300,000, about 5.7 MB: a fitted canvas of a 64x64 maze with values and
arrows has 280,000); a larger one (a 128x128 maze at 16-pixel cells with values and arrows:
2.2 million rectangles, 41 MB, against a 3.5 MB PNG) gets a coarse copy of itself as at most
``COARSE_RECTS`` rectangles (blocks of pixels, each in the colour of its centre: about one a
cell), drawn at once, and the PNG over it: the canvas shows the coarse picture, never nothing,
until the PNG is decoded.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["COARSE_RECTS", "MAX_RECTS", "coarse_rectangles", "picture_calls", "put_picture", "rectangles"]

MAX_RECTS = 300_000  # a picture sent as rectangles: at most this many
COARSE_RECTS = 20_000  # the coarse copy under a PNG: at most this many


def rectangles(img: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``img`` (uint8[H, W, 3]) as ``(x, y, width, height, colours)`` (int32[N] four times and
    uint8[N, 3]) covering every pixel once: each row's runs of one colour, each run merged with
    the same run (same columns, same colour) in the rows right below it. A plain level's flat
    floor is then a few rectangles a cell; only anti-aliased edges and text stay a pixel high."""
    h, w, _ = img.shape
    key = (img[..., 0].astype(np.uint32) << 16) | (img[..., 1].astype(np.uint32) << 8) | img[..., 2]  # one number a pixel
    starts = np.ones((h, w), dtype=bool)
    starts[:, 1:] = key[:, 1:] != key[:, :-1]
    ys, xs = np.nonzero(starts)  # row-major: each row's runs left to right
    ends = np.append(xs[1:], w)
    ends[np.append(ys[1:] != ys[:-1], True)] = w  # a row's last run ends at the right edge
    colour = key[ys, xs].astype(np.int64)
    run = (((xs << 16) | ends) << 24) | colour  # columns and colour: one number per kind of run
    order = np.lexsort((ys, run))  # the same runs together, top to bottom
    r, y = run[order], ys[order]
    first = np.flatnonzero(np.append(True, (r[1:] != r[:-1]) | (y[1:] != y[:-1] + 1)))
    heights = np.diff(np.append(first, len(r)))
    top = order[first]
    x0 = xs[top]
    colours = np.stack([(colour[top] >> s) & 255 for s in (16, 8, 0)], axis=1).astype(np.uint8)
    return (x0.astype(np.int32), ys[top].astype(np.int32), (ends[top] - x0).astype(np.int32),
            heights.astype(np.int32), colours)  # fmt: skip


def coarse_rectangles(img: np.ndarray, most: int = COARSE_RECTS) -> tuple[np.ndarray, ...]:
    """``rectangles`` of ``img`` seen in square blocks of pixels, each block the colour of its
    centre pixel, the smallest blocks that give at most ``most`` rectangles; clipped to ``img``."""
    h, w, _ = img.shape
    b = 1
    while -(-h // b) * -(-w // b) > most:
        b += 1
    ys = np.minimum(np.arange(0, h, b) + b // 2, h - 1)
    xs = np.minimum(np.arange(0, w, b) + b // 2, w - 1)
    x, y, rw, rh, colours = rectangles(np.ascontiguousarray(img[ys][:, xs]))
    x0, y0 = x * b, y * b
    return (x0, y0, (np.minimum((x + rw) * b, w) - x0).astype(np.int32),
            (np.minimum((y + rh) * b, h) - y0).astype(np.int32), colours)  # fmt: skip


def put_picture(layer: Any, img: np.ndarray, fresh: bool) -> None:
    """``img`` (uint8[H, W, 3]) on ``layer`` (an ipycanvas canvas), pixel for pixel, inside the
    caller's ``hold_canvas``. A layer that shows a picture gets the new one as PNG: the browser
    keeps the old one on screen until it has decoded the new. A ``fresh`` layer (it may show
    nothing yet) gets ``rectangles`` instead, drawn as they arrive: a canvas put on the page while
    a PNG still decodes would show nothing, for a frame or more; past ``MAX_RECTS`` rectangles,
    a coarse copy as rectangles and the PNG over it."""
    picture_calls(img, fresh)(layer)


def picture_calls(img: np.ndarray, fresh: bool) -> Any:
    """``put_picture`` in two halves: the work done now (the rectangles), the sending in the
    function returned (``layer`` -> None), so a canvas cleared by a resize waits for no computing."""
    rects = rectangles(img) if fresh else None
    coarse = coarse_rectangles(img) if rects is not None and len(rects[0]) > MAX_RECTS else None
    # RGBA, sent as lossless PNG: made now too
    rgba = None if rects is not None and coarse is None else np.concatenate(
        [img, np.full(img.shape[:2] + (1,), 255, dtype=np.uint8)], axis=2)

    def put(layer: Any) -> None:
        layer.clear()
        if rgba is None:
            layer.fill_styled_rects(*rects)
            return
        if coarse is not None:
            layer.fill_styled_rects(*coarse)  # on screen until the PNG is decoded
        layer.put_image_data(rgba, 0, 0)

    return put
