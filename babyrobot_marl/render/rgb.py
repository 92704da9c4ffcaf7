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

from ..checks import check_int
from ..core.level import Cell, Level
from .font import draw_text, text_size
from .geometry import ARROWS, CELL_TEXT_CENTRE, ROBOT_RADIUS, TRIANGLES, VALUE_TEXT_CENTRE, cell_mask
from .overlay import Overlay, format_value, value_colours

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
    # overlays: value tints from low to high, arrows, overlay text, the panel below the grid
    value_low: Colour = (214, 96, 77)
    value_high: Colour = (77, 172, 120)
    arrow: Colour = (40, 40, 40)
    text: Colour = (20, 20, 20)
    panel: Colour = (250, 250, 250)


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
        value_low=(150, 60, 50),
        value_high=(50, 130, 80),
        arrow=(240, 240, 240),
        text=(240, 240, 240),
        panel=(30, 32, 38),
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
        value_low=(120, 120, 120),
        value_high=(245, 245, 245),
        arrow=(0, 0, 0),
        text=(0, 0, 0),
        panel=(255, 255, 255),
    ),
}

MIN_CELL_SIZE, MAX_CELL_SIZE = 8, 256


def resolve_theme(theme: str | Theme) -> Theme:
    if isinstance(theme, Theme):
        return theme
    if theme in THEMES:
        return THEMES[theme]
    raise ValueError(f"theme: unknown theme {theme!r}; built-in themes: {', '.join(THEMES)}, or pass a Theme")


def check_cell_size(cell_size: object) -> int:
    return check_int(cell_size, "cell_size", MIN_CELL_SIZE, MAX_CELL_SIZE)  # numpy integers too


