"""Overlays on rgb_array frames: values, action values, arrows, text, panel; checks and clearing."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

from babyrobot_marl import Action, race_v0
from babyrobot_marl.envs.single import BabyRobotEnv
from babyrobot_marl.render.rgb import THEMES

CS = 32
INSET = max(2, CS // 8)


def env_with(level="maze-8x8", **kw) -> BabyRobotEnv:
    env = BabyRobotEnv(level=level, render_mode="rgb_array", cell_size=CS, **kw)
    env.reset(seed=0)
    return env


def blend(under, over):
    """The tint rule written out: 35% of what is there, 65% of the tint."""
    return tuple(int(0.35 * u + 0.65 * o) for u, o in zip(under, over))


def px(img, x, y, u, v):
    """Pixel at fraction (u, v) of cell (x, y)."""
    return tuple(int(c) for c in img[int((y + v) * CS), int((x + u) * CS)])


def test_values_tint_the_best_cell_with_the_high_colour_and_the_worst_with_the_low():
    env = env_with()
    values = np.zeros((8, 8))
    values[2, 3], values[5, 6] = 10.0, -10.0
    env.set_overlay(values=values)
    img = env.render()
    th = THEMES["light"]
    corner = INSET / CS + 0.02  # inside the walls, away from the printed number and the robot
    assert px(img, 3, 2, corner, corner) == blend(th.floor, th.value_high)
    assert px(img, 6, 5, corner, corner) == blend(th.floor, th.value_low)
    mid = tuple(int(round((a + b) / 2)) for a, b in zip(th.value_low, th.value_high))
    assert np.abs(np.array(px(img, 1, 1, corner, corner)) - blend(th.floor, mid)).max() <= 1


def test_nan_values_leave_the_cell_as_it_was():
    env = env_with()
    plain = env.render()
    values = np.full((8, 8), np.nan)
    values[0, 0] = 1.0
    env.set_overlay(values=values)
    img = env.render()
    assert (img[CS:, CS:] == plain[CS:, CS:]).all()
    assert not (img[:CS, :CS] == plain[:CS, :CS]).all()


@pytest.mark.parametrize(
    "action, u, v", [(Action.EAST, 0.82, 0.5), (Action.WEST, 0.18, 0.5), (Action.NORTH, 0.5, 0.18), (Action.SOUTH, 0.5, 0.82)]
)
def test_an_arrow_points_from_the_centre_towards_its_direction(action, u, v):
    env = env_with()
    arrows = np.zeros((8, 8), dtype=np.int64)
    arrows[4, 4] = action
    env.set_overlay(arrows=arrows)
    img = env.render()
    arrow = THEMES["light"].arrow
    assert px(img, 4, 4, u, v) == arrow
    assert px(img, 4, 4, 1 - u, 1 - v) != arrow  # nothing on the opposite side
    assert px(img, 3, 4, u, v) != arrow  # nor in a cell without an arrow


def test_several_arrows_per_cell_from_booleans():
    env = env_with()
    arrows = np.zeros((8, 8, 5), dtype=bool)
    arrows[4, 4, [Action.EAST, Action.SOUTH]] = True
    env.set_overlay(arrows=arrows)
    img = env.render()
    arrow = THEMES["light"].arrow
    assert px(img, 4, 4, 0.82, 0.5) == arrow and px(img, 4, 4, 0.5, 0.82) == arrow
    assert px(img, 4, 4, 0.18, 0.5) != arrow


def test_q_values_colour_the_four_triangles_by_action():
    env = env_with()
    q = np.zeros((8, 8, 5))
    q[3, 5, Action.NORTH], q[3, 5, Action.SOUTH] = 5.0, -5.0
    env.set_overlay(q_values=q)
    img = env.render()
    th = THEMES["light"]
    assert px(img, 5, 3, 0.5, 0.25) == blend(th.floor, th.value_high)
    assert px(img, 5, 3, 0.5, 0.75) == blend(th.floor, th.value_low)


def test_text_is_drawn_in_its_cell_only():
    env = env_with()
    plain = env.render()
    env.set_overlay(text={(6, 1): "HI"})
    img = env.render()
    changed = np.argwhere((img != plain).any(axis=2))
    assert len(changed) > 0
    assert set(map(tuple, changed // CS)) == {(1, 6)}  # (row, column) of cell (6, 1)
    assert (img[changed[:, 0], changed[:, 1]] == THEMES["light"].text).all()


def test_a_panel_adds_rows_below_the_grid_and_the_grid_is_unchanged():
    env = env_with()
    plain = env.render()
    env.set_overlay(panel=["step 3", "return -2.5"])
    img = env.render()
    assert img.shape[0] > plain.shape[0] and img.shape[1:] == plain.shape[1:]
    assert (img[: plain.shape[0]] == plain).all()
    assert (img[plain.shape[0] :] == THEMES["light"].text).all(axis=2).any()


def test_parts_not_given_are_kept_none_clears_one_and_clear_overlay_clears_all():
    env = env_with()
    plain = env.render()
    env.set_overlay(values=np.ones((8, 8)))
    env.set_overlay(arrows=np.full((8, 8), int(Action.EAST)))
    assert env.overlay.values is not None and env.overlay.arrows is not None
    env.set_overlay(values=None)
    assert env.overlay.values is None and env.overlay.arrows is not None
    env.clear_overlay()
    assert env.overlay.empty
    assert (env.render() == plain).all()


def test_overlay_frames_are_deterministic_tints_under_the_robot_arrows_over_it():
    env = env_with()
    env.set_overlay(values=np.arange(64.0).reshape(8, 8), arrows=np.full((8, 8), int(Action.SOUTH)))
    a, b = env.render(), env.render()
    assert (a == b).all()
    x, y = env.robot_cell
    th = THEMES["light"]
    assert px(a, x, y, 0.3, 0.5) == th.robots[0]  # on the disc, beside the arrow: the robot, not tinted
    assert px(a, x, y, 0.5, 0.6) == th.arrow  # the arrow's shaft crosses the disc
    env.clear_overlay()
    assert px(env.render(), x, y, 0.5, 0.6) == th.robots[0]


def test_only_ink_goes_back_over_a_robot():
    """What is drawn over the robot's disc is exactly the overlay's arrow pixels there."""
    env = env_with()
    x, y = env.robot_cell
    plain = env.render()
    env.set_overlay(arrows=np.full((8, 8), int(Action.EAST)))
    img = env.render()
    cell = (slice(y * CS, (y + 1) * CS), slice(x * CS, (x + 1) * CS))
    robot = (plain[cell] == THEMES["light"].robots[0]).all(axis=2)
    changed = (img[cell] != plain[cell]).any(axis=2)
    assert changed.any() and robot[changed].any()
    assert (img[cell][changed] == THEMES["light"].arrow).all()


BAD = [
    (dict(values=np.zeros((3, 3))), "values"),
    (dict(values="high"), "values"),
    (dict(values=np.full((8, 8), np.inf)), "values"),
    (dict(values=np.zeros((8, 8), dtype=bool)), "values"),
    (dict(q_values=np.zeros((8, 8, 3))), "q_values"),
    (dict(arrows=np.full((8, 8), 7)), "arrows"),
    (dict(arrows=np.zeros((8, 8), dtype=float)), "arrows"),
    (dict(arrows=np.zeros((8, 8, 2), dtype=bool)), "arrows"),
    (dict(text={(9, 0): "x"}), "text"),
    (dict(text={(0, 0): 5}), "text"),
    (dict(text=["x"]), "text"),
    (dict(panel=5), "panel"),
    (dict(panel=["ok", 3]), "panel"),
]


@pytest.mark.parametrize("kwargs, name", BAD)
def test_bad_overlay_arguments_are_value_errors_naming_them_and_change_nothing(kwargs, name):
    env = env_with()
    env.set_overlay(values=np.ones((8, 8)))
    before = env.render()
    with pytest.raises(ValueError, match=f"^{name}"):
        env.set_overlay(**kwargs)
    assert (env.render() == before).all()


def test_the_race_draws_overlays_too():
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=CS)
    env.reset(seed=0)
    plain = env.render()
    h, w = env.level.height, env.level.width
    env.unwrapped.set_overlay(values=np.arange(h * w, dtype=float).reshape(h, w), panel="race")
    img = env.render()
    assert img.shape[0] > plain.shape[0]
    assert not (img[: plain.shape[0]] == plain).all()


def test_overlays_work_through_gymnasium_make():
    env = gymnasium.make("babyrobot_marl/BabyRobot-v0", level="maze-8x8", render_mode="rgb_array")
    env.reset(seed=0)
    env.unwrapped.set_overlay(arrows=np.full((8, 8), int(Action.EAST)))
    assert env.render().shape == (8 * 32, 8 * 32, 3)
