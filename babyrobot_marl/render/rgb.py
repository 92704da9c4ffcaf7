"""``rgb_array`` frames in pure numpy: the level drawn once, robots painted on a copy per frame.

A frame is ``uint8[height * cell_size, width * cell_size, 3]``. Walls are thick lines on cell
edges, glass walls dashed in their own colour, blocked cells filled, puddles tinted (large
darker), start cells labelled with their digit (``S`` for a lone start) and exits with ``E``.
Each robot is a disc in its own colour. The same state always gives the same bytes.

Themes are data: a ``Theme`` is a set of colours; ``THEMES`` holds the built-in ones.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..core.level import Cell, Level

Colour = tuple[int, int, int]


@dataclass(frozen=True)
class Theme:
    """The colours of a frame (RGB, 0..255)."""

    floor: Colour
    grid: Colour
    wall: Colour
    glass: Colour
    blocked: Colour
    small_puddle: Colour
    large_puddle: Colour
    exit: Colour
    start: Colour
    label: Colour
    robots: tuple[Colour, ...]


THEMES: dict[str, Theme] = {
    "light": Theme(
        floor=(245, 243, 236),
        grid=(220, 216, 205),
        wall=(60, 60, 70),
        glass=(90, 170, 220),
        blocked=(120, 120, 128),
        small_puddle=(170, 205, 235),
        large_puddle=(110, 160, 215),
        exit=(150, 215, 150),
        start=(235, 225, 170),
        label=(40, 40, 40),
        robots=((220, 60, 50), (50, 90, 210), (40, 160, 70), (160, 60, 180), (230, 150, 30), (30, 170, 180)),
    ),
    "dark": Theme(
        floor=(38, 40, 48),
        grid=(58, 60, 70),
        wall=(210, 210, 220),
        glass=(100, 190, 240),
        blocked=(90, 92, 104),
        small_puddle=(40, 70, 110),
        large_puddle=(30, 55, 150),
        exit=(40, 120, 60),
        start=(110, 100, 50),
        label=(235, 235, 235),
        robots=((255, 95, 85), (100, 150, 255), (90, 220, 120), (210, 120, 240), (255, 190, 70), (70, 220, 230)),
    ),
    "mono": Theme(
        floor=(255, 255, 255),
        grid=(225, 225, 225),
        wall=(0, 0, 0),
        glass=(150, 150, 150),
        blocked=(90, 90, 90),
        small_puddle=(215, 215, 215),
        large_puddle=(175, 175, 175),
        exit=(235, 235, 235),
        start=(245, 245, 245),
        label=(0, 0, 0),
        robots=((30, 30, 30), (110, 110, 110), (60, 60, 60), (140, 140, 140)),
    ),
}

# 3x5 bitmaps of the labels, one string per row ('#' on).
_GLYPHS = {
    "S": ("###", "#..", "###", "..#", "###"),
    "E": ("###", "#..", "###", "#..", "###"),
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
}
MIN_CELL_SIZE, MAX_CELL_SIZE = 8, 256


def resolve_theme(theme: str | Theme) -> Theme:
    if isinstance(theme, Theme):
        return theme
    if theme in THEMES:
        return THEMES[theme]
    raise ValueError(f"theme: unknown theme {theme!r}; built-in themes: {', '.join(THEMES)}, or pass a Theme")


def check_cell_size(cell_size: object) -> int:
    if isinstance(cell_size, bool) or not isinstance(cell_size, int) or not MIN_CELL_SIZE <= cell_size <= MAX_CELL_SIZE:
        raise ValueError(f"cell_size: must be an integer in {MIN_CELL_SIZE}..{MAX_CELL_SIZE} (pixels), got {cell_size!r}")
    return cell_size


class RgbRenderer:
    """Draws one level at one cell size and theme; ``frame(robots)`` returns a fresh image."""

    def __init__(self, level: Level, cell_size: int = 32, theme: str | Theme = "light"):
        self.level = level
        self.cell_size = check_cell_size(cell_size)
        self.theme = resolve_theme(theme)
        self.background = self._draw_level()
        self.background.setflags(write=False)
        r = (cell_size - 1) / 2
        yy, xx = np.mgrid[0:cell_size, 0:cell_size]
        self._disc = (yy - r) ** 2 + (xx - r) ** 2 <= (0.34 * cell_size) ** 2

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.background.shape  # type: ignore[return-value]

    def frame(self, robots: Sequence[Cell | None] = ()) -> np.ndarray:
        """The level with robot ``i`` as a disc at ``robots[i]`` (``None``: off the board).

        Robots sharing a cell (collisions "pass") show the lowest-numbered one on top.
        """
        img = self.background.copy()
        cs, colours = self.cell_size, self.theme.robots
        for i in reversed(range(len(robots))):
            cell = robots[i]
            if cell is None:
                continue
            x, y = cell
            img[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs][self._disc] = colours[i % len(colours)]
        return img

    # ------------------------------------------------------------------ the static layer
    def _draw_level(self) -> np.ndarray:
        lv, cs, th = self.level, self.cell_size, self.theme
        img = np.empty((lv.height * cs, lv.width * cs, 3), dtype=np.uint8)
        img[:] = th.floor
        img[::cs, :] = th.grid  # thin grid lines on the top and left of each cell
        img[:, ::cs] = th.grid
        fills = [
            (lv.small_puddles, th.small_puddle),
            (lv.large_puddles, th.large_puddle),
            (lv.exits, th.exit),
            (lv.starts, th.start),
            (lv.blocked, th.blocked),
        ]
        for cells, colour in fills:
            for x, y in cells:
                img[y * cs + 1 : (y + 1) * cs, x * cs + 1 : (x + 1) * cs] = colour
        labels = {c: ("S" if len(lv.starts) == 1 else str(i)) for i, c in enumerate(lv.starts) if i < 10}
        labels.update(dict.fromkeys(lv.exits, "E"))
        for cell, text in labels.items():
            self._label(img, cell, text)
        t = max(2, cs // 8)  # wall thickness
        for a, b in lv.walls:
            self._edge(img, a, b, t, th.wall, dashed=False)
        for a, b in lv.glass:
            self._edge(img, a, b, t, th.glass, dashed=True)
        img[:t, :] = th.wall  # the outer border
        img[-t:, :] = th.wall
        img[:, :t] = th.wall
        img[:, -t:] = th.wall
        return img

    def _edge(self, img: np.ndarray, a: Cell, b: Cell, t: int, colour: Colour, dashed: bool) -> None:
        cs = self.cell_size
        h = t // 2
        if a[1] == b[1]:  # horizontal neighbours: a vertical line at b's left edge
            x0, y0 = b[0] * cs - h, a[1] * cs
            strip = img[y0 : y0 + cs, max(0, x0) : x0 + t]
            along = np.arange(strip.shape[0])[:, None]
        else:  # vertical neighbours: a horizontal line at b's top edge
            x0, y0 = a[0] * cs, b[1] * cs - h
            strip = img[max(0, y0) : y0 + t, x0 : x0 + cs]
            along = np.arange(strip.shape[1])[None, :]
        if dashed:
            dash = max(2, cs // 6)
            on = np.broadcast_to((along // dash) % 2 == 0, strip.shape[:2])
            strip[on] = colour
        else:
            strip[:] = colour

    def _label(self, img: np.ndarray, cell: Cell, text: str) -> None:
        cs = self.cell_size
        glyph = np.array([[ch == "#" for ch in row] for row in _GLYPHS[text]])
        scale = max(1, cs // 16)
        bitmap = np.kron(glyph, np.ones((scale, scale), dtype=bool))
        gh, gw = bitmap.shape
        x0 = cell[0] * cs + (cs - gw) // 2
        y0 = cell[1] * cs + (cs - gh) // 2
        img[y0 : y0 + gh, x0 : x0 + gw][bitmap] = self.theme.label
