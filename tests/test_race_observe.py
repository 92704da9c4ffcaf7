"""Observation modes wired into the race envs: parallel, AEC, BabyRobotRace-v0, the vector envs."""

from __future__ import annotations

import tracemalloc

import gymnasium as gym
import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test

from babyrobot_marl import race_v0
from babyrobot_marl.core import observe
from babyrobot_marl.envs.vector import RaceVectorEnv

MODES = [
    {"observe": "local", "view_radius": 1},
    {"observe": "local"},
    {"observe": "nearest", "k": 2},
    {"observe": "nearest"},
]


def direct(env, mode_kw):
    """Every robot's row straight from core.observe, from the env's robot cells and racing flags."""
    t = env.table
    cells = np.array([t.cell_id(c) for c in env.robot_cells])
    racing = np.array([r == 0 for r in env.ranks])
    if mode_kw["observe"] == "local":
        view = observe.local_view(t, mode_kw.get("view_radius", observe.DEFAULT_VIEW_RADIUS))
        return observe.local_observations(view, cells, racing)
    xy = np.array(env.robot_cells)
    return observe.nearest_observations(xy, racing, mode_kw.get("k", observe.DEFAULT_K), t.width, t.height)


@pytest.mark.parametrize("mode_kw", MODES)
@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_parallel_env_rows_are_the_mode_of_every_reported_robot(mode_kw, finished):
    env = race_v0.parallel_env(level="race-4", n_robots=4, finished=finished, **mode_kw)
    space = env.observation_space("robot_0")
    expected_size = (
        2 + 6 * (2 * mode_kw.get("view_radius", 2) + 1) ** 2 if mode_kw["observe"] == "local" else 2 + 2 * mode_kw.get("k", 4)
    )
    assert space.shape == (expected_size,)
    obs, _ = env.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(60):
        rows = direct(env, mode_kw)
        assert set(obs) == set(env.agents)
        for a, o in obs.items():
            assert space.contains(o)
            assert o.tolist() == rows[int(a.split("_")[1])].tolist()
        if not env.agents:
            obs, _ = env.reset()
            continue
        obs, *_ = env.step({a: int(rng.integers(1, 5)) for a in env.agents})


@pytest.mark.parametrize("mode_kw", MODES[:1] + MODES[2:3])
def test_pettingzoo_api_tests_pass_in_each_mode(mode_kw):
    with pytest.warns(UserWarning, match="unknown option 'options' ignored"):  # the api tests' reset probe
        parallel_api_test(race_v0.parallel_env(level="race-4", n_robots=4, **mode_kw), num_cycles=100)
        api_test(race_v0.env(level="race-4", n_robots=4, **mode_kw), num_cycles=50)


@pytest.mark.parametrize("mode_kw", MODES)
def test_batch_matches_separate_envs_in_each_mode(mode_kw):
    n_envs, n_robots = 4, 5
    kw = dict(level="mixed-8x8", n_robots=n_robots, finished="freeze", start="random", **mode_kw)
    envs = [race_v0.parallel_env(**kw) for _ in range(n_envs)]
    batch = envs[0].batch(n_envs)
    batch.seed(range(n_envs))
    batch.reset_envs(range(n_envs))
    for i, env in enumerate(envs):
        env.reset(seed=i)
    rng = np.random.default_rng(1)
    for _ in range(120):
        actions = rng.integers(0, 5, (n_envs, n_robots))
        *_, over = batch.step(actions)
        obs = batch.observations()
        for i, env in enumerate(envs):
            o, *_ = env.step({a: int(actions[i, k]) for k, a in enumerate(env.agents)})
            for k, agent in enumerate(env.possible_agents):
                assert np.array_equal(o[agent], obs[i, k])
            if not env.agents:
                env.reset()
        if over.any():
            batch.reset_envs(np.flatnonzero(over))


@pytest.mark.parametrize("mode_kw", MODES[:1] + MODES[2:3])
def test_vector_env_and_race_gym_take_the_mode(mode_kw):
    v = RaceVectorEnv(3, level="race-4", n_robots=4, **mode_kw)
    single = race_v0.parallel_env(level="race-4", n_robots=4, **mode_kw).observation_space("robot_0")
    assert v.single_observation_space == single
    obs, _ = v.reset(seed=0)
    assert obs.shape == (12, single.shape[0]) and all(single.contains(row) for row in obs)
    g = gym.make("babyrobot_marl/BabyRobotRace-v0", level="race-4", opponents=["shortest"] * 3, **mode_kw)
    o, _ = g.reset(seed=0)
    assert g.observation_space == single and single.contains(o)
    for _ in range(200):  # the shortest-path opponents read their own [x, y] from these rows
        o, _, term, trunc, info = g.step(0)
        if term or trunc:
            break
    assert 1 in info["ranks"]  # an opponent finished


@pytest.mark.parametrize(
    ("kw", "word"),
    [
        ({"observe": "egocentric"}, "observe"),
        ({"observe": "global", "view_radius": 2}, "view_radius"),
        ({"observe": "nearest", "view_radius": 2}, "view_radius"),
        ({"observe": "local", "k": 3}, "k"),
        ({"observe": "local", "view_radius": -1}, "view_radius"),
        ({"observe": "local", "view_radius": 1.5}, "view_radius"),
        ({"observe": "nearest", "k": 0}, "k"),
        ({"observe": "nearest", "k": True}, "k"),
    ],
)
def test_bad_observation_arguments_name_the_argument(kw, word):
    with pytest.raises(ValueError, match=word):
        race_v0.parallel_env(level="race-4", n_robots=4, **kw)


def test_local_and_nearest_envs_do_not_build_the_global_gather():
    """n^2 numbers at construction would make thousands of robots cost gigabytes."""
    env = race_v0.parallel_env(level="maze-64x64", n_robots=2000, start="random", observe="local", view_radius=1)
    assert env._gather.size == 0
    tracemalloc.start()
    env.batch(1)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 2000 * 2000 * 8  # a gather index of the global rows would be 2000 x 5999 of 8 bytes
    obs, _ = env.reset(seed=0)
    assert len(obs) == 2000 and obs["robot_1999"].shape == (2 + 6 * 9,)


@pytest.mark.parametrize("n_robots", [23, 24, 63, 64, 90])
def test_batch_global_rows_of_many_robots_equal_the_parallel_env(n_robots):
    """From 24 robots the batch engine copies windows of the state instead of gathering by index."""
    env = race_v0.parallel_env(level="maze-16x16", n_robots=n_robots, start="random", finished="freeze")
    batch = env.batch(2)
    batch.seed([5, 6])
    batch.reset_envs([0, 1])
    env.reset(seed=6)
    rng = np.random.default_rng(2)
    for _ in range(40):
        actions = rng.integers(0, 5, (2, n_robots))
        batch.step(actions)
        obs, *_ = env.step({a: int(actions[1, k]) for k, a in enumerate(env.agents)})
    rows = batch.observations()
    assert rows.shape == (2, n_robots, 3 * n_robots - 1)
    assert all(np.array_equal(obs[a], rows[1, k]) for k, a in enumerate(env.possible_agents))
