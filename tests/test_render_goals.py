"""Own goals drawn: each robot's target in its colour in rgb_array frames, on the live canvas's
bottom layer, and as its letter in lower case in the text frame."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.render.palette import THEMES, contrast_ratio, robot_colour


def own_race(cs, theme="light", n=4, mode="rgb_array"):
    env = race_v0.parallel_env(level="maze-8x8", n_robots=n, start="random", goals="own", render_mode=mode,
                               cell_size=cs, theme=theme)  # fmt: skip
    env.reset(seed=3)
    return env


def cell_pixels(img, cell, cs):
    x, y = cell
    return img[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs].reshape(-1, 3)


@pytest.mark.parametrize("theme", ["light", "dark"])
@pytest.mark.parametrize("cs", [8, 24, 64])
def test_each_robot_s_target_shows_in_its_colour_in_rgb_array(cs, theme):
    env = own_race(cs, theme)
    u = env.unwrapped
    img = env.render()
    th = THEMES[theme]
    occupied = set(u.robot_cells)
    for k, agent in enumerate(env.possible_agents):
        cell = u.goals[agent]
        if cell in occupied:
            continue
        px = cell_pixels(img, cell, cs)
        colour = np.array(robot_colour(th, k))
        share = (np.abs(px.astype(int) - colour).max(axis=1) <= 20).mean()
        assert share >= 0.1, (k, cell, share)  # a ring (or a diamond) of its colour
        # outlined in the robots' ink: it stands out from the floor in both themes
        ink = (np.abs(px.astype(int) - np.array(th.robot_ink)).max(axis=1) <= 40).mean()
        assert ink > 0.02 and contrast_ratio(th.robot_ink, th.floor) >= 3.0, (k, ink)
        others = [robot_colour(th, j) for j in range(4) if robot_colour(th, j) != robot_colour(th, k)]
        for other in others:  # and no other robot's colour
            assert (np.abs(px.astype(int) - np.array(other)).max(axis=1) <= 2).mean() < 0.01


def test_targets_are_drawn_only_with_own_goals_and_only_while_racing():
    exit_race = race_v0.parallel_env(level="maze-8x8", n_robots=4, start="random", render_mode="rgb_array", cell_size=24)
    exit_race.reset(seed=3)
    assert exit_race.unwrapped._scene().goals == ()
    env = own_race(24)
    u = env.unwrapped
    scene = u._scene()
    assert dict(scene.goals) == {k: u.goals[a] for k, a in enumerate(env.possible_agents)}
    plain = u.rgb_renderer.frame(scene.__class__(scene.robots, scene.marks, scene.legend))
    assert (env.render() != plain).any()
    from types import SimpleNamespace

    from babyrobot_marl.envs.scenes import own_goals

    done = SimpleNamespace(_goal_of=u._goal_of, _xy=u._xy, _racing=[True, False, True, True])
    assert [k for k, _ in own_goals(done)] == [0, 2, 3]  # robot 1 there: its target goes


def test_the_text_frame_shows_each_target_as_its_robot_s_letter_in_lower_case():
    env = own_race(None, mode="ansi")
    u = env.unwrapped
    text = env.render()
    lines = text.split("\n")
    occupied = set(u.robot_cells)
    for k, agent in enumerate(env.possible_agents):
        x, y = u.goals[agent]
        if (x, y) not in occupied:
            assert lines[2 * y + 1][2 * x + 1] == "ABCD"[k].lower()
    assert "a-d: the targets of robots A-D" in text
    coloured = u.render_text(colour=True)
    assert "\x1b[" in coloured and "a-d" in coloured
    plain = race_v0.parallel_env(level="maze-8x8", n_robots=4, start="random", render_mode="ansi")
    plain.reset(seed=3)
    assert "targets" not in plain.render()


def test_the_live_canvas_shows_the_targets_on_its_bottom_layer():
    pytest.importorskip("ipycanvas")
    from babyrobot_marl.render.canvas import LiveCanvas

    env = own_race(24)
    u = env.unwrapped
    scene = u._scene()
    canvas = LiveCanvas(u.rgb_renderer, animation_frames=0, fps=0)
    canvas.draw(scene)
    assert canvas._static is canvas.hi.static(canvas.overlay, scene.goals)
    assert (canvas._static != canvas.hi.static(canvas.overlay)).any()
    hi = canvas.hi.cell_size
    for number, cell in scene.goals:
        if cell not in set(u.robot_cells):
            px = cell_pixels(canvas._static, cell, hi)
            colour = np.array(robot_colour(canvas.hi.theme, number))
            assert (np.abs(px.astype(int) - colour).max(axis=1) <= 2).mean() >= 0.08
