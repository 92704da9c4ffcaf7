"""The goal hint (issue 27): ``planning.optimal_actions`` and the race envs' ``hint=True``."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.actions import Action
from babyrobot_marl.levels import get
from babyrobot_marl.levels.sources import maze_range_family
from babyrobot_marl.planning import hint as hint_module
from babyrobot_marl.planning import model, optimal_actions


def test_optimal_actions_on_the_empty_3x3_grid_by_hand():
    h = optimal_actions("default")  # start top left, exit bottom right
    assert h.shape == (3, 3, 5) and h.dtype == np.uint8
    east, south = int(Action.EAST), int(Action.SOUTH)
    for y in range(3):
        for x in range(3):
            want = set()
            if (x, y) != (2, 2):
                want = ({east} if x < 2 else set()) | ({south} if y < 2 else set())
            assert set(np.flatnonzero(h[y, x])) == want, (x, y)


def test_blocked_cells_and_exits_have_no_hint_and_read_only():
    level = get("blocked")
    h = optimal_actions(level)
    for x, y in level.blocked | level.exits:
        assert not h[y, x].any()
    with pytest.raises(ValueError):
        h[0, 0, 0] = 1


@pytest.mark.parametrize("name", ["walls", "maze-16x16", "maze-9x13-s7"])
def test_following_any_hinted_action_reaches_the_exit_in_the_fewest_steps(name):
    level = get(name)
    steps = model(level).exit_steps
    h = optimal_actions(level)
    rng = np.random.default_rng(0)
    moves = {1: (0, -1), 2: (1, 0), 3: (0, 1), 4: (-1, 0)}
    for start in [(0, 0), (level.width - 1, 0), (0, level.height - 1)]:
        x, y = start
        n = 0
        while (x, y) not in level.exits:
            a = int(rng.choice(np.flatnonzero(h[y, x])))
            x, y = x + moves[a][0], y + moves[a][1]
            n += 1
        assert n == steps[start[1] * level.width + start[0]]


def test_hint_rows_end_with_the_hint_of_the_robots_cell():
    env = race_v0.parallel_env(level="race-4", n_robots=4, observe="local", view_radius=1, hint=True)
    plain = race_v0.parallel_env(level="race-4", n_robots=4, observe="local", view_radius=1)
    space = env.observation_space("robot_0")
    assert list(space.nvec[-5:]) == [2] * 5 and len(space.nvec) == len(plain.observation_space("robot_0").nvec) + 5
    h = optimal_actions("race-4")
    obs, infos = env.reset(seed=1)
    ref, _ = plain.reset(seed=1)
    rng = np.random.default_rng(0)
    while env.agents:
        for a, o in obs.items():
            x, y = infos[a]["cell"]
            assert list(o[-5:]) == list(h[y, x]) and list(o[:-5]) == list(ref[a]) and space.contains(o)
        acts = {a: int(rng.integers(5)) for a in env.agents}
        obs, _, _, _, infos = env.step(acts)
        ref, *_ = plain.step(acts)


def test_a_finished_robot_sees_no_hint_and_the_batch_engine_gets_the_hint():
    env = race_v0.parallel_env(level="race-corridor", n_robots=4, observe="local", hint=True, finished="freeze")
    obs, _ = env.reset(seed=0)
    while env.agents:
        obs, _, _, _, infos = env.step({a: int(np.argmax(o[-5:])) for a, o in obs.items()})
        for a, info in infos.items():
            if info["finished"]:
                assert not obs[a][-5:].any()
    batch = env.batch(3)
    assert batch.observer is env._observer and batch.observer.nvec.size == len(env.observation_space("robot_0").nvec)


def test_on_a_family_each_drawn_level_gets_its_own_hint():
    env = race_v0.parallel_env(level="maze:5..12", n_robots=3, start="random", observe="local", hint=True)
    for seed in range(6):
        obs, infos = env.reset(seed=seed)
        h = optimal_actions(env.level)
        for a, o in obs.items():
            x, y = infos[a]["cell"]
            assert list(o[-5:]) == list(h[y, x]) and o[-5:].sum() >= 1


def test_planned_once_per_level_not_per_step_or_reset(monkeypatch):
    calls = []
    real = hint_module.value_iteration
    monkeypatch.setattr(hint_module, "value_iteration", lambda m: calls.append(m.level.name) or real(m))
    hint_module._optimal.cache_clear()
    env = race_v0.parallel_env(level="maze-8x8", n_robots=2, start="random", observe="local", hint=True)
    for seed in range(5):
        env.reset(seed=seed)
        for _ in range(10):
            if env.agents:
                env.step(dict.fromkeys(env.agents, 1))
    assert calls == ["maze-8x8"]
    calls.clear()
    family = race_v0.parallel_env(level=maze_range_family(6, 7, seeds=range(2)), n_robots=2, start="random",
                                  observe="local", hint=True)
    for seed in range(20):
        family.reset(seed=seed)
        family.step(dict.fromkeys(family.agents, 0))
    assert 1 <= len(calls) <= 5 and len(set(calls)) == len(calls)  # the first level, then at most the 4 drawn ones


@pytest.mark.parametrize(("kw", "message"), [
    (dict(hint=True), r"^hint: the goal hint is for observe='local'.*got observe='global'"),
    (dict(hint=True, observe="nearest"), r"^hint: the goal hint is for observe='local'"),
    (dict(hint="yes", observe="local"), r"^hint: must be True or False, got 'yes'"),
])
def test_bad_hint_arguments_are_clear_errors(kw, message):
    with pytest.raises(ValueError, match=message):
        race_v0.parallel_env(level="race-2", **kw)


def test_a_rewarding_cell_kind_is_refused_by_name_before_any_planning(monkeypatch):
    from babyrobot_marl import race_v0
    from babyrobot_marl.planning import hint

    def never(*args, **kwargs):
        raise AssertionError("planned a problem without a finite optimum")

    monkeypatch.setattr(hint, "value_iteration", never)
    with pytest.raises(ValueError, match=r"^floor_reward: the goal hint .* got 1\.0$"):
        hint.optimal_actions("maze-8x8", {"floor_reward": 1.0})
    with pytest.raises(ValueError, match=r"^small_puddle_reward: the goal hint"):
        hint.optimal_actions("puddles", {"small_puddle_reward": 0.5})
    with pytest.raises(ValueError, match="floor_reward"):
        race_v0.parallel_env(level="maze-8x8", n_robots=2, start="random", observe="local", hint=True,
                             rules={"floor_reward": 2.0})


def test_a_reward_of_a_kind_the_level_lacks_or_of_zero_plans():
    from babyrobot_marl.planning.hint import optimal_actions

    assert optimal_actions("maze-6x6", {"large_puddle_reward": 3.0}).shape == (6, 6, 5)  # no puddles in a maze
    assert optimal_actions("maze-6x6", {"floor_reward": 0.0}).shape == (6, 6, 5)
