"""Every kind of terrain stands out from the floor (WCAG 3:1, as graphics need) in every theme:
measured on the theme's colours and on the drawn picture."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import levels
from babyrobot_marl.render.palette import THEMES, contrast_ratio, luminance
from babyrobot_marl.render.rgb import RgbRenderer

# the colour that sets each kind apart from the floor: its fill, or the line round it
FILLED = ("wall", "small_puddle", "large_puddle", "blocked")
OUTLINED = {"glass": "glass_frame", "own-goal target": "robot_ink"}


@pytest.mark.parametrize("name", sorted(THEMES))
def test_every_filled_terrain_kind_stands_out_from_the_floor(name):
    t = THEMES[name]
    for kind in FILLED:
        ratio = contrast_ratio(getattr(t, kind), t.floor)
        assert ratio >= 3.0, f"{name}: {kind} {ratio:.2f}:1 against the floor"
    for kind, line in OUTLINED.items():
        ratio = contrast_ratio(getattr(t, line), t.floor)
        assert ratio >= 3.0, f"{name}: {kind}'s {line} {ratio:.2f}:1 against the floor"


@pytest.mark.parametrize("name", sorted(THEMES))
def test_the_large_puddle_is_deeper_than_the_small_one(name):
    """Darker than the small one in every theme, light or dark floor."""
    t = THEMES[name]
    assert luminance(t.large_puddle) < luminance(t.small_puddle), name


def _best_contrast(pixels: np.ndarray, floor) -> float:
    return max(contrast_ratio(tuple(int(v) for v in p), floor) for p in pixels)


@pytest.mark.parametrize("cs", [16, 32, 64])
@pytest.mark.parametrize("name", sorted(THEMES))
def test_start_and_exit_tiles_are_outlined_against_the_floor(name, cs):
    """A pale START or EXIT tile keeps its edge: across the side of the tile that has no wall, some
    pixel stands 3:1 against the floor (its fill or its outline)."""
    level = levels.get("mixed-8x8")  # START at (0, 0), open to its right; EXIT at (7, 7), open to its left
    assert (0, 0) in level.starts and (7, 7) in level.exits
    img = RgbRenderer(level, cs, name).background
    floor = THEMES[name].floor
    mid, band = cs // 2, max(2, cs // 10)
    start_edge = img[mid, cs - band : cs]  # the start tile's right side, up to the cell's edge
    exit_edge = img[7 * cs + mid, 7 * cs : 7 * cs + band]  # the exit tile's left side
    for kind, pixels in (("START", start_edge), ("EXIT", exit_edge)):
        ratio = _best_contrast(pixels, floor)
        assert ratio >= 3.0, f"{name} at {cs} px: {kind}'s edge {ratio:.2f}:1 against the floor"
