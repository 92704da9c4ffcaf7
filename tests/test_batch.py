"""The batch engine: env i of a batch plays exactly the episode of a single env with the same seed."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import BabyRobotEnv, levels, race_v0
from babyrobot_marl.core.batch import resolve_collisions_array
from tests.batch_twins import batch_beside
from tests.strategies import resolve_all_robots

MODES = ("block", "bounce", "pass", "soft")


RACES = [
    ("race-2", 2, "level"),
    ("race-4", 4, "level"),
    ("race-corridor", 4, "level"),
    ("puddles", 3, "fill"),
    ("glass", 3, "fill"),
    ("mixed-8x8", 4, "random"),
]


OWN_GOALS = [  # own goals: each robot its own target (the exits are floor), in every observation mode
    ("race-4", 4, "level", {}),
    ("race-corridor", 4, "level", {"observe": "local", "view_radius": 1, "hint": True}),
    ("mixed-8x8", 5, "random", {"observe": "nearest", "k": 2}),
    ("puddles", 1, "fill", {"observe": "local", "hint": True}),
    ("glass", 1, "fill", {}),
]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("level", "n_robots", "start"), RACES)
def test_batch_matches_separate_race_envs_step_by_step(level, n_robots, start, mode):
    _batch_matches_envs(level, n_robots, start, mode, {})


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("level", "n_robots", "start", "kw"), OWN_GOALS)
def test_batch_with_own_goals_matches_separate_race_envs_step_by_step(level, n_robots, start, kw, mode):
    _batch_matches_envs(level, n_robots, start, mode, {"goals": "own", **kw})


def _batch_matches_envs(level, n_robots, start, mode, kw):
    n_envs, seed0 = 5, 100
    envs = [
        race_v0.parallel_env(level=level, n_robots=n_robots, collisions=mode, finished="freeze", start=start, **kw)
        for _ in range(n_envs)
    ]
    batch = batch_beside(envs, seed0)
    rng = np.random.default_rng(7)
    resets = blocked_seen = finished_seen = 0
    for _ in range(250):
        actions = rng.integers(0, 5, (n_envs, n_robots))
        rewards, finishing, blocked, _, over = batch.step(actions)
        obs = batch.observations()
        for i, env in enumerate(envs):
            o, r, term, trunc, info = env.step({a: int(actions[i, k]) for k, a in enumerate(env.agents)})
            for k, agent in enumerate(env.possible_agents):
                assert r[agent] == rewards[i, k]
                assert np.array_equal(o[agent], obs[i, k])
                assert info[agent]["blocked"] == blocked[i, k]
            assert (not env.agents) == over[i]
            assert env.ranks == batch.rank[i].tolist()
            if not env.agents:
                env.reset()
        blocked_seen += int(blocked.sum())
        finished_seen += int(finishing.sum())
        done = np.flatnonzero(over)
        resets += done.size
        if done.size:
            batch.reset_envs(done)
    if mode != "pass" and n_robots > 1:
        assert blocked_seen > 0  # the run did exercise collisions
    if kw.get("goals") == "own":
        goals = [[e.table.cell_id(e.goals[a]) for a in e.possible_agents] for e in envs]
        assert finished_seen > 0 and np.array_equal(batch.goals, goals)


@pytest.mark.parametrize("start", [None, "random"])
@pytest.mark.parametrize("level", levels.names())
def test_batch_of_one_robot_matches_separate_single_envs_across_resets(level, start):
    n_envs = 4
    envs = [BabyRobotEnv(level=level, start=start, max_steps=60) for _ in range(n_envs)]
    batch = envs[0].batch(n_envs)
    batch.seed(range(20, 20 + n_envs))
    batch.reset_envs(range(n_envs))
    for i, env in enumerate(envs):
        env.reset(seed=20 + i)
    rng = np.random.default_rng(3)
    episodes = 0
    for _ in range(200):
        actions = rng.integers(0, 5, (n_envs, 1))
        rewards, finishing, _, _, over = batch.step(actions)
        obs = batch.observations()
        for i, env in enumerate(envs):
            o, r, term, trunc, _ = env.step(int(actions[i, 0]))
            assert (r, term, term or trunc) == (rewards[i, 0], finishing[i, 0], over[i])
            assert np.array_equal(o, obs[i, 0])
            if term or trunc:
                env.reset()
                episodes += 1
        done = np.flatnonzero(over)
        if done.size:
            batch.reset_envs(done)
    assert episodes >= n_envs  # max_steps=60 forces resets: the auto-reset path was exercised


@settings(max_examples=300, deadline=None)
@given(
    data=st.data(),
    n=st.integers(1, 6),
    mode=st.sampled_from(["block", "bounce"]),
)
def test_array_collisions_equal_the_scalar_rules_on_random_crowds(data, n, mode):
    # a 4x4 patch: robots on distinct cells, each heading for a neighbour or staying
    width = 4
    cells = data.draw(st.lists(st.integers(0, width * width - 1), min_size=n, max_size=n, unique=True))
    racing = data.draw(st.lists(st.booleans(), min_size=n, max_size=n))
    desired = []
    for c, r in zip(cells, racing):
        x, y = c % width, c // width
        options = [c] + [
            nx + ny * width for nx, ny in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)) if 0 <= nx < width and 0 <= ny < width
        ]
        desired.append(data.draw(st.sampled_from(options)) if r else c)
    key, step = data.draw(st.integers(0, 2**64 - 1)), data.draw(st.integers(0, 1000))
    expected = resolve_all_robots(mode, cells, desired, racing, key, step)
    got = resolve_collisions_array(
        mode,
        np.array([cells]),
        np.array([desired]),
        np.array([racing]),
        np.array([key], dtype=np.uint64),
        np.array([step]),
    )
    assert got[0].tolist() == expected


def test_state_is_a_few_bytes_per_env():
    env = race_v0.parallel_env(level="maze-8x8", n_robots=4, start="random")
    batch = env.batch(4096)
    assert batch.nbytes / 4096 <= 128  # cells, racing, rank, step, key: tens of bytes, not kilobytes
    assert batch.nbytes < 1 << 20


def test_an_env_whose_race_is_over_stays_as_it_is_until_reset():
    env = BabyRobotEnv(level="default", max_steps=1)
    batch = env.batch(2)
    batch.seed([0, 1])
    batch.reset_envs([0, 1])
    *_, over = batch.step(np.array([[2], [2]]))  # EAST, then truncated at max_steps=1
    assert over.tolist() == [True, True]
    cells, t = batch.cells.copy(), batch.t.copy()
    rewards, *_, over = batch.step(np.array([[2], [2]]))
    assert np.array_equal(batch.cells, cells) and np.array_equal(batch.t, t)
    assert over.tolist() == [True, True] and not rewards.any()
    batch.reset_envs([1])
    assert batch.cells[1, 0] == 0  # back at the start (0, 0)
    batch.step(np.array([[2], [2]]))
    assert np.array_equal(batch.cells[0], cells[0])  # still waiting
    assert batch.cells[1, 0] == 1 and batch.t[1] == 1  # a new episode, stepped once
