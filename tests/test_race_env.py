"""The race env (``race_v0.parallel_env`` / ``RaceEnv``): arguments, starts, observations, state,
finishing (remove / freeze), truncation, bad input, copies and seeding."""

from __future__ import annotations

import copy
import pickle

import cloudpickle
import numpy as np
import pytest
from gymnasium import spaces

from babyrobot_marl import Action, race_v0
from babyrobot_marl.core.outcomes import OUTCOME_NAMES
from babyrobot_marl.envs.race import RaceEnv
from tests.strategies import OPEN

STAY, NORTH, EAST, SOUTH, WEST = (int(a) for a in (Action.STAY, Action.NORTH, Action.EAST, Action.SOUTH, Action.WEST))
MODES = ("block", "bounce", "pass", "soft")

CORRIDOR = """
+-+-+-+-+-+-+-+
|0 1 2 3     E|
+-+-+-+-+-+-+-+
"""  # one row, x = 0..6, exit at x = 6; no puddles or glass: moves are certain
TINY = """
+-+-+-+
|0   E|
+-+-+-+
"""  # 3x1: free cells (0,0) and (1,0)


def all_stay(env) -> dict[str, int]:
    return dict.fromkeys(env.agents, STAY)


def run(env, seed: int, n_steps: int, actions_seed: int = 7):
    """A trajectory of seeded random actions: every step's (obs, rewards, terms, truncs, infos)."""
    out = [env.reset(seed=seed)]
    g = np.random.default_rng(actions_seed)
    for _ in range(n_steps):
        if not env.agents:
            break
        out.append(env.step({a: int(g.integers(5)) for a in env.agents}))
    return out


