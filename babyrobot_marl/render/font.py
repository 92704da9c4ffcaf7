"""A 3x5 bitmap font for ``rgb_array`` labels, values and overlay text (pure numpy, no font files).

Upper-case letters, digits and common punctuation; lower case is drawn as upper case and any
other character as a small box, so no text is ever dropped silently.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

GLYPH_W, GLYPH_H = 3, 5

# one string per row, '#' on
_ROWS: dict[str, tuple[str, ...]] = {
    " ": ("...", "...", "...", "...", "..."),
    "0": ("###", "#.#", "#.#", "#.#", "###"),
    "1": (".#.", "##.", ".#.", ".#.", "###"),
    "2": ("###", "..#", "###", "#..", "###"),
    "3": ("###", "..#", "###", "..#", "###"),
    "4": ("#.#", "#.#", "###", "..#", "..#"),
    "5": ("###", "#..", "###", "..#", "###"),
    "6": ("###", "#..", "###", "#.#", "###"),
    "7": ("###", "..#", "..#", "..#", "..#"),
    "8": ("###", "#.#", "###", "#.#", "###"),
    "9": ("###", "#.#", "###", "..#", "###"),
    "A": (".#.", "#.#", "###", "#.#", "#.#"),
    "B": ("##.", "#.#", "##.", "#.#", "##."),
    "C": (".##", "#..", "#..", "#..", ".##"),
    "D": ("##.", "#.#", "#.#", "#.#", "##."),
    "E": ("###", "#..", "###", "#..", "###"),
    "F": ("###", "#..", "###", "#..", "#.."),
    "G": (".##", "#..", "#.#", "#.#", ".##"),
    "H": ("#.#", "#.#", "###", "#.#", "#.#"),
    "I": ("###", ".#.", ".#.", ".#.", "###"),
    "J": ("..#", "..#", "..#", "#.#", ".#."),
    "K": ("#.#", "#.#", "##.", "#.#", "#.#"),
    "L": ("#..", "#..", "#..", "#..", "###"),
    "M": ("#.#", "###", "###", "#.#", "#.#"),
    "N": ("##.", "#.#", "#.#", "#.#", "#.#"),
    "O": (".#.", "#.#", "#.#", "#.#", ".#."),
    "P": ("##.", "#.#", "##.", "#..", "#.."),
    "Q": (".#.", "#.#", "#.#", "##.", ".##"),
    "R": ("##.", "#.#", "##.", "#.#", "#.#"),
    "S": ("###", "#..", "###", "..#", "###"),
    "T": ("###", ".#.", ".#.", ".#.", ".#."),
    "U": ("#.#", "#.#", "#.#", "#.#", "###"),
    "V": ("#.#", "#.#", "#.#", "#.#", ".#."),
    "W": ("#.#", "#.#", "###", "###", "#.#"),
    "X": ("#.#", "#.#", ".#.", "#.#", "#.#"),
    "Y": ("#.#", "#.#", ".#.", ".#.", ".#."),
    "Z": ("###", "..#", ".#.", "#..", "###"),
    "-": ("...", "...", "###", "...", "..."),
    "+": ("...", ".#.", "###", ".#.", "..."),
    ".": ("...", "...", "...", "...", ".#."),
    ",": ("...", "...", "...", ".#.", "#.."),
    ":": ("...", ".#.", "...", ".#.", "..."),
    "/": ("..#", "..#", ".#.", "#..", "#.."),
    "%": ("#.#", "..#", ".#.", "#..", "#.#"),
    "=": ("...", "###", "...", "###", "..."),
    "(": (".#.", "#..", "#..", "#..", ".#."),
    ")": (".#.", "..#", "..#", "..#", ".#."),
    "!": (".#.", ".#.", ".#.", "...", ".#."),
    "?": ("###", "..#", ".##", "...", ".#."),
    "#": ("#.#", "###", "#.#", "###", "#.#"),
    "*": ("#.#", ".#.", "###", ".#.", "#.#"),
    "_": ("...", "...", "...", "...", "###"),
    "'": (".#.", ".#.", "...", "...", "..."),
    "<": ("..#", ".#.", "#..", ".#.", "..#"),
    ">": ("#..", ".#.", "..#", ".#.", "#.."),
}
_UNKNOWN = ("###", "#.#", "#.#", "#.#", "###")


@lru_cache(maxsize=512)
def text_bitmap(text: str, scale: int = 1) -> np.ndarray:
    """``bool[5 * scale, (4 * len(text) - 1) * scale]``: the text, one pixel column between glyphs."""
    if not text:
        return np.zeros((GLYPH_H * scale, 0), dtype=bool)
    cols = []
    for k, ch in enumerate(text):
        if k:
            cols.append(np.zeros((GLYPH_H, 1), dtype=bool))
        rows = _ROWS.get(ch.upper(), _UNKNOWN)
        cols.append(np.array([[c == "#" for c in row] for row in rows], dtype=bool))
    bitmap = np.concatenate(cols, axis=1)
    if scale > 1:
        bitmap = np.kron(bitmap, np.ones((scale, scale), dtype=bool))
    bitmap.setflags(write=False)
    return bitmap


def draw_text(img: np.ndarray, text: str, x: int, y: int, colour: tuple[int, int, int], scale: int = 1) -> None:
    """Paint ``text`` with its top-left corner at pixel ``(x, y)``, clipped to the image."""
    bitmap = text_bitmap(text, scale)
    h, w = bitmap.shape
    y0, x0 = max(0, y), max(0, x)
    y1, x1 = min(img.shape[0], y + h), min(img.shape[1], x + w)
    if y1 <= y0 or x1 <= x0:
        return
    img[y0:y1, x0:x1][bitmap[y0 - y : y1 - y, x0 - x : x1 - x]] = colour


def text_size(text: str, scale: int = 1) -> tuple[int, int]:
    """``(width, height)`` in pixels of ``text`` drawn at ``scale``."""
    return max(0, 4 * len(text) - 1) * scale, GLYPH_H * scale
