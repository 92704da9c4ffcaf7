"""Level families by spec, ``"maze:A..B"`` (issue 27): a maze of a new size at each reset, from the env's generator."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.envs.single import default_max_steps
from babyrobot_marl.levels import get
from babyrobot_marl.levels.sources import (
    EVAL_MAZE_SEEDS,
    TRAIN_MAZE_SEEDS,
    level_source,
    maze_range_family,
    parse_level_family,
)


def race(level="maze:8..16", **kw):
    return race_v0.parallel_env(level=level, **{"n_robots": 4, "start": "random", **kw})


def test_training_and_evaluation_seeds_are_disjoint_and_cover_the_family_range():
    assert TRAIN_MAZE_SEEDS.stop == EVAL_MAZE_SEEDS.start and TRAIN_MAZE_SEEDS.start == 0 and EVAL_MAZE_SEEDS.stop == 2**31
    assert not set(range(TRAIN_MAZE_SEEDS.stop - 5, TRAIN_MAZE_SEEDS.stop)) & set(EVAL_MAZE_SEEDS[:5])


def test_a_range_family_draws_square_mazes_of_every_side_from_the_generator():
    draw = maze_range_family(3, 6, seeds=EVAL_MAZE_SEEDS)
    assert draw.family == "maze:3..6" and draw.largest == (6, 6)
    rng = np.random.default_rng(1)
    levels = [draw(rng) for _ in range(60)]
    assert {lv.width for lv in levels} == {3, 4, 5, 6}
    assert all(lv.width == lv.height for lv in levels)
    seeds = {int(lv.name.rsplit("-s", 1)[1]) for lv in levels}
    assert all(s in EVAL_MAZE_SEEDS for s in seeds) and len(seeds) == 60
    again = [draw(np.random.default_rng(1)) for _ in range(1)]
    assert again[0].name == levels[0].name  # same generator state, same maze
    assert levels[0] == get(levels[0].name)  # a built-in maze name: it can be shown and replayed


def test_parse_level_family_reads_the_spec_and_leaves_other_levels():
    assert parse_level_family("maze:16..16").largest == (16, 16)
    assert parse_level_family("maze-16x16") is None and parse_level_family("race-4") is None
    assert level_source("maze:8..16").family == "maze:8..16"


@pytest.mark.parametrize("bad", ["maze:", "maze:8", "maze:8..", "maze:16..8", "maze:0..4", "maze:1..4", "maze:8..300",
                                 "maze:a..b", "maze:8...16", "maze:8..16x", "maze:" + "9" * 5000])
def test_a_bad_family_spec_is_one_clear_error_naming_level_and_the_form(bad):
    for make in (parse_level_family, lambda s: race(s)):
        with pytest.raises(ValueError, match=r"^level: a level family is 'maze:A\.\.B'") as err:
            make(bad)
        assert "\n" not in str(err.value) and len(str(err.value)) < 400


def test_the_env_is_sized_for_the_largest_level_and_races_on_each_drawn_size():
    for observe, kw in (("global", {}), ("local", {"view_radius": 3}), ("nearest", {"k": 2})):
        env = race(observe=observe, finished="freeze", **kw)
        space = env.observation_space("robot_0")
        assert list(space.nvec[:2]) == [16, 16]
        assert env.max_cycles == default_max_steps(get("maze-16x16"))
        assert env.state_space.contains(env.state_space.sample())
        sides = set()
        for seed in range(12):
            obs, infos = env.reset(seed=seed)
            sides.add(env.level.width)
            rng = np.random.default_rng(seed)
            while env.agents:
                for a, o in obs.items():
                    assert space.contains(o), (observe, env.level.name, o)
                    x, y = infos[a]["cell"]
                    assert 0 <= x < env.level.width and 0 <= y < env.level.height and list(o[:2]) == [x, y]
                assert env.state_space.contains(env.state())
                obs, _, _, _, infos = env.step({a: int(rng.integers(5)) for a in env.agents})
                if env.elapsed_steps > 30:
                    break
        assert len(sides) >= 4 and sides <= set(range(8, 17))


def test_nearest_offsets_use_the_largest_levels_scale():
    env = race(observe="nearest", k=1, n_robots=2)
    env.reset(seed=0)
    env.set_cells([(0, 0), (1, 0)])  # any level of the family has these cells
    obs = env._observations()
    assert list(obs[0][2:]) == [1 + 15, 0 + 15] and list(obs[1][2:]) == [-1 + 15, 15]


def test_same_seed_same_levels_and_starts():
    a, b = race(), race()
    for seed in (0, 5, 99):
        a.reset(seed=seed)
        b.reset(seed=seed)
        assert a.level.name == b.level.name and a.robot_cells == b.robot_cells
    names = set()
    for _ in range(5):
        a.reset()  # unseeded resets go on drawing from the seeded generator
        names.add(a.level.name)
    assert len(names) == 5


def test_frames_are_drawn_at_each_drawn_size():
    env = race("maze:4..7", render_mode="rgb_array", cell_size=16)
    shapes = set()
    for seed in range(10):
        env.reset(seed=seed)
        frame = env.render()
        w, h = env.level.width, env.level.height
        assert frame.dtype == np.uint8 and frame.shape[1] >= w * 16 and frame.shape[0] >= h * 16
        shapes.add(frame.shape)
        env.step(dict.fromkeys(env.agents, 0))
        assert env.render().shape == frame.shape
    assert len(shapes) >= 3


def test_race_gym_takes_a_family_and_its_step_limit_is_the_largest_levels():
    env = gym.make("babyrobot_marl/BabyRobotRace-v0", level="maze:6..9", opponents=["shortest"], start="random")
    assert env.spec.max_episode_steps == default_max_steps(get("maze-9x9"))
    sizes = set()
    for seed in range(8):
        obs, _ = env.reset(seed=seed)
        sizes.add(env.unwrapped.level.width)
        assert env.observation_space.contains(obs)
    assert len(sizes) >= 2


def test_one_size_family_and_the_batch_engine_refuses_it():
    env = race("maze:16..16")
    env.reset(seed=0)
    assert env.level.width == 16 and env.level.name.startswith("maze-16x16-s")
    with pytest.raises(ValueError, match="^level: the batch engine"):
        env.batch(2)


def test_evaluation_mazes_are_never_training_mazes_by_content_on_small_families():
    """Small mazes repeat across seeds: maze:4..6 drew about 31 of 200 evaluation mazes equal to training mazes."""
    def walls(seeds, n, seed):
        rng, draw = np.random.default_rng(seed), maze_range_family(4, 6, seeds=seeds)
        return {(lv.width, frozenset(lv.walls)) for lv in (draw(rng) for _ in range(n))}

    train, unseen = walls(TRAIN_MAZE_SEEDS, 3000, 0), walls(EVAL_MAZE_SEEDS, 300, 1)
    assert len(unseen) > 100 and not train & unseen
    assert len(walls(range(2**31), 300, 1) & train) > 0  # any seed: repeats, as the split keeps apart
