"""Real-browser tests of the live canvas's first frame and its replay (issue 26 items 3 and 6).

- No blank first frame: from the moment the canvas output appears on the page, every animation
  frame of the page shows it drawn (read in the page at each animation frame, ``record_canvas``).
- Replay: after an episode the replay bar (slider and play button) shows under the canvas; dragging
  the slider to its start draws the first scene on the same canvas, and the kernel's env has not
  stepped (its step counter and the canvas's scenes unchanged). For one robot and for a race.

Every wait is for an event, with the harness's limit (``chrome.WAIT``). The intervals between the
frames drawn in the first steps are printed (a figure, not a test).
"""

from __future__ import annotations

import numpy as np

from babyrobot_marl.render.palette import THEMES
from tests.test_browser import CELL, MARKER, cell_box, count, shot

THEME = THEMES["light"]
# mixed-8x8 from (0, 0) to its exit (7, 7) along a shortest path (14 steps)
PATH = [2, 2, 3, 3, 2, 2, 2, 3, 2, 2, 3, 3, 3, 3]


def _open(page, screenshots, name: str, cells: list[str], before=None) -> None:
    from tests.browser.notebook_files import write_notebook

    write_notebook(page.lab.root_dir / f"{name}.ipynb", [*cells, f"print({MARKER!r})"])
    try:
        page.run_all(f"{name}.ipynb", MARKER, before=before)
    finally:
        shot(page, screenshots, name)


def signature(rgba: np.ndarray) -> int:
    """The page's checksum of a canvas's pixels (``_RECORD_CANVAS`` in tests/browser/chrome.py)."""
    sig = 0
    flat = rgba.reshape(-1)
    for i in range(0, flat.size, 28):
        sig = (sig * 31 + int(flat[i]) + 3 * int(flat[i + 1]) + 7 * int(flat[i + 2])) % 2**32
    return sig


def test_no_blank_first_frame(page, screenshots):
    """From the first animation frame the canvas is on the page, it shows the level with the robot:
    the picture it keeps (no blank canvas, no level without its robot, before any step)."""
    name = "first_frame"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL})
        env.reset(seed=0)
        """,
    ], before=page.record_canvas)  # fmt: skip
    final = page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], (0, 0)), THEME.robots[0]) > 50)
    frames = page.recorded_frames()
    assert frames, "the canvas was never seen on the page"
    assert frames[0]["drawn"], f"the canvas appeared blank (not drawn) at first: {frames[:3]}"
    assert [f["sig"] for f in frames] == [signature(final)], f"the canvas changed after it appeared: {frames}"


def test_the_first_steps_are_paced_as_the_others(page, screenshots):
    """Eight steps at 4 a second right after the canvas is shown: each step's frame seen, none
    blank; the times between them are printed (the first step's stall of issue 26, if any)."""
    name = "first_steps"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL}, animation_frames=1, render_fps=4)
        env.reset(seed=0)
        for a in {PATH[:8]}:
            env.step(a)
        """,
    ], before=page.record_canvas)  # fmt: skip
    # the last step's frame (the robot where the eight steps take it), then the record
    page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], (5, 3)), THEME.robots[0]) > 50)
    frames = page.recorded_frames()
    assert frames and all(f["drawn"] for f in frames), f"a blank canvas was seen: {frames}"
    times = [round(f["t"] - frames[0]["t"]) for f in frames]
    page.log(f"{name}: canvas changes at {times} ms after it appeared (4 steps a second intended: 250 ms apart)")
    assert len(frames) >= 8, f"fewer changes than steps: {times}"