class RgbRenderer:
    """Draws one level at one cell size and theme; ``frame(robots)`` returns a fresh image.

    Layers, bottom to top: the level, the overlay's tints (values, action values), the robots,
    the overlay's ink (arrows, text), the panel below the grid. The live canvas stacks the same.
    """

    def __init__(self, level: Level, cell_size: int = 32, theme: str | Theme = "light"):
        self.level = level
        self.cell_size = check_cell_size(cell_size)
        self.theme = resolve_theme(theme)
        self.background = self._draw_level()
        self.background.setflags(write=False)
        r = (cell_size - 1) / 2
        yy, xx = np.mgrid[0:cell_size, 0:cell_size]
        self._disc = (yy - r) ** 2 + (xx - r) ** 2 <= (ROBOT_RADIUS * cell_size) ** 2
        # an Overlay is immutable: its images are drawn once, then copied per frame
        self._tinted: tuple[tuple[object, object], np.ndarray] = ((None, None), self.background)
        self._overlaid: tuple[Overlay | None, np.ndarray, np.ndarray] = (None, self.background, np.zeros((0, 0), bool))

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.background.shape  # type: ignore[return-value]

    def frame(self, robots: Sequence[Cell | None] = (), overlay: Overlay | None = None) -> np.ndarray:
        """The level with robot ``i`` as a disc at ``robots[i]`` (``None``: off the board).

        Robots sharing a cell (collisions "pass") show the lowest-numbered one on top. An
        ``overlay``'s tints are drawn under the robots, its arrows and text over them; its
        panel makes the frame taller.
        """
        if overlay is None or overlay.empty:
            img, ink = self.background.copy(), None
        else:
            if self._overlaid[0] is not overlay:
                image, ink = self._overlay_layers(overlay)
                image.setflags(write=False)
                self._overlaid = (overlay, image, ink)
            image, ink = self._overlaid[1], self._overlaid[2]
            img = image.copy()
        cs, colours = self.cell_size, self.theme.robots
        for i in reversed(range(len(robots))):
            cell = robots[i]
            if cell is None:
                continue
            x, y = cell
            img[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs][self._disc] = colours[i % len(colours)]
        if ink is not None:  # arrows and text back over the robots
            for cell in set(c for c in robots if c is not None):
                x, y = cell
                box = (slice(y * cs, (y + 1) * cs), slice(x * cs, (x + 1) * cs))
                on = ink[box]
                img[box][on] = image[box][on]
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
        scale = max(1, cs // 16)
        gw, gh = text_size(text, scale)
        draw_text(img, text, cell[0] * cs + (cs - gw) // 2, cell[1] * cs + (cs - gh) // 2, self.theme.label, scale)

    # ------------------------------------------------------------------ overlays
    def tinted(self, overlay: Overlay) -> np.ndarray:
        """The level with the overlay's value and action-value tints (read-only; the live
        canvas's static layer). The same arrays give the same image object back."""
        key = (overlay.values, overlay.q_values)
        if self._tinted[0][0] is key[0] and self._tinted[0][1] is key[1]:
            return self._tinted[1]
        img = self.background.copy()
        cs, th = self.cell_size, self.theme
        if overlay.values is not None:
            colours = value_colours(overlay.values, th.value_low, th.value_high)
            self._tint(img, colours, np.isfinite(overlay.values), self._interior)
        if overlay.q_values is not None:
            colours = value_colours(overlay.q_values[:, :, 1:], th.value_low, th.value_high)
            for action, polygon in TRIANGLES.items():
                on = np.isfinite(overlay.q_values[:, :, action])
                self._tint(img, colours[:, :, action - 1], on, cell_mask(polygon, cs) & self._interior)
        img.setflags(write=False)
        self._tinted = (key, img)
        return img

    def overlay_image(self, overlay: Overlay) -> np.ndarray:
        """The level with ``overlay`` drawn on it (and its panel below), without robots."""
        return self._overlay_layers(overlay)[0]

    def _overlay_layers(self, overlay: Overlay) -> tuple[np.ndarray, np.ndarray]:
        """The overlay image and ``bool[H * cs, W * cs]``: its ink (arrows, text) pixels."""
        img = self.tinted(overlay).copy()
        ink = np.zeros(img.shape[:2], dtype=bool)
        lv, cs, th = self.level, self.cell_size, self.theme
        if overlay.arrows is not None:
            for action, polygon in ARROWS.items():
                on = np.repeat(np.repeat(overlay.arrows[:, :, action], cs, axis=0), cs, axis=1)
                on &= np.tile(cell_mask(polygon, cs), (lv.height, lv.width))
                img[on] = th.arrow
                ink |= on
        if overlay.values is not None and cs >= 24:  # the numbers, where they fit
            for y, x in zip(*np.nonzero(np.isfinite(overlay.values))):
                self._cell_text(img, ink, format_value(float(overlay.values[y, x])), int(x), int(y), VALUE_TEXT_CENTRE)
        for (x, y), text in overlay.text.items():
            self._cell_text(img, ink, text, x, y, CELL_TEXT_CENTRE)
        if overlay.panel:
            img = np.concatenate([img, self._panel(overlay.panel, img.shape[1])], axis=0)
        return img, ink

    @property
    def _inset(self) -> int:
        return max(2, self.cell_size // 8)  # the wall thickness: tints stay inside the walls

    @property
    def _interior(self) -> np.ndarray:
        cs, m = self.cell_size, self._inset
        mask = np.zeros((cs, cs), dtype=bool)
        mask[m : cs - m, m : cs - m] = True
        return mask

    def _tint(self, img: np.ndarray, colours: np.ndarray, on: np.ndarray, cell_pixels: np.ndarray) -> None:
        """Blend ``colours[y, x]`` over the ``cell_pixels`` of every cell where ``on[y, x]``."""
        cs, lv = self.cell_size, self.level
        big = np.repeat(np.repeat(colours, cs, axis=0), cs, axis=1)
        mask = np.repeat(np.repeat(on, cs, axis=0), cs, axis=1) & np.tile(cell_pixels, (lv.height, lv.width))
        img[mask] = (0.35 * img[mask] + 0.65 * big[mask]).astype(np.uint8)

    def _cell_text(self, img: np.ndarray, ink: np.ndarray, text: str, x: int, y: int, centre: tuple[float, float]) -> None:
        """``text`` centred on the point ``centre`` (cell units) of cell ``(x, y)``, kept inside the walls."""
        cs, m = self.cell_size, self._inset
        scale = max(1, cs // 32)
        w, h = text_size(text, scale)
        tx = min(max(round((x + centre[0]) * cs - w / 2), x * cs + m), (x + 1) * cs - m - w)
        ty = min(max(round((y + centre[1]) * cs - h / 2), y * cs + m + 1), (y + 1) * cs - m - 1 - h)
        tx = max(tx, x * cs + m)  # too wide for the cell: start inside it and clip at the edge of the image
        draw_text(img, text, tx, ty, self.theme.text, scale)
        draw_text(ink, text, tx, ty, True, scale)  # type: ignore[arg-type]  # the same pixels in the ink mask

    def _panel(self, lines: tuple[str, ...], width: int) -> np.ndarray:
        scale = max(1, self.cell_size // 16)
        line_h = (5 + 2) * scale
        panel = np.empty((len(lines) * line_h + 3 * scale, width, 3), dtype=np.uint8)
        panel[:] = self.theme.panel
        for k, line in enumerate(lines):
            draw_text(panel, line, 2 * scale, 2 * scale + k * line_h, self.theme.text, scale)
        return panel
