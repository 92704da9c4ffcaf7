"""The still a saved notebook keeps: the canvas's picture at its backing store's resolution, the panel too."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("ipycanvas", reason="the notebook extra (ipycanvas) is part of the test extra; CI installs it")

from babyrobot_marl import levels, race_v0  # noqa: E402
from babyrobot_marl.render import canvas as live  # noqa: E402
from babyrobot_marl.render.overlay import Overlay, update_overlay  # noqa: E402
from babyrobot_marl.render.palette import THEMES  # noqa: E402
from babyrobot_marl.render.rgb import RgbRenderer  # noqa: E402


def ink_box(img: np.ndarray, colour) -> tuple[int, int, int, int]:
    """The box (x0, y0, x1, y1) of the pixels near ``colour`` (the panel's text)."""
    ys, xs = np.nonzero(np.abs(img.astype(int) - colour).max(axis=2) < 80)
    return int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1


@pytest.mark.parametrize("cs", [24, 32, 48])
def test_the_stills_panel_is_the_rgb_array_panel_drawn_twice_as_large(cs):
    """The still is drawn at two device pixels per CSS pixel: its panel's text is twice the
    size of the same panel in the rgb_array frame, where it was laid out for a cell twice as
    large (small text, blurred when the page scales it to the canvas's CSS size)."""
    level = levels.get("maze-8x8")
    c = live.LiveCanvas(RgbRenderer(level, cs), fps=0, animation_frames=0)
    overlay = update_overlay(Overlay(), level, panel=["episode 3  return -7"])
    c.draw([(1, 1)], overlay)
    still, frame = c.picture(), c.frame()
    ink = THEMES["light"].text
    x0, y0, x1, y1 = ink_box(still[c.hi.grid_height :], ink)
    u0, v0, u1, v1 = ink_box(frame[c.renderer.grid_height :], ink)
    assert abs((y1 - y0) - 2 * (v1 - v0)) <= 2 and abs((x1 - x0) - 2 * (u1 - u0)) <= 4
    assert abs(y0 - 2 * v0) <= 2 and abs(x0 - 2 * u0) <= 2


def test_the_stills_legend_rows_are_the_rgb_array_rows_drawn_twice_as_large():
    env = race_v0.parallel_env(level="maze-8x8", n_robots=3, start="random", render_mode="rgb_array", cell_size=32)
    env.reset(seed=0)
    c = live.LiveCanvas(env.unwrapped.drawing.renderer, fps=0, animation_frames=0)
    c.draw(env.unwrapped._scene())
    still, frame = c.picture(), c.frame()
    ink = THEMES["light"].text
    x0, y0, x1, y1 = ink_box(still[c.hi.grid_height :], ink)
    u0, v0, u1, v1 = ink_box(frame[c.renderer.grid_height :], ink)
    assert abs((y1 - y0) - 2 * (v1 - v0)) <= 8 and abs(y0 - 2 * v0) <= 3  # rows rounded to whole pixels