def same(a, b) -> bool:
    """Deep equality of nested dicts / tuples / lists / arrays (arrays: dtype and values)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.dtype == b.dtype and np.array_equal(a, b)
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return type(a) is type(b) and a == b


# ------------------------------------------------------------------------ construction
def test_defaults_are_two_robots_on_race_2_blocking():
    env = race_v0.parallel_env()
    assert isinstance(env, RaceEnv)
    assert env.possible_agents == ["robot_0", "robot_1"]
    assert env.collisions == "block" and env.finished_mode == "remove" and env.level.name == "race-2"
    assert env.agents == []  # before reset
    env.reset(seed=0)
    assert env.agents == ["robot_0", "robot_1"]
    assert env.robot_cells == list(env.level.starts[:2])


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"collisions": "x"}, "collisions"),
        ({"collisions": "Block"}, "collisions"),
        ({"finished": "x"}, "finished"),
        ({"start": "x"}, "start"),
        ({"max_cycles": 0}, "max_cycles"),
        ({"max_cycles": -3}, "max_cycles"),
        ({"max_cycles": 2.5}, "max_cycles"),
        ({"n_robots": 0}, "n_robots"),
        ({"n_robots": -1}, "n_robots"),
        ({"render_mode": "rgb"}, "render_mode"),
    ],
)
def test_bad_arguments_are_value_errors_naming_the_argument(kwargs, name):
    with pytest.raises(ValueError, match=name):
        race_v0.parallel_env(**kwargs)


def test_an_unknown_keyword_argument_is_an_error_naming_it():
    with pytest.raises((TypeError, ValueError), match="colisions"):
        race_v0.parallel_env(colisions="block")


def test_rule_overrides_are_accepted_as_keywords():
    env = race_v0.parallel_env(win_bonus=0, glass_pass_prob=1)
    assert env.rules.win_bonus == 0.0 and env.rules.glass_pass_prob == 1.0


def test_default_max_cycles_is_at_least_100_and_grows_with_the_level():
    assert race_v0.parallel_env(level="race-2").max_cycles >= 100
    assert race_v0.parallel_env(level="maze-16x16", n_robots=1).max_cycles >= 16 * 16


# ------------------------------------------------------------------------ starts
def test_level_start_with_too_few_starts_suggests_fill_or_random():
    with pytest.raises(ValueError, match="n_robots") as err:
        race_v0.parallel_env(level="race-2", n_robots=3)
    assert "start='fill'" in str(err.value) and "start='random'" in str(err.value)


def test_fill_start_uses_the_level_starts_then_random_free_cells():
    env = race_v0.parallel_env(level="race-2", n_robots=5, start="fill")
    level = env.level
    seen = set()
    for seed in range(20):
        env.reset(seed=seed)
        cells = env.robot_cells
        assert cells[:2] == list(level.starts)
        assert len(set(cells)) == 5
        assert all(c in level.free_cells() for c in cells[2:])
        seen.add(tuple(cells[2:]))
    assert len(seen) > 1  # the extra robots are drawn, not fixed


def test_random_start_is_seeded_and_draws_distinct_free_cells():
    env = race_v0.parallel_env(level="maze-8x8", n_robots=6, start="random")
    free = set(env.level.free_cells())
    draws = {}
    for seed in range(10):
        env.reset(seed=seed)
        cells = env.robot_cells
        assert len(set(cells)) == 6 and set(cells) <= free
        draws[seed] = cells
    twin = race_v0.parallel_env(level="maze-8x8", n_robots=6, start="random")
    for seed in (3, 0, 7):
        twin.reset(seed=seed)
        assert twin.robot_cells == draws[seed]
    assert len({tuple(c) for c in draws.values()}) > 1


def test_random_start_draws_again_at_each_unseeded_reset():
    env = race_v0.parallel_env(level="maze-8x8", n_robots=6, start="random")
    env.reset(seed=1)
    starts = {tuple(env.robot_cells)}
    for _ in range(5):
        env.reset()
        starts.add(tuple(env.robot_cells))
    assert len(starts) > 1


@pytest.mark.parametrize("start", ["fill", "random"])
def test_more_robots_than_free_cells_is_an_error_naming_n_robots(start):
    race_v0.parallel_env(level=TINY, n_robots=2, start=start).reset(seed=0)  # exactly fits
    with pytest.raises(ValueError, match="n_robots"):
        race_v0.parallel_env(level=TINY, n_robots=3, start=start)


def test_tiny_level_with_every_free_cell_taken_places_each_robot_once():
    env = race_v0.parallel_env(level=TINY, n_robots=2, start="random")
    for seed in range(5):
        env.reset(seed=seed)
        assert sorted(env.robot_cells) == [(0, 0), (1, 0)]


# ------------------------------------------------------------------------ spaces, observations, state
def test_spaces_are_the_same_object_at_every_call():
    env = race_v0.parallel_env(level="race-4", n_robots=4)
    for agent in env.possible_agents:
        assert env.observation_space(agent) is env.observation_space(agent)
        assert env.action_space(agent) is env.action_space(agent)


@pytest.mark.parametrize(("level", "n"), [("race-2", 2), ("race-4", 4), ("race-corridor", 3), (OPEN, 1)])
def test_spaces_have_the_documented_shapes(level, n):
    env = race_v0.parallel_env(level=level, n_robots=n)
    w, h = env.level.width, env.level.height
    for agent in env.possible_agents:
        obs_space = env.observation_space(agent)
        assert isinstance(obs_space, spaces.MultiDiscrete)
        assert obs_space.nvec.tolist() == [w, h] + [w, h, 2] * (n - 1)
        assert env.action_space(agent) == spaces.Discrete(5)
    assert isinstance(env.state_space, spaces.Box)
    assert env.state_space.shape == (3 * n,)
    assert env.state_space.low.tolist() == [0] * (3 * n)
    assert env.state_space.high.tolist() == [w - 1, h - 1, 1] * n


def test_observations_start_with_the_robot_then_the_next_robots_in_turn():
    env = race_v0.parallel_env(level=OPEN, n_robots=4, collisions="pass")
    env.reset(seed=0)
    cells = [(0, 2), (1, 3), (2, 4), (3, 0)]
    env.set_cells(cells)
    obs, *_ = env.step(all_stay(env))
    for i in range(4):
        want = list(cells[i])
        for k in range(1, 4):
            want += [*cells[(i + k) % 4], 0]
        got = obs[f"robot_{i}"]
        assert got.dtype == np.int64
        assert got.tolist() == want
        assert env.observation_space(f"robot_{i}").contains(got)
    assert env.state().tolist() == [v for c in cells for v in (*c, 0)]
    assert env.state().dtype == np.int64 and env.state_space.contains(env.state())


@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_a_finished_robot_is_seen_at_its_exit_with_the_finished_flag(finished):
    env = race_v0.parallel_env(level=OPEN, n_robots=3, finished=finished)
    env.reset(seed=0)
    env.set_cells([(3, 4), (0, 0), (1, 0)])
    obs, *_ = env.step({"robot_0": EAST, "robot_1": STAY, "robot_2": STAY})
    exit_cell = [4, 4]
    assert obs["robot_1"].tolist() == [0, 0, 1, 0, 0, *exit_cell, 1]  # robot_2 next, then robot_0
    assert obs["robot_2"].tolist() == [1, 0, *exit_cell, 1, 0, 0, 0]
    assert env.state().tolist() == [*exit_cell, 1, 0, 0, 0, 1, 0, 0]
    assert obs["robot_0"].tolist() == [*exit_cell, 0, 0, 0, 1, 0, 0]  # reported in the finishing step
    obs, *_ = env.step(all_stay(env))
    assert ("robot_0" in obs) == (finished == "freeze")
    assert env.state().tolist() == [*exit_cell, 1, 0, 0, 0, 1, 0, 0]  # it stays finished


@pytest.mark.parametrize("mode", MODES)
def test_every_observation_and_state_lies_in_its_space(mode):
    env = race_v0.parallel_env(level="race-4", n_robots=4, collisions=mode, finished="freeze")
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        g = np.random.default_rng(seed)
        while env.agents:
            for agent, o in obs.items():
                assert o.dtype == np.int64 and env.observation_space(agent).contains(o)
            assert env.state_space.contains(env.state())
            obs, *_ = env.step({a: int(g.integers(5)) for a in env.agents})


def test_observations_are_fresh_arrays_each_step():
    env = race_v0.parallel_env(level=CORRIDOR, n_robots=2)
    obs0, _ = env.reset(seed=0)
    kept = obs0["robot_0"].copy()
    obs1, *_ = env.step({"robot_0": STAY, "robot_1": EAST})
    obs1["robot_0"][:] = 0  # a user scribbling on an observation changes nothing else
    assert obs0["robot_0"].tolist() == kept.tolist()
    assert obs1["robot_1"].tolist() == [2, 0, 0, 0, 0]


def test_reset_returns_every_agent_with_start_infos():
    env = race_v0.parallel_env(level="race-4", n_robots=4)
    obs, infos = env.reset(seed=3)
    assert set(obs) == set(infos) == set(env.possible_agents)
    for i, agent in enumerate(env.possible_agents):
        assert tuple(infos[agent]["cell"].tolist()) == env.level.starts[i]
        assert OUTCOME_NAMES[infos[agent]["outcome"]] == "start"
        assert infos[agent]["finished"] is False and infos[agent]["blocked"] is False
        assert obs[agent][:2].tolist() == list(env.level.starts[i])


# ------------------------------------------------------------------------ finishing: remove and freeze
def _finish_robot_0(env):
    """Robot 0 one step from the exit of CORRIDOR, robot 1 far behind; robot 0 steps in."""
    env.reset(seed=0)
    env.set_cells([(5, 0), (0, 0)])
    return env.step({"robot_0": EAST, "robot_1": STAY})


def test_remove_a_finished_robot_leaves_agents_in_the_step_it_finishes_and_never_returns():
    env = race_v0.parallel_env(level=CORRIDOR, n_robots=2, finished="remove")
    obs, rewards, terms, truncs, infos = _finish_robot_0(env)
    assert set(obs) == set(rewards) == set(terms) == set(truncs) == set(infos) == {"robot_0", "robot_1"}
    assert terms == {"robot_0": True, "robot_1": False} and truncs == {"robot_0": False, "robot_1": False}
    assert infos["robot_0"]["finished"] is True and infos["robot_0"]["rank"] == 1
    assert env.agents == ["robot_1"]
    for _ in range(3):
        obs, rewards, terms, truncs, infos = env.step({"robot_1": STAY})
        assert set(obs) == set(rewards) == set(terms) == set(truncs) == set(infos) == {"robot_1"}
        assert env.agents == ["robot_1"]
    # an action for the finished robot is checked, then ignored (as PettingZoo's conversions do)
    with pytest.raises(ValueError, match="robot_0"):
        env.step({"robot_0": 9, "robot_1": STAY})
    assert env.elapsed_steps == 4
    obs, rewards, terms, truncs, infos = env.step({"robot_0": STAY, "robot_1": EAST})
    assert set(obs) == set(rewards) == set(infos) == {"robot_1"} and env.elapsed_steps == 5


def test_remove_ignores_actions_for_finished_robots_as_agilerl_sends_them():
    """AgileRL's vector env sends an action for every possible agent: the race goes on as without them."""
    a, b = (race_v0.parallel_env(level=CORRIDOR, n_robots=2, finished="remove") for _ in range(2))
    _finish_robot_0(a), _finish_robot_0(b)
    for action in (EAST, EAST, STAY, EAST):
        assert str(a.step({"robot_0": action, "robot_1": action})) == str(b.step({"robot_1": action}))


