"""Real-browser measure: an episode of 160 planned frames (40 steps of 4 frames at 4 steps a
second: one every 62.5 ms). Every animation frame of the page is read (``record_canvas``); the
canvas changes seen, their median gap, the frames the kernel dropped to keep to the clock and the
machine's load are printed: figures, not a test of speed. What is tested: frames are dropped,
never the picture (no frame shows the canvas empty or partly drawn), and the last frame shows
the episode's end. Harness: tests/browser."""

from __future__ import annotations

import os

import numpy as np

from babyrobot_marl.render.palette import THEMES
from tests.test_browser import CELL, cell_box, count
from tests.test_browser_replay import _open

THEME = THEMES["light"]
STEPS, FRAMES, FPS = 40, 4, 4


def test_an_episode_of_160_frames_keeps_to_the_clock_and_never_blanks(page, screenshots):
    name = "pacing"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL}, animation_frames={FRAMES},
                           render_fps={FPS})
        env.reset(seed=0)
        for t in range({STEPS}):
            env.step(2 if t % 2 == 0 else 4)  # east and back west: a glide at every step
        """,
    ], before=page.record_canvas)  # fmt: skip
    # the last step's frame: the robot back at (0, 0)
    page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], (0, 0)), THEME.robots[0]) > 50)
    frames = page.recorded_frames()
    sent = page.kernel_output("print(env.unwrapped.canvas.frames_sent, env.unwrapped.canvas.pacer.dropped)").strip()
    drawn = [f for f in frames if f["drawn"]]
    first = 1 if len(drawn) > 1 else 0  # from the first change after the canvas appeared
    times = np.array([f["t"] for f in drawn[first:]])
    gaps = np.diff(times)
    load = os.getloadavg()
    page.log(f"{STEPS * FRAMES} frames planned ({1000 / (FPS * FRAMES):.1f} ms apart); {len(drawn)} canvas changes seen "
             f"over {(times[-1] - times[0]) / 1000:.2f} s, median gap {np.median(gaps):.1f} ms; kernel batches sent, "
             f"frames dropped: {sent}; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")  # fmt: skip
    empty = [f for f in frames if f["sig"] == 0]
    partial = [f for f in frames if not f["drawn"] and f["sig"] != 0]
    assert not empty, f"{len(empty)} frames showed the canvas empty: {empty[:5]}"
    assert not partial, f"{len(partial)} frames showed a part of the picture: {partial[:5]}"
    assert frames[-1]["drawn"] and len(drawn) >= STEPS // 2  # the robot seen moving, step after step
