"""Colours as data: themes, robot colours, colour maps, and the contrast measures the tests use.

A ``Theme`` is a frozen set of RGB colours; ``THEMES`` holds the built-in ones (light, dark,
mono, high-contrast). The first eight robot colours are the Okabe-Ito palette (made for
colour-blind readers) with a slate grey; robots also carry their number, so any count stays
distinguishable. Values are coloured with viridis or cividis: perceptually uniform, readable
with every common colour-vision deficiency, and in order when printed in grey.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

Colour = tuple[int, int, int]

ROBOT_COLOURS: tuple[Colour, ...] = (
    (0, 114, 178),  # blue
    (230, 159, 0),  # orange
    (0, 158, 115),  # bluish green
    (213, 94, 0),  # vermillion
    (86, 180, 233),  # sky blue
    (204, 121, 167),  # reddish purple
    (240, 228, 66),  # yellow
    (110, 116, 132),  # slate
    (136, 34, 85),  # wine
    (153, 153, 51),  # olive
    (68, 170, 153),  # teal
    (51, 34, 136),  # indigo
)

COLOUR_MAPS: dict[str, tuple[Colour, ...]] = {  # 17 evenly spaced stops (matplotlib's data, CC0)
    "viridis": (
        (68, 1, 84), (72, 24, 106), (71, 45, 123), (66, 64, 134), (59, 82, 139), (51, 99, 141),
        (44, 114, 142), (38, 130, 142), (33, 145, 140), (31, 160, 136), (40, 174, 128), (63, 188, 115),
        (94, 201, 98), (132, 212, 75), (173, 220, 48), (216, 226, 25), (253, 231, 37),
    ),
    "cividis": (
        (0, 34, 78), (0, 46, 106), (26, 56, 111), (50, 67, 109), (67, 78, 108), (83, 90, 109),
        (97, 101, 111), (111, 112, 115), (125, 124, 120), (140, 136, 120), (155, 148, 118), (171, 160, 114),
        (188, 174, 108), (205, 187, 99), (222, 201, 88), (240, 216, 70), (254, 232, 56),
    ),
    "greys": tuple((v, v, v) for v in np.linspace(40, 240, 17).round().astype(int).tolist()),
}  # fmt: skip


@dataclass(frozen=True)
class Theme:
    """Every colour of a picture (RGB 0..255). ``replace(theme, floor=...)`` makes a variant."""

    floor: Colour
    floor_line: Colour  # the faint tile lines
    wall: Colour
    glass: Colour  # the pane
    glass_frame: Colour  # its frame and glint
    blocked: Colour
    small_puddle: Colour
    large_puddle: Colour
    exit: Colour
    exit_ink: Colour  # the door icon
    start: Colour
    start_ink: Colour  # the flag icon
    label_bg: Colour  # START / EXIT pills
    label_text: Colour
    robot_ink: Colour  # outlines of robots and marks
    visor: Colour
    eye: Colour
    value_box: Colour
    value_text: Colour
    arrow: Colour
    arrow_edge: Colour
    text: Colour  # panel and legend text
    panel: Colour
    mark: Colour  # the burst where a robot was stopped
    colour_map: str = "viridis"
    robots: tuple[Colour, ...] = ROBOT_COLOURS

    # the names the renderers used before this palette (kept: custom themes and tests use them)
    @property
    def grid(self) -> Colour:
        return self.floor_line

    @property
    def label(self) -> Colour:
        return self.label_text


THEMES: dict[str, Theme] = {
    "light": Theme(
        floor=(246, 243, 234), floor_line=(226, 220, 206), wall=(52, 58, 74),
        glass=(176, 226, 248), glass_frame=(24, 104, 160), blocked=(132, 128, 140),
        small_puddle=(76, 142, 214), large_puddle=(52, 110, 192), exit=(150, 214, 140), exit_ink=(28, 96, 44),
        start=(250, 224, 140), start_ink=(120, 84, 0), label_bg=(36, 40, 52), label_text=(255, 255, 255),
        robot_ink=(30, 32, 44), visor=(30, 34, 50), eye=(150, 240, 255), value_box=(22, 24, 32),
        value_text=(255, 255, 255), arrow=(255, 255, 255), arrow_edge=(22, 24, 32), text=(30, 32, 40),
        panel=(250, 248, 242), mark=(240, 70, 30),
    ),
    "dark": Theme(
        floor=(36, 40, 50), floor_line=(50, 55, 68), wall=(214, 218, 230),
        glass=(40, 110, 160), glass_frame=(190, 236, 255), blocked=(112, 116, 132),
        small_puddle=(84, 152, 214), large_puddle=(54, 116, 200), exit=(36, 116, 60), exit_ink=(180, 240, 190),
        start=(116, 96, 36), start_ink=(255, 226, 140), label_bg=(236, 238, 244), label_text=(20, 22, 30),
        robot_ink=(232, 234, 242), visor=(22, 24, 34), eye=(150, 240, 255), value_box=(12, 14, 20),
        value_text=(255, 255, 255), arrow=(255, 255, 255), arrow_edge=(12, 14, 20), text=(236, 238, 244),
        panel=(28, 31, 40), mark=(255, 110, 60),
    ),
    "mono": Theme(
        floor=(255, 255, 255), floor_line=(228, 228, 228), wall=(0, 0, 0),
        glass=(215, 215, 215), glass_frame=(70, 70, 70), blocked=(110, 110, 110),
        small_puddle=(148, 148, 148), large_puddle=(100, 100, 100), exit=(185, 185, 185), exit_ink=(0, 0, 0),
        start=(222, 222, 222), start_ink=(0, 0, 0), label_bg=(0, 0, 0), label_text=(255, 255, 255),
        robot_ink=(0, 0, 0), visor=(20, 20, 20), eye=(255, 255, 255), value_box=(0, 0, 0),
        value_text=(255, 255, 255), arrow=(255, 255, 255), arrow_edge=(0, 0, 0), text=(0, 0, 0),
        panel=(255, 255, 255), mark=(0, 0, 0), colour_map="greys",
        robots=((70, 70, 70), (150, 150, 150), (110, 110, 110), (190, 190, 190)),
    ),
    "high-contrast": Theme(
        floor=(255, 255, 255), floor_line=(200, 200, 200), wall=(0, 0, 0),
        glass=(120, 210, 255), glass_frame=(0, 40, 160), blocked=(60, 60, 60),
        small_puddle=(76, 136, 228), large_puddle=(0, 70, 200), exit=(0, 160, 60), exit_ink=(255, 255, 255),
        start=(255, 210, 0), start_ink=(0, 0, 0), label_bg=(0, 0, 0), label_text=(255, 255, 255),
        robot_ink=(0, 0, 0), visor=(0, 0, 0), eye=(255, 255, 255), value_box=(0, 0, 0),
        value_text=(255, 255, 255), arrow=(255, 255, 255), arrow_edge=(0, 0, 0), text=(0, 0, 0),
        panel=(255, 255, 255), mark=(220, 0, 0), colour_map="cividis",
    ),
}  # fmt: skip


def resolve_theme(theme: str | Theme) -> Theme:
    if isinstance(theme, Theme):
        return theme
    if isinstance(theme, str) and theme in THEMES:
        return THEMES[theme]
    raise ValueError(f"theme: unknown theme {theme!r}; built-in themes: {', '.join(THEMES)}, or pass a Theme")


def variant(theme: Theme, **colours: Colour) -> Theme:
    """A copy of ``theme`` with some colours replaced."""
    return replace(theme, **colours)


def robot_colour(theme: Theme, i: int) -> Colour:
    return theme.robots[i % len(theme.robots)]


def tile_edge(theme: Theme, ink: Colour) -> Colour:
    """The line round a START or EXIT tile: its icon's ``ink`` where that stands out on the floor
    (3:1, as graphics need), else the robots' ink; pale tiles keep their shape on every floor."""
    return ink if contrast_ratio(ink, theme.floor) >= 3.0 else theme.robot_ink


