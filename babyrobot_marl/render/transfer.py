"""A picture sent to a browser's canvas, pixel for pixel: as PNG, or as rectangles of one colour.

ipycanvas sends a picture (``put_image_data``) as PNG, and the browser decodes it in its own
time: a canvas put on the page before the decode ends shows nothing for a frame or more.
Rectangles (``fill_styled_rects``) are drawn as their message is handled, before the page can
show the canvas. Each rectangle covers whole pixels in one opaque colour, so nothing is blended:
the browser shows exactly the pixels of the picture.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["put_picture", "rectangles"]


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


def put_picture(layer: Any, img: np.ndarray, fresh: bool) -> None:
    """``img`` (uint8[H, W, 3]) on ``layer`` (an ipycanvas canvas), pixel for pixel, inside the
    caller's ``hold_canvas``. A layer that shows a picture gets the new one as PNG: the browser
    keeps the old one on screen until it has decoded the new. A ``fresh`` layer (it may show
    nothing yet) gets ``rectangles`` instead, drawn as they arrive: a canvas put on the page while
    a PNG still decodes would show nothing, for a frame or more."""
    layer.clear()
    if fresh:
        x, y, w, h, colours = rectangles(img)
        layer.fill_styled_rects(x, y, w, h, colours)
    else:  # RGBA: sent as lossless PNG
        layer.put_image_data(np.concatenate([img, np.full(img.shape[:2] + (1,), 255, dtype=np.uint8)], axis=2), 0, 0)