def test_remove_when_everyone_has_finished_step_with_no_actions_returns_empty_dicts():
    env = race_v0.parallel_env(level=CORRIDOR, n_robots=2, finished="remove")
    _finish_robot_0(env)
    for _ in range(5):
        _, _, terms, _, _ = env.step({"robot_1": EAST})
    _, _, terms, _, _ = env.step({"robot_1": EAST})  # from (0,0): six steps east reach the exit
    assert terms == {"robot_1": True}
    assert env.agents == [] and env.ranks == [1, 2]
    assert env.step({}) == ({}, {}, {}, {}, {})
    with pytest.raises(ValueError, match="reset"):
        env.step({"robot_1": STAY})


def test_freeze_keeps_finished_robots_parked_with_reward_zero_until_the_race_ends():
    env = race_v0.parallel_env(level=CORRIDOR, n_robots=2, finished="freeze")
    obs, rewards, terms, truncs, infos = _finish_robot_0(env)
    assert env.agents == ["robot_0", "robot_1"]
    assert terms == {"robot_0": False, "robot_1": False}  # not yet: it would have to leave agents
    assert infos["robot_0"]["finished"] is True and infos["robot_0"]["rank"] == 1
    assert rewards["robot_0"] == 10.0  # the exit's 0 plus the win bonus, in the finishing step
    for k in range(6):
        last = k == 5  # six steps east from (0,0) reach the exit
        obs, rewards, terms, truncs, infos = env.step({"robot_0": NORTH, "robot_1": EAST})  # parked: action ignored
        assert set(obs) == {"robot_0", "robot_1"}
        assert rewards["robot_0"] == 0.0
        assert obs["robot_0"][:2].tolist() == [6, 0]
        assert infos["robot_0"]["finished"] is True and OUTCOME_NAMES[infos["robot_0"]["outcome"]] == "finished"
        assert terms == {"robot_0": last, "robot_1": last}
        assert truncs == {"robot_0": False, "robot_1": False}
        assert env.agents == ([] if last else ["robot_0", "robot_1"])
    assert rewards["robot_1"] == 0.0 and infos["robot_1"]["rank"] == 2
    assert env.returns == [10.0, -1.0 * 6]  # robot_1: one step waiting, five on the floor, the exit's 0


