"""The small robot in its cell's corner under an overlay: ringed so it reads on any tint."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.render.palette import THEMES
from babyrobot_marl.render.robot import CORNER, SCALE


@pytest.mark.parametrize("theme", ["light", "dark", "mono", "high-contrast"])
@pytest.mark.parametrize("cs", [32, 48, 64])
def test_the_corner_robot_is_ringed_in_the_floor_colour_on_a_tinted_cell(theme, cs):
    """At 32-pixel cells the corner robot is about 10 pixels tall: beside its head, on both
    sides, pixels of the floor's colour that the plain robot does not draw (its outline) set it
    off from the value tint."""
    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=cs, theme=theme)
    env.reset(seed=0)
    u = env.unwrapped
    u.set_overlay(values=np.linspace(-9, 0, 64).reshape(8, 8))  # the robot's cell: the darkest tint
    under = u.rgb_renderer.static(u.overlay).astype(int)
    shown = env.render().astype(int)[: under.shape[0]]
    x, y = u.robot_cell
    s = CORNER[0] * cs * SCALE  # the robot's unit in pixels, as ``robot.robot`` draws it
    cx, cy = (x + CORNER[1]) * cs, (y + CORNER[2]) * cs
    floorish = (np.abs(shown - THEMES[theme].floor).max(axis=2) <= 40) & (np.abs(shown - under).max(axis=2) > 0)
    yy, xx = np.mgrid[: shown.shape[0], : shown.shape[1]]
    head_rows = (yy >= cy - 0.37 * s) & (yy <= cy - 0.05 * s)  # the head spans -0.27..0.27 across
    rows = round(0.32 * s)
    assert (floorish & head_rows & (xx > cx + 0.31 * s)).sum() >= rows // 2
    assert (floorish & head_rows & (xx < cx - 0.31 * s)).sum() >= rows // 2


def test_only_a_lone_robot_in_the_corner_is_outlined():
    """Robots drawn at full size, or sharing a cell, keep their plain look."""
    from babyrobot_marl.render.scene import RobotView, Scene, placements

    alone = placements(Scene((RobotView(0, (1, 1)),), corner=True))
    shared = placements(Scene((RobotView(0, (1, 1)), RobotView(1, (1, 1))), corner=True))
    plain = placements(Scene((RobotView(0, (1, 1)),)))
    assert [p.outlined for p in alone] == [True]
    assert [p.outlined for p in shared + plain] == [False, False, False]


@pytest.mark.parametrize("cs", [32, 48, 64, 96])
@pytest.mark.parametrize("corner", [False, True])
def test_a_bumped_robot_and_its_stars_stay_inside_the_outer_walls(cs, corner):
    """A robot that bumped into the left or right outer wall: its stars drew over the wall and
    past the board's edge (and a corner robot, leaning into the wall, its outline over it); now
    nothing of it covers the wall's band."""
    from babyrobot_marl import levels
    from babyrobot_marl.render.overlay import Overlay
    from babyrobot_marl.render.picture import wall_width
    from babyrobot_marl.render.rgb import RgbRenderer
    from babyrobot_marl.render.scene import RobotView, Scene

    level = levels.get("maze-8x8")
    r = RgbRenderer(level, cs)
    overlay = Overlay(values=np.zeros((8, 8))) if corner else None
    static = r.static(overlay)
    band = int(wall_width(cs) // 2)
    for x, heading, cols in ((0, 4, slice(0, band)), (7, 2, slice(8 * cs - band, 8 * cs))):
        view = RobotView(0, (x, 3), heading, "bumped", numbered=False)
        img = r.frame(Scene((view,), corner=corner), overlay)
        rows = slice(3 * cs, 4 * cs)
        assert (img[rows, cols] == static[rows, cols]).all()
