"""Levels drawn per reset: maze families and callables, seeded by the env."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from babyrobot_marl import levels, race_v0
from babyrobot_marl.envs.vector import RaceVectorEnv
from babyrobot_marl.levels.sources import maze_family


def race(level, **kw):
    return race_v0.parallel_env(level=level, n_robots=3, start="random", **kw)


def test_a_maze_family_draws_a_new_maze_each_reset_from_the_env_seed():
    env = race("maze-8x8-*", observe="local")
    names = []
    for seed in range(6):
        env.reset(seed=seed)
        names.append(env.level.name)
        assert env.table.level is env.level and env.level.width == env.level.height == 8
    assert len(set(names)) == 6
    again = race("maze-8x8-*", observe="local")
    again.reset(seed=3)
    env.reset(seed=3)
    assert again.level.name == env.level.name and again.robot_cells == env.robot_cells
    env.reset()  # unseeded resets go on drawing from the same generator
    assert env.level.name != names[3]


def test_robots_start_on_the_drawn_level_and_the_race_runs_on_it():
    env = race(maze_family(8, 8, seeds=range(40, 50)), observe="local", view_radius=1)
    rng = np.random.default_rng(0)
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        drawn = env.level
        assert drawn.name in {f"maze-8x8-s{s}" for s in range(40, 50)}
        free = set(drawn.free_cells())
        assert all(c in free for c in env.robot_cells)
        # the local window shows the drawn level's walls: robot 0's own cell, north side
        x, y = env.robot_cells[0]
        wall_north = y == 0 or ((x, y - 1), (x, y)) in drawn.walls
        centre = 2 + 6 * 4  # the centre cell of a 3x3 window
        assert obs["robot_0"][centre + 2] == int(wall_north)
        for _ in range(20):
            if not env.agents:
                break
            env.step({a: int(rng.integers(5)) for a in env.agents})
            assert all(c in free or c in drawn.exits for c in env.robot_cells)


def test_a_callable_draws_levels_from_the_env_generator():
    seen = []

    def pick(rng):
        name = ["maze-6x6-s1", "maze-6x6-s2", levels.text("maze-6x6-s3")][int(rng.integers(3))]
        seen.append(name)
        return name

    env = race(pick)
    texts = {levels.text(f"maze-6x6-s{s}") for s in (1, 2, 3)}
    for seed in range(30):
        env.reset(seed=seed)
        assert env.level.to_ascii() in texts
    assert len(seen) == 31  # one draw at construction (its own generator), one per reset
    assert len(set(seen)) == 3


def test_levels_of_another_size_are_refused_at_reset():
    sizes = iter(["maze-6x6", "maze-6x6", "maze-7x6"])
    env = race(lambda rng: next(sizes))
    env.reset(seed=0)
    with pytest.raises(ValueError, match="level: drawn levels must all be 6x6"):
        env.reset(seed=1)


@pytest.mark.parametrize("bad", ["maze-8x8-s*", "mixed-*", "maze-8-*"])
def test_a_bad_family_name_is_a_clear_error(bad):
    with pytest.raises(ValueError, match="level: a level family is 'maze-WxH-\\*'"):
        race(bad)


def test_a_callable_returning_something_else_is_a_type_error():
    with pytest.raises(TypeError, match="level: the level callable returned int"):
        race(lambda rng: 3)


def test_the_batch_engine_and_vector_envs_refuse_drawn_levels():
    with pytest.raises(ValueError, match="drawn levels are for parallel_env"):
        race("maze-8x8-*").batch(2)
    with pytest.raises(ValueError, match="drawn levels are for parallel_env"):
        RaceVectorEnv(2, level="maze-8x8-*", n_robots=2, start="random")


def test_race_gym_opponents_follow_the_drawn_level():
    env = gym.make("babyrobot_marl/BabyRobotRace-v0", level="maze-8x8-*", opponents=["shortest"], start="random", observe="local")
    for seed in range(4):
        env.reset(seed=seed)
        race_env = env.unwrapped.race
        opponent = env.unwrapped._opponents[0]
        assert np.array_equal(opponent.actions, __import__("babyrobot_marl").policies.make("shortest", race_env.table).actions)