def test_freeze_parked_robots_are_terminated_and_racers_truncated_at_max_cycles():
    env = race_v0.parallel_env(level=CORRIDOR, n_robots=2, finished="freeze", max_cycles=3)
    _finish_robot_0(env)
    env.step({"robot_0": STAY, "robot_1": STAY})
    _, _, terms, truncs, _ = env.step({"robot_0": STAY, "robot_1": STAY})
    assert terms == {"robot_0": True, "robot_1": False}
    assert truncs == {"robot_0": False, "robot_1": True}
    assert env.agents == []


def test_freeze_checks_a_parked_robots_action():
    env = race_v0.parallel_env(level=CORRIDOR, n_robots=2, finished="freeze")
    _finish_robot_0(env)
    with pytest.raises(ValueError, match="robot_0"):
        env.step({"robot_0": 9, "robot_1": STAY})
    env.step({"robot_1": STAY})  # a parked robot's action may be left out


@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_returns_are_the_same_under_remove_and_freeze(finished):
    env = race_v0.parallel_env(level="race-4", n_robots=4, finished=finished)
    other = race_v0.parallel_env(level="race-4", n_robots=4, finished="remove" if finished == "freeze" else "freeze")
    for seed in range(4):
        totals = []
        for e in (env, other):
            e.reset(seed=seed)
            g = np.random.default_rng(seed)
            total = dict.fromkeys(e.possible_agents, 0.0)
            while e.agents:
                acts = [int(g.integers(5)) for _ in e.possible_agents]  # same draws whatever the agents
                _, rewards, *_ = e.step({a: acts[int(a[-1])] for a in e.agents})
                for a, r in rewards.items():
                    total[a] += r
            totals.append(total)
            assert e.returns == [total[a] for a in e.possible_agents]
        assert totals[0] == totals[1]


