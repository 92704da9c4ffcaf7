"""The race legend stays a few rows tall, and the frame limit counts the whole frame (grid, panel, legend)."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv, levels, race_v0
from babyrobot_marl.render.checks import MAX_FRAME_PIXELS, check_frame_size
from babyrobot_marl.render.overlay import Overlay, update_overlay
from babyrobot_marl.render.palette import THEMES, robot_colour
from babyrobot_marl.render.panel import (
    COMPACT_LINES,
    LEGEND_ROWS,
    LegendRow,
    compact_layout,
    legend_rows,
    panel_height,
    panel_sections,
)
from babyrobot_marl.render.rgb import RgbRenderer
from babyrobot_marl.render.scene import Scene


def race_frame(n: int, steps: int = 0, **kw) -> tuple[np.ndarray, object]:
    env = race_v0.parallel_env(level="maze-16x16", n_robots=n, start="random", render_mode="rgb_array", **kw)
    env.reset(seed=0)
    for _ in range(steps):
        env.step({a: 2 for a in env.agents})
    return env.render(), env.unwrapped


@pytest.mark.parametrize("n", [9, 12, 100])
def test_a_large_race_legend_is_compact_a_few_lines_of_entries(n):
    frame, race = race_frame(n)
    grid = race.level.height * race.cell_size
    cols, lines = compact_layout(frame.shape[1], race.cell_size, n)
    assert lines <= COMPACT_LINES and cols >= 4  # 768 pixels across: several entries a line
    assert frame.shape == (grid + panel_height(frame.shape[1], race.cell_size, robots=n), race.level.width * race.cell_size, 3)
    assert frame.shape[0] - grid < panel_height(frame.shape[1], race.cell_size, robots=8) / 2


@pytest.mark.parametrize("cs", [32, 48, 64])
@pytest.mark.parametrize("n", [12, 32])
def test_beyond_eight_robots_the_legend_takes_a_small_share_of_the_picture(cs, n):
    """Issue 26: a 12-robot legend took a quarter of the picture (a third on an 8x8 level at 64 px)."""
    env = race_v0.parallel_env(level="mixed-8x8", n_robots=n, start="random", render_mode="rgb_array", cell_size=cs)
    env.reset(seed=0)
    frame = env.render()
    share = 1 - 8 * cs / frame.shape[0]  # the rows below the grid
    assert share <= {32: 0.23, 48: 0.17, 64: 0.16}[cs], share


def test_the_compact_legend_shows_each_robot_it_lists_with_its_colour():
    frame, race = race_frame(12, cell_size=48)  # 768 pixels across: all twelve fit
    panel = frame[race.level.height * race.cell_size :]
    theme = race.theme
    for i in range(12):
        colour = np.array(robot_colour(theme, i))
        assert (np.abs(panel.astype(int) - colour).sum(axis=2) < 8).sum() >= 6, i  # its icon's body


def test_the_legend_lists_every_robot_up_to_eight_then_the_leaders_and_a_row_counting_the_rest():
    rows = [LegendRow(i, "", -float(i), 0, True) for i in range(6)]
    assert legend_rows(rows) == (rows, "")
    rows = [LegendRow(i, "", -5.0 + (i == 9), 0, True) for i in range(12)]
    rows[4] = LegendRow(4, "", -2.0, 2, False)  # finished second
    rows[7] = LegendRow(7, "", -1.0, 1, False)  # finished first
    shown, more = legend_rows(rows)
    assert [r.number for r in shown] == [7, 4, 9, 0, 1, 2, 3]  # ranks, then the best return, then robot order
    assert more == "+5 more: 5 racing"
    over = [LegendRow(i, "", -3.0, 1 + (i > 3), False) for i in range(40)]
    assert legend_rows(over) == (over[:LEGEND_ROWS - 1], "+33 more: 33 finished")
    sections = panel_sections(512, 64, THEMES["light"], legend=rows)  # compact: 3 entries a line, on 3 lines
    assert compact_layout(512, 64, 12) == (3, 3)
    assert [s.key[0] for s in sections] == ["top", "entries", "entries", "entries", "bottom"]
    listed = [part[2] for sec in sections[1:4] for part in sec.parts]
    assert [k[2].number for k in listed[:8]] == [7, 4, 9, 0, 1, 2, 3, 5]  # the leaders (8 places)
    assert listed[8][:1] == ("count",) and listed[8][2] == "+4 more: 4 racing"


def test_the_legend_of_a_1200_robot_race_fits_the_frame():
    env = race_v0.parallel_env(level="maze-64x64", n_robots=1200, start="random", render_mode="rgb_array")
    env.reset(seed=0)
    race = env.unwrapped
    h = race.level.height * race.cell_size + panel_height(race.level.width * race.cell_size, race.cell_size, robots=1200)
    assert env.render().shape == (h, 768, 3) and h < 1000  # it was 25,996 pixels tall


def test_the_frame_limit_counts_the_legend_and_is_refused_by_cell_size_before_drawing():
    level = levels.get("maze-16x16")
    check_frame_size(level, 256)  # the grid alone: 4096 x 4096, just within
    message = (r"^cell_size: a 16x16 level at 256 pixels a cell with the legend of 4 robots below is "
               r"a 4096x4262 frame, over the limit of 16,777,216 pixels; use cell_size <= 250")  # fmt: skip
    with pytest.raises(ValueError, match=message):
        race_v0.parallel_env(level=level, n_robots=4, start="random", cell_size=256, render_mode="rgb_array")
    check_frame_size(level, 250, robots=4)  # the size the error names fits, and the next one does not
    with pytest.raises(ValueError, match="use cell_size <= 250"):
        check_frame_size(level, 251, robots=4)
    w = 16 * 250
    assert w * (16 * 250 + panel_height(w, 250, robots=4)) <= MAX_FRAME_PIXELS
    # without render_mode there is no frame, nothing to refuse; the renderer refuses before drawing
    race = race_v0.parallel_env(level=level, n_robots=4, start="random", cell_size=256).unwrapped
    race.reset(seed=0)
    with pytest.raises(ValueError, match=r"^cell_size: .* with the legend of 4 robots below"):
        race.rgb_renderer.frame(race._scene())


def test_panel_lines_past_the_frame_limit_are_refused_by_name_and_the_env_keeps_its_overlay():
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array")
    env.reset(seed=0)
    env.unwrapped.set_overlay(panel="fits")
    before = env.render()
    message = (r"^panel: 3,000 lines \(3,000 wrapped to the frame's width\) make a 512x60,524 frame, "
               r"over the limit of 16,777,216 pixels; at cell_size 64 at most 1,612 wrapped lines fit")  # fmt: skip
    with pytest.raises(ValueError, match=message):
        env.unwrapped.set_overlay(panel=[f"line {i}" for i in range(3000)])
    assert env.unwrapped.overlay.panel == ("fits",) and (env.render() == before).all()
    one_word = "x" * 200_000  # a single word wraps too: into pieces as wide as the frame
    with pytest.raises(ValueError, match=r"^panel: 1 lines \([0-9,]+ wrapped"):
        env.unwrapped.set_overlay(panel=one_word)
    renderer = RgbRenderer(levels.get("maze-8x8"), 64)
    with pytest.raises(ValueError, match=r"^panel: 3,000 lines"):  # the renderer itself refuses before drawing
        renderer.frame([(0, 0)], update_overlay(Overlay(), levels.get("maze-8x8"), panel=["l"] * 3000))


@pytest.mark.parametrize("ratio", [1, 2])
@pytest.mark.parametrize("robots", [0, 3, 30])
@pytest.mark.parametrize("lines", [(), ("a short line", "a line " * 40)])
@pytest.mark.parametrize("bar", [False, True])
def test_panel_height_is_the_height_of_the_strips(ratio, robots, lines, bar):
    cs, width = 40 * ratio, 8 * 40 * ratio
    legend = tuple(LegendRow(i, "", 0.0, 0, True) for i in range(robots))
    sections = panel_sections(width, cs, THEMES["dark"], lines, (0.0, 1.0) if bar else None, legend, ratio)
    assert sum(s.height for s in sections) == panel_height(width, cs, lines, bar, robots, ratio)


def test_a_frame_with_a_legend_is_drawn_the_same_as_before_for_up_to_eight_robots():
    frame, race = race_frame(4, steps=3)
    scene = race._scene()
    assert isinstance(scene, Scene) and len(scene.legend) == 4
    strips = panel_sections(frame.shape[1], race.cell_size, race.theme, legend=scene.legend)
    assert [s.key[0] for s in strips] == ["top", "legend", "row", "row", "row", "row", "bottom"]