def colour_map(values: np.ndarray, name: str, lo: float | None = None, hi: float | None = None) -> np.ndarray:
    """``uint8[..., 3]``: finite values placed on the colour map between ``lo`` and ``hi`` (default:
    their minimum and maximum; all equal: the middle colour). Non-finite values get the lowest colour."""
    finite = np.isfinite(values)
    if lo is None or hi is None:
        lo = float(values[finite].min()) if finite.any() else 0.0
        hi = float(values[finite].max()) if finite.any() else 0.0
    if hi == lo:
        t = np.full(values.shape, 0.5)
    else:  # scaled first: values near the float maximum give no overflow in the differences
        s = max(abs(lo), abs(hi))
        t = (np.where(finite, values, lo) / s - lo / s) / (hi / s - lo / s)
    stops = np.array(COLOUR_MAPS[name], dtype=np.float64)
    pos = np.clip(t, 0.0, 1.0) * (len(stops) - 1)
    k = np.minimum(pos.astype(int), len(stops) - 2)
    f = (pos - k)[..., None]
    return np.rint(stops[k] * (1 - f) + stops[k + 1] * f).astype(np.uint8)


# ---------------------------------------------------------------------- contrast measures (tests, docs)
def _linear(c: np.ndarray) -> np.ndarray:
    c = np.asarray(c, dtype=np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def luminance(c: Colour) -> float:
    r, g, b = _linear(np.array(c))
    return float(0.2126 * r + 0.7152 * g + 0.0722 * b)


def contrast_ratio(a: Colour, b: Colour) -> float:
    """WCAG 2 contrast ratio, 1..21 (text wants >= 4.5, graphics >= 3)."""
    la, lb = sorted((luminance(a), luminance(b)), reverse=True)
    return (la + 0.05) / (lb + 0.05)


def lab(c: Colour) -> np.ndarray:
    lin = _linear(np.array(c))
    m = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = m @ lin / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e(a: Colour, b: Colour) -> float:
    """CIE76 colour difference (about 2.3: just noticeable; > 20: clearly different)."""
    return float(np.linalg.norm(lab(a) - lab(b)))


_CVD = {  # Machado, Oliveira and Fernandes (2009), severity 1.0, on linear RGB
    "protanopia": ((0.152286, 1.052583, -0.204868), (0.114503, 0.786281, 0.099216), (-0.003882, -0.048116, 1.051998)),
    "deuteranopia": ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413), (-0.011820, 0.042940, 0.968881)),
    "tritanopia": ((1.255528, -0.076749, -0.178779), (-0.078411, 0.930809, 0.147602), (0.004733, 0.691367, 0.303900)),
}


def simulate_cvd(c: Colour, kind: str) -> Colour:
    """``c`` as seen with a colour-vision deficiency (``protanopia``, ``deuteranopia``, ``tritanopia``)."""
    lin = np.clip(np.array(_CVD[kind]) @ _linear(np.array(c)), 0.0, 1.0)
    srgb = np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)
    return tuple(int(v) for v in np.rint(srgb * 255))  # type: ignore[return-value]
