"""rgb_array frames: size, what each pixel region shows, determinism, themes, bad options."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import babyrobot_marl  # noqa: F401  (registers the envs)
from babyrobot_marl import BabyRobotEnv, Level, levels, race_v0
from babyrobot_marl.render.rgb import THEMES, RgbRenderer, Theme

CS = 20  # a cell size whose centre pixel (10, 10) lies well inside the robot disc


def centre(frame: np.ndarray, cell: tuple[int, int], cs: int = CS) -> tuple[int, int, int]:
    x, y = cell
    return tuple(int(v) for v in frame[y * cs + cs // 2, x * cs + cs // 2])


def edge_pixels(frame: np.ndarray, a: tuple[int, int], b: tuple[int, int], cs: int = CS) -> np.ndarray:
    """The pixels on the shared edge of two neighbour cells, away from the corners."""
    if a[1] == b[1]:  # side by side: the vertical line at the right cell's left edge
        x = max(a[0], b[0]) * cs
        return frame[a[1] * cs + 3 : (a[1] + 1) * cs - 3, x]
    y = max(a[1], b[1]) * cs
    return frame[y, a[0] * cs + 3 : (a[0] + 1) * cs - 3]


def colours(pixels: np.ndarray) -> set[tuple[int, int, int]]:
    return {tuple(int(v) for v in p) for p in pixels.reshape(-1, 3)}


@pytest.mark.parametrize("name", levels.names())
def test_frame_is_uint8_of_the_level_size_in_cells_times_cell_size(name):
    level = levels.get(name)
    env = BabyRobotEnv(level=level, render_mode="rgb_array", cell_size=CS)
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8
    assert frame.shape == (level.height * CS, level.width * CS, 3)


def test_the_robot_is_a_disc_of_the_first_robot_colour_at_its_cell_and_moves_with_it():
    theme = THEMES["light"]
    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=CS)
    env.reset(seed=0)
    before = env.render()
    assert centre(before, (0, 0)) == theme.robots[0]
    env.step(2)  # EAST: (0, 0) -> (1, 0) on the open default level
    after = env.render()
    assert centre(after, (1, 0)) == theme.robots[0]
    assert centre(after, (0, 0)) != theme.robots[0]  # the start cell shows again


def test_cells_show_their_kind_in_the_theme_colours():
    theme = THEMES["light"]
    level = Level.from_ascii(
        """
        +-+-+-+-+-+
        |S p P # E|
        + + + + + +
        |         |
        +-+-+-+-+-+
        """
    )
    frame = RgbRenderer(level, CS, "light").frame()
    assert centre(frame, (2, 0)) == theme.large_puddle
    assert centre(frame, (3, 0)) == theme.blocked
    # small puddle and exit: the fill colour fills the cell (the exit has a label in the middle)
    assert colours(frame[3:6, CS + 3 : CS + 6]) == {theme.small_puddle}
    assert colours(frame[3:6, 4 * CS + 3 : 4 * CS + 6]) == {theme.exit}
    assert theme.label in colours(frame[:CS, 4 * CS : 5 * CS])  # the 'E'
    assert theme.label in colours(frame[:CS, :CS])  # the 'S'


def test_walls_are_solid_glass_walls_dashed_and_open_edges_not_drawn():
    theme = THEMES["light"]
    level = Level.from_ascii(
        """
        +-+-+-+-+
        |S| *   |
        + + +-+ +
        |      E|
        +-+-+-+-+
        """
    )
    frame = RgbRenderer(level, CS, "light").frame()
    assert colours(edge_pixels(frame, (0, 0), (1, 0))) == {theme.wall}
    assert colours(edge_pixels(frame, (2, 0), (2, 1))) == {theme.wall}
    glass = colours(edge_pixels(frame, (1, 0), (2, 0)))
    assert theme.glass in glass and theme.wall not in glass and len(glass) > 1  # dashes and gaps
    open_edge = colours(edge_pixels(frame, (0, 1), (1, 1)))
    assert theme.wall not in open_edge and theme.glass not in open_edge


def test_the_outer_border_is_a_wall_all_round():
    theme = THEMES["dark"]
    frame = RgbRenderer(levels.get("default"), CS, "dark").frame()
    for strip in (frame[0], frame[-1], frame[:, 0], frame[:, -1]):
        assert colours(strip) == {theme.wall}


LANE = """
+-+-+-+-+
|0   E 1|
+-+-+-+-+
"""


def test_race_robots_each_have_their_colour_and_finished_robots_are_not_drawn():
    theme = THEMES["light"]
    env = race_v0.parallel_env(level=LANE, n_robots=2, render_mode="rgb_array", cell_size=CS)
    env.reset(seed=0)
    frame = env.render()
    cells = env.robot_cells
    assert centre(frame, cells[0]) == theme.robots[0]
    assert centre(frame, cells[1]) == theme.robots[1]
    # LANE: robot 0 at (0, 0) is two moves EAST from the exit (2, 0); robot 1 at (3, 0) stays,
    # so robot 0 finishes alone and leaves the board.
    for action in (2, 2):
        env.step({a: (action if a == "robot_0" else 0) for a in env.agents})
    assert env.ranks[0] == 1
    frame = env.render()
    assert theme.robots[0] not in colours(frame)
    assert centre(frame, env.robot_cells[1]) == theme.robots[1]


def test_the_same_state_gives_the_same_bytes_and_frames_are_fresh_arrays():
    a = BabyRobotEnv(level="puddles", render_mode="rgb_array")
    b = BabyRobotEnv(level="puddles", render_mode="rgb_array")
    a.reset(seed=3)
    b.reset(seed=3)
    for action in [2, 3, 3, 2, 2, 3]:
        a.step(action)
        b.step(action)
        fa, fb = a.render(), b.render()
        assert fa.tobytes() == fb.tobytes()
    fa[:] = 0  # a caller scribbling on a frame does not touch the next one
    assert a.render().tobytes() == fb.tobytes()


def test_themes_change_colours_and_a_custom_theme_is_data():
    level = levels.get("mixed-8x8")
    light = RgbRenderer(level, CS, "light").frame([(0, 0)])
    dark = RgbRenderer(level, CS, "dark").frame([(0, 0)])
    assert light.tobytes() != dark.tobytes()
    custom = Theme(**{**THEMES["light"].__dict__, "floor": (1, 2, 3)})
    frame = RgbRenderer(level, CS, custom).frame()
    assert (1, 2, 3) in colours(frame)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"cell_size": 4}, "cell_size"),
        ({"cell_size": 32.0}, "cell_size"),
        ({"cell_size": True}, "cell_size"),
        ({"theme": "neon"}, "theme: unknown theme 'neon'"),
    ],
)
def test_bad_render_options_name_the_argument(kwargs, message):
    with pytest.raises(ValueError, match=message):
        BabyRobotEnv(level="default", render_mode="rgb_array", **kwargs)
    with pytest.raises(ValueError, match=message):
        race_v0.parallel_env(render_mode="rgb_array", **kwargs)


def test_gymnasium_make_renders_rgb_array_for_both_registered_envs():
    for env_id, kwargs in [("babyrobot_marl/BabyRobot-v0", {}), ("babyrobot_marl/BabyRobotRace-v0", {"level": "race-4"})]:
        env = gymnasium.make(env_id, render_mode="rgb_array", cell_size=16, **kwargs)
        env.reset(seed=0)
        frame = env.render()
        level = env.unwrapped.level
        assert frame.shape == (level.height * 16, level.width * 16, 3)
