"""An episode stopped before its end (a loop of 40 steps that never reached the exit) still gets
its replay bar once the notebook cell finishes; an unchanged canvas is not offered it again."""

from __future__ import annotations

import pytest

pytest.importorskip("ipycanvas")

from babyrobot_marl import levels  # noqa: E402
from babyrobot_marl.render import canvas as live  # noqa: E402
from babyrobot_marl.render.rgb import RgbRenderer  # noqa: E402


def test_a_cell_that_stops_an_episode_midway_leaves_a_replay_bar(monkeypatch):
    c = live.LiveCanvas(RgbRenderer(levels.get("mixed-8x8"), 32), animation_frames=0, fps=0)
    bar = c.replay_bar()
    monkeypatch.setattr(live, "_shown", live.deque([c], maxlen=live.MAX_TRACKED))
    for cell in [(0, 0), (1, 0), (2, 0), (2, 1)]:  # not done: the episode goes on
        c.draw([cell])
    assert bar.widget.layout.display == "none"  # nothing offered while the cell runs
    live._after_cell()  # IPython's post_run_cell
    assert bar.widget.layout.display == "flex"
    assert bar.slider.max == len(c.history) - 1 == 3
    bar.slider.value = 0  # the bar replays the start
    assert c._replaying == 0
    c.draw([(3, 1)])  # the next cell steps on: the bar follows at its end
    live._after_cell()
    assert bar.slider.max == 4