# ------------------------------------------------------------------------ truncation
@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_race_is_truncated_at_max_cycles(finished):
    env = race_v0.parallel_env(level="race-4", n_robots=4, max_cycles=5, finished=finished)
    env.reset(seed=0)
    for t in range(1, 6):
        _, rewards, terms, truncs, infos = env.step(all_stay(env))
        assert env.elapsed_steps == t
        assert not any(terms.values())
        assert all(truncs.values()) == (t == 5) and any(truncs.values()) == (t == 5)
        assert set(truncs) == set(env.possible_agents)
    assert env.agents == []
    assert env.step({}) == ({}, {}, {}, {}, {})


def test_reset_after_a_race_starts_a_fresh_one():
    env = race_v0.parallel_env(level="race-2", max_cycles=2)
    env.reset(seed=0)
    env.step(all_stay(env))
    env.step(all_stay(env))
    assert env.agents == []
    env.reset()
    assert env.agents == env.possible_agents and env.elapsed_steps == 0 and env.ranks == [0, 0]
    assert env.robot_cells == list(env.level.starts)


# ------------------------------------------------------------------------ bad actions
def _mid_race(seed: int = 5, finished: str = "remove"):
    """A race on race-4 (puddles, glass: random moves) a few steps in, robot_0 already finished."""
    env = race_v0.parallel_env(level="race-4", n_robots=4, finished=finished)
    env.reset(seed=seed)
    env.set_cells([(4, 3), (6, 0), (6, 6), (0, 6)])  # the exit (3, 3) is open only to the east, to (4, 3)
    env.step({"robot_0": WEST, "robot_1": STAY, "robot_2": NORTH, "robot_3": EAST})
    assert env.ranks[0] == 1
    return env


BAD_ACTIONS = {
    "unknown agent": {"robot_1": 0, "robot_2": 0, "robot_3": 0, "robot_9": 0},
    "not an agent name": {"robot_1": 0, "robot_2": 0, "robot_3": 0, 1: 0},
    "finished agent, bad action": {"robot_0": 7, "robot_1": 0, "robot_2": 0, "robot_3": 0},
    "missing agent": {"robot_1": 0, "robot_2": 0},
    "too large": {"robot_1": 5, "robot_2": 0, "robot_3": 0},
    "negative": {"robot_1": -1, "robot_2": 0, "robot_3": 0},
    "float": {"robot_1": 2.5, "robot_2": 0, "robot_3": 0},
    "whole float": {"robot_1": 2.0, "robot_2": 0, "robot_3": 0},
    "string": {"robot_1": "1", "robot_2": 0, "robot_3": 0},
    "None": {"robot_1": None, "robot_2": 0, "robot_3": 0},
    "list": {"robot_1": [1], "robot_2": 0, "robot_3": 0},
    "bool": {"robot_1": True, "robot_2": 0, "robot_3": 0},
    "not a dict": [0, 0, 0],
    "None for the dict": None,
}


