"""A live canvas taller than it is shown: rows kept below the picture, cropped by the canvas's box.

The browser clears a canvas it resizes, and ipycanvas composes its layers into the page's canvas
only after the next batch of commands: a resize can show an empty canvas for a frame or more.
So the backing store keeps ``SPARE_LINES`` lines of panel text below what is shown; the panel
grows into them by a change of CSS alone (the canvas's bottom margin, negative, and its box's
``overflow: hidden`` hide the rows below the picture), and the canvas is resized only when a
panel outgrows them too (with as many spare lines again).

A percentage margin is a share of the containing block's width: the canvas is as wide as its
box, so ``-k * 100%`` hides ``k`` times the canvas's width, at any width the column gives it.
"""

from __future__ import annotations

from .panel import metrics

SPARE_LINES = 12  # lines of panel text the backing store has room for below the picture


def backing_height(shown: int, cs: int, ratio: int, lines: int = SPARE_LINES) -> int:
    """The backing store's height for a picture ``shown`` pixels tall (cells of ``cs`` backing
    pixels, ``ratio`` of them to a CSS pixel): room for ``lines`` more lines, whole CSS pixels."""
    spare = lines * metrics(cs, ratio).line_h
    return shown + spare + (-spare) % ratio


def crop_margin(backing: int, shown: int, width: int) -> str:
    """The canvas's CSS margin that hides its backing store's rows below ``shown`` (``width``: its
    backing store's width)."""
    hidden = backing - shown
    return "0" if hidden <= 0 else f"0 0 calc({-hidden / width:.6f} * 100%) 0"
