"""Real-browser test: a canvas whose panel gains a line at every step, past the room kept for it.
The browser clears a canvas it resizes, so the canvas keeps spare rows below its picture and the
panel grows into them by a change of CSS (``render/crop.py``): no frame shows the canvas empty or
a part of the picture (the level without its panel, say). Every animation frame of the page is
read (``record_canvas``). (Before the spare rows, each growth resized the canvas: 0-3 frames seen
empty for 10 resizes.) Harness: tests/browser."""

from __future__ import annotations

from babyrobot_marl.render.palette import THEMES
from tests.test_browser import CELL, cell_box, count
from tests.test_browser_replay import _open

THEME = THEMES["light"]


def test_a_panel_that_grows_mid_episode_never_blanks_the_canvas(page, screenshots):
    name = "growing_panel"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL}, animation_frames=2, render_fps=8)
        env.reset(seed=0)
        u = env.unwrapped
        for t, a in enumerate([2, 2, 3, 3, 2, 2, 2, 3, 2, 2], start=1):
            env.step(a)
            u.set_overlay(panel=[f"step {{t}}  return {{-t}}"] + ["moved"] * (t - 1))
        """,
    ], before=page.record_canvas)  # fmt: skip
    # the last step's frame: the robot at (7, 3)
    page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], (7, 3)), THEME.robots[0]) > 50)
    frames = page.recorded_frames()
    page.log(f"{len(frames)} canvas changes seen; first {frames[:2]}")
    assert len(frames) >= 3, frames
    empty = [f for f in frames if f["sig"] == 0]
    partial = [f for f in frames if not f["drawn"] and f["sig"] != 0]
    page.log(f"frames seen empty while the canvas grew: {len(empty)}")
    assert not empty, f"{len(empty)} frames showed the canvas empty: {empty[:5]}"
    assert not partial, f"{len(partial)} frames showed a part of the picture: {partial[:5]}"
    assert frames[-1]["drawn"]