@pytest.mark.parametrize("case", list(BAD_ACTIONS))
def test_a_bad_actions_dict_is_a_value_error_and_changes_nothing(case):
    env, twin = _mid_race(), _mid_race()
    before = (env.state().tolist(), env.robot_cells, env.agents[:], env.elapsed_steps, env.returns, env.ranks)
    with pytest.raises(ValueError):
        env.step(BAD_ACTIONS[case])
    assert (env.state().tolist(), env.robot_cells, env.agents, env.elapsed_steps, env.returns, env.ranks) == before
    # and the next good step gives exactly what it gives in a twin that never saw the bad one
    good = {"robot_1": WEST, "robot_2": NORTH, "robot_3": EAST}
    for _ in range(4):
        if not env.agents:
            break
        assert same(env.step({a: good[a] for a in env.agents}), twin.step({a: good[a] for a in twin.agents}))


@pytest.mark.parametrize("case", ["unknown agent", "missing agent", "too large"])
def test_a_bad_action_error_names_the_agent(case):
    env = _mid_race()
    with pytest.raises(ValueError, match="robot_9" if case == "unknown agent" else "robot_[13]"):
        env.step(BAD_ACTIONS[case])


def test_numpy_integer_actions_are_accepted_like_ints():
    env, twin = _mid_race(), _mid_race()
    acts = {"robot_1": WEST, "robot_2": NORTH, "robot_3": EAST}
    assert same(env.step({a: np.int64(v) for a, v in acts.items()}), twin.step(acts))



@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_the_order_of_the_actions_dict_does_not_matter(finished):
    """Actions given in another order than ``agents`` (not the step's fast path) act the same."""
    env, twin = race_v0.parallel_env(level="race-4", n_robots=4, finished=finished), race_v0.parallel_env(
        level="race-4", n_robots=4, finished=finished
    )
    env.reset(seed=3)
    twin.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(200):
        if not env.agents:
            break
        acts = {a: int(rng.integers(5)) for a in env.agents}
        assert same(env.step(dict(reversed(acts.items()))), twin.step(acts))
    assert env.ranks == twin.ranks and env.returns == twin.returns

# ------------------------------------------------------------------------ copies and seeding
@pytest.mark.parametrize("how", ["pickle", "cloudpickle", "deepcopy"])
@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_a_copy_made_mid_race_continues_exactly_like_the_original(how, finished):
    env = race_v0.parallel_env(level="race-4", n_robots=4, finished=finished, start="fill")
    env.reset(seed=11)
    g = np.random.default_rng(0)
    for _ in range(15):
        env.step({a: int(g.integers(5)) for a in env.agents})
    if how == "pickle":
        twin = pickle.loads(pickle.dumps(env))
    elif how == "cloudpickle":
        twin = cloudpickle.loads(cloudpickle.dumps(env))
    else:
        twin = copy.deepcopy(env)
    assert twin is not env
    assert twin.state().tolist() == env.state().tolist() and twin.agents == env.agents
    # the rest of this race, and two more unseeded races (the generator state travels too)
    for _ in range(3):
        while env.agents:
            acts = {a: int(g.integers(5)) for a in env.agents}
            assert same(env.step(acts), twin.step(dict(acts)))
        assert same(env.reset(), twin.reset())


def test_same_seed_and_actions_give_identical_trajectories():
    for mode in MODES:
        a = run(race_v0.parallel_env(level="race-4", n_robots=4, collisions=mode), seed=42, n_steps=200)
        b = run(race_v0.parallel_env(level="race-4", n_robots=4, collisions=mode), seed=42, n_steps=200)
        assert same(a, b)


def test_different_seeds_give_different_trajectories():
    # race-4 has puddles and a glass wall: the same actions meet different luck
    trajectories = [run(race_v0.parallel_env(level="race-4", n_robots=4), seed=s, n_steps=60) for s in range(6)]
    assert any(not same(trajectories[0], t) for t in trajectories[1:])
    starts = [run(race_v0.parallel_env(level="maze-8x8", n_robots=6, start="random"), seed=s, n_steps=0) for s in range(6)]
    assert any(not same(starts[0], s) for s in starts[1:])


def test_reseeding_repeats_the_race_and_the_env_owns_its_randomness():
    env = race_v0.parallel_env(level="race-4", n_robots=4)
    first = run(env, seed=9, n_steps=80)
    np.random.seed(123)  # the global generator has nothing to do with it
    assert same(run(env, seed=9, n_steps=80), first)
