"""Rendering never fails and draws what it should, on random levels, for every render mode of
the single-robot env and the race: before the first reset, after reset, along an episode.

``ansi`` frames are the level text (2H+1 lines of 2W+1 characters) with each robot's glyph on
its cell (``R`` for a lone robot, ``A``, ``B``, ... in a race; a finished robot is not drawn;
robots sharing a cell under "pass" show the lowest-numbered one) and a status line;
``rgb_array`` frames are ``uint8[H * cell_size, W * cell_size, 3]``; ``human`` prints the text frame.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import string

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from babyrobot_marl import BabyRobotEnv, Level, race_v0
from tests.strategies import SEEDS, free_cells, grid_levels

RENDER_MODES = ("ansi", "rgb_array", "human")
CELL_SIZE = 8
RENDER = settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def at_most_ten_starts(level: Level) -> Level:
    return dataclasses.replace(level, starts=level.starts[:10]) if len(level.starts) > 10 else level


def rendered(env):
    """``render()``'s result, or for "human" what it printed (it returns None)."""
    if env.render_mode != "human":
        return env.render()
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert env.render() is None
    return out.getvalue().rstrip("\n")


def check_frame(frame, level: Level, mode: str, robots: dict[tuple[int, int], str]) -> None:
    """``robots``: cell -> the glyph that must be drawn there."""
    if mode == "rgb_array":
        assert isinstance(frame, np.ndarray) and frame.dtype == np.uint8
        # a race adds its legend under the grid
        assert frame.shape[1:] == (level.width * CELL_SIZE, 3) and frame.shape[0] >= level.height * CELL_SIZE
        return
    assert isinstance(frame, str)
    lines = frame.split("\n")
    grid = lines[: 2 * level.height + 1]
    assert len(lines) > len(grid), "no status line"
    assert all(len(line) == 2 * level.width + 1 for line in grid), frame
    for (x, y), glyph in robots.items():
        assert grid[2 * y + 1][2 * x + 1] == glyph, f"expected {glyph!r} at {(x, y)}:\n{frame}"


@RENDER
@given(
    level=grid_levels(max_side=12),
    mode=st.sampled_from(RENDER_MODES),
    seed=SEEDS,
    actions=st.lists(st.integers(0, 4), max_size=12),
)
def test_single_env_renders_every_state_in_every_mode(level, mode, seed, actions):
    level = at_most_ten_starts(level)
    if not free_cells(level) and not level.starts:
        return
    env = BabyRobotEnv(level=level, render_mode=mode, cell_size=CELL_SIZE, start=None)
    with contextlib.redirect_stdout(io.StringIO()):
        check_frame(rendered(env), level, mode, {})  # before the first reset: the level alone
        _, info = env.reset(seed=seed)
        check_frame(rendered(env), level, mode, {tuple(info["cell"].tolist()): "R"})
        for a in actions:
            _, _, terminated, truncated, info = env.step(a)
            check_frame(rendered(env), level, mode, {tuple(info["cell"].tolist()): "R"})
            if terminated or truncated:
                break


@RENDER
@given(
    level=grid_levels(max_side=12),
    mode=st.sampled_from(RENDER_MODES),
    n_robots=st.integers(1, 10),
    collisions=st.sampled_from(["block", "bounce", "pass"]),
    finished=st.sampled_from(["remove", "freeze"]),
    seed=SEEDS,
    actions=st.lists(st.integers(0, 4), min_size=1, max_size=12),
)
def test_race_renders_every_state_in_every_mode(level, mode, n_robots, collisions, finished, seed, actions):
    level = at_most_ten_starts(level)
    if n_robots > len(free_cells(level)):
        return
    env = race_v0.parallel_env(
        level=level,
        n_robots=n_robots,
        start="fill",
        collisions=collisions,
        finished=finished,
        render_mode=mode,
        cell_size=CELL_SIZE,
        max_cycles=len(actions),
    )
    glyphs = "R" if n_robots == 1 else string.ascii_uppercase

    def expected(infos, racing):
        drawn = {}
        for i in reversed(range(n_robots)):  # the lowest-numbered robot on top
            if racing[i]:
                drawn[tuple(infos[f"robot_{i}"]["cell"].tolist())] = glyphs[i]
        return drawn

    with contextlib.redirect_stdout(io.StringIO()):
        _, infos = env.reset(seed=seed)
        cells = {a: info for a, info in infos.items()}
        racing = [True] * n_robots
        check_frame(rendered(env), level, mode, expected(cells, racing))
        t = 0
        while env.agents:
            _, _, _, _, infos = env.step({a: actions[t % len(actions)] for a in env.agents})
            t += 1
            cells.update(infos)
            racing = [not cells[f"robot_{i}"]["finished"] for i in range(n_robots)]
            check_frame(rendered(env), level, mode, expected(cells, racing))


ELEVEN_STARTS = Level(width=12, height=1, starts=[(x, 0) for x in range(11)], exits=[(11, 0)])


@pytest.mark.parametrize("mode", ["ansi", "human"])
@pytest.mark.parametrize("which", ["single", "race"])
def test_levels_with_more_than_ten_starts_render_as_text(which, mode):
    if which == "single":
        env = BabyRobotEnv(level=ELEVEN_STARTS, render_mode=mode)
    else:
        env = race_v0.parallel_env(level=ELEVEN_STARTS, n_robots=11, render_mode=mode)
    with contextlib.redirect_stdout(io.StringIO()):
        env.reset(seed=0)
        frame = rendered(env)
    assert frame.split("\n")[1].startswith("|" + ("R" if which == "single" else "A"))


@pytest.mark.parametrize("mode", ["ansi", "human"])
def test_race_text_render_before_the_first_reset_draws_the_level(mode):
    env = race_v0.parallel_env(level="race-2", render_mode=mode)
    with contextlib.redirect_stdout(io.StringIO()):
        frame = rendered(env)
    assert frame.split("\n")[0] == "+-+-+-+-+-+"


def test_race_rgb_render_before_the_first_reset_draws_the_level():
    env = race_v0.parallel_env(level="race-2", render_mode="rgb_array", cell_size=CELL_SIZE)
    assert env.render().shape == (5 * CELL_SIZE, 5 * CELL_SIZE, 3)
