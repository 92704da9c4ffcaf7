"""Lifelong own goals (``lifelong=True``): a robot on its target gets a new one and keeps going."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.goals import goal_step, next_goal, reach
from babyrobot_marl.envs.vector import RaceVectorEnv
from tests.test_own_goals import OPEN  # open floor, one exit in a corner


def shortest(env):
    """Every robot's first step on a shortest path to its own target."""
    t = env.table
    return {a: goal_step(t, t.cell_id(env.robot_cells[i]), t.cell_id(env.goals[a])) for i, a in enumerate(env.possible_agents)
            if a in env.agents}


def test_lifelong_is_for_own_goals_and_a_bool():
    with pytest.raises(ValueError, match=r"^lifelong: new targets are for own goals \(goals='own'\), got goals='exit'$"):
        race_v0.parallel_env(lifelong=True)
    with pytest.raises(ValueError, match=r"^lifelong: must be True or False, got 'yes'$"):
        race_v0.parallel_env(goals="own", lifelong="yes")


def test_a_robot_on_its_target_gets_a_new_one_and_keeps_going_until_the_step_limit():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own", lifelong=True, max_cycles=40)
    env.reset(seed=0, options={"goals": [(1, 0), (0, 3)]})
    _, rewards, terms, truncs, infos = env.step({"robot_0": 2, "robot_1": 1})  # both on their targets
    assert rewards == {"robot_0": 0.0, "robot_1": 0.0} and not any(terms.values()) and not any(truncs.values())
    assert env.goals_reached == [1, 1] and env.agents == ["robot_0", "robot_1"] and env.ranks == [0, 0]
    assert not infos["robot_0"]["finished"]
    goals = env.goals
    part = reach(env.table).component
    cells = [env.table.cell_id(c) for c in env.robot_cells]
    for i, a in enumerate(env.possible_agents):  # new: not where it stands, reachable, free, distinct
        g = env.table.cell_id(goals[a])
        assert g != cells[i] and part[g] == part[cells[i]] and env.table.move_prob[g] == 1.0
    assert goals["robot_0"] != goals["robot_1"]
    steps = 1
    while env.agents:
        _, rewards, terms, truncs, _ = env.step(shortest(env))
        steps += 1
    assert steps == 40 and all(truncs.values()) and not any(terms.values())
    assert min(env.goals_reached) >= 3  # shortest-path robots on an open level reach target after target


def test_the_same_seed_gives_the_same_targets_one_after_another():
    def run(seed):
        env = race_v0.parallel_env(level="mixed-8x8", n_robots=4, start="random", goals="own", lifelong=True, max_cycles=60)
        env.reset(seed=seed)
        seen = []
        while env.agents:
            env.step(shortest(env))
            seen.append(tuple(env.goals.values()))
        return seen, env.goals_reached

    assert run(5) == run(5)
    assert run(5) != run(6)


def test_without_lifelong_goals_reached_counts_each_robot_once():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own", max_cycles=40, finished="freeze")
    env.reset(seed=0, options={"goals": [(1, 0), (0, 3)]})
    env.step({"robot_0": 2, "robot_1": 0})
    assert env.goals_reached == [1, 0] and env.goals["robot_0"] == (1, 0)


def test_next_goal_draws_uniformly_among_the_cells_left():
    env = race_v0.parallel_env(level=OPEN, n_robots=1, goals="own")
    t = env.table
    free = reach(t).members[int(reach(t).component[0])]
    taken = set(free[1:5])
    rng = np.random.default_rng(0)
    counts = {}
    for _ in range(3000):
        g = next_goal(rng, t, free[0], taken)
        counts[g] = counts.get(g, 0) + 1
    assert set(counts) == set(free) - taken - {free[0]}
    expected = 3000 / len(counts)
    assert all(abs(c - expected) < 5 * expected**0.5 for c in counts.values())
    crowded = set(free) - {free[0], free[1]}  # one cell left: found however few draws hit it
    assert all(next_goal(rng, t, free[0], crowded) == free[1] for _ in range(50))


@pytest.mark.parametrize(
    ("level", "n_robots", "start", "kw"),
    [
        ("race-2", 2, "level", {}),
        ("mixed-8x8", 5, "random", {"observe": "local", "hint": True, "collisions": "bounce"}),
        ("race-corridor", 4, "level", {"observe": "nearest", "k": 2}),
        ("race-2", 1, "fill", {"observe": "local"}),
    ],
)
def test_the_batch_engine_plays_lifelong_races_as_the_env_does(level, n_robots, start, kw):
    n_envs = 4
    envs = [race_v0.parallel_env(level=level, n_robots=n_robots, start=start, finished="freeze", goals="own", lifelong=True,
                                 max_cycles=50, **kw) for _ in range(n_envs)]
    b = envs[0].batch(n_envs)
    b.seed(range(n_envs))
    b.reset_envs(range(n_envs))
    for i, e in enumerate(envs):
        e.reset(seed=i)
    rng, reached = np.random.default_rng(0), 0
    for _ in range(200):
        # half the robots walk to their targets, half at random: targets are reached and collisions happen
        actions = rng.integers(0, 5, (n_envs, n_robots))
        for i, e in enumerate(envs):
            for k, a in enumerate(e.possible_agents[::2]):
                actions[i, 2 * k] = shortest(e)[a]
        rewards, finishing, _, _, over = b.step(actions)
        obs = b.observations()
        assert not finishing.any()
        for i, e in enumerate(envs):
            o, r, te, tr, _ = e.step({a: int(actions[i, k]) for k, a in enumerate(e.agents)})
            for k, a in enumerate(e.possible_agents):
                assert r[a] == rewards[i, k] and np.array_equal(o[a], obs[i, k])
            assert e.goals_reached == b.reached[i].tolist()
            assert [e.table.cell_id(e.goals[a]) for a in e.possible_agents] == b.goals[i].tolist()
            assert (not e.agents) == over[i]
            if not e.agents:
                reached += sum(e.goals_reached)
                e.reset()
        if over.any():
            b.reset_envs(np.flatnonzero(over))
    assert reached > 2 * n_envs


def test_the_vector_race_and_the_gymnasium_race_take_lifelong():
    v = RaceVectorEnv(2, level="race-4", n_robots=4, goals="own", lifelong=True, max_cycles=30)
    single = race_v0.parallel_env(level="race-4", n_robots=4, goals="own", lifelong=True, max_cycles=30, finished="freeze")
    obs, _ = v.reset(seed=3)
    s_obs, _ = single.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(29):
        actions = rng.integers(0, 5, 8)
        obs, rewards, terms, truncs, _ = v.step(actions)
        s_obs, s_r, *_ = single.step({a: int(actions[k]) for k, a in enumerate(single.agents)})
        assert all(np.array_equal(obs[k], s_obs[f"robot_{k}"]) and rewards[k] == s_r[f"robot_{k}"] for k in range(4))
    obs, rewards, terms, truncs, _ = v.step(rng.integers(0, 5, 8))
    assert truncs.all() and not terms.any()
    g = gym.make("babyrobot_marl/BabyRobotRace-v0", level=OPEN, opponents=["shortest"], goals="own", lifelong=True, max_cycles=25)
    g.reset(seed=0)
    done = False
    steps = 0
    while not done:
        _, _, term, trunc, _ = g.step(g.action_space.sample())
        done, steps = term or trunc, steps + 1
    assert trunc and not term and steps == 25 and g.unwrapped.race.goals_reached[1] >= 2  # the shortest opponent kept going


# ---------------------------------------------------------------------------- evaluate: throughput
def test_throughput_by_hand_and_only_for_lifelong_runs():
    from babyrobot_marl.experiments import Episode, crowd_metrics

    eps = [Episode(0, "a", 10, [0, 0], goals_reached=5), Episode(1, "b", 20, [0, 0], goals_reached=2)]
    m = crowd_metrics(eps, 2, 20, lifelong=True)
    assert m["throughput"] == (0.5 + 0.1) / 2 and 0 <= m["throughput_low"] <= m["throughput"] <= m["throughput_high"] <= 2
    assert "throughput" not in crowd_metrics(eps, 2, 20)


def test_evaluate_own_goals_shortest_robots_reach_their_targets_and_lifelong_reports_throughput():
    from babyrobot_marl.experiments import evaluate

    ev = evaluate(None, level="race-4", n_robots=2, episodes=6, seed=0, goals="own", max_cycles=60)
    assert ev.names[-1] == "makespan" and ev.metrics["shortest"]["success_rate"] > ev.metrics["random"]["success_rate"]
    assert ev.metrics["shortest"]["success_rate"] >= 0.9
    ev = evaluate(None, level="race-4", n_robots=2, episodes=6, seed=0, goals="own", lifelong=True, max_cycles=60)
    shortest, rand = ev.metrics["shortest"], ev.metrics["random"]
    assert ev.names[-1] == "throughput" and "throughput" in ev.table()
    assert shortest["success_rate"] == 0.0 and shortest["throughput"] > 0.1 > rand["throughput"] >= 0
    assert sum(e.goals_reached for e in ev.episodes["shortest"]) == round(shortest["throughput"] * 6 * 60)


def test_the_evaluate_command_takes_goals_own_and_lifelong(capsys):
    import json

    from tests.cli_run import run

    code = run(["evaluate", "shortest", "--level", "race-4", "--robots", "2", "--episodes", "3", "--goals", "own", "--lifelong"])
    out, err = capsys.readouterr()
    assert code == 0, err
    last = json.loads(out.strip().splitlines()[-1])
    assert last["policy"]["throughput"] > 0 and last["policy"]["throughput"] == last["shortest"]["throughput"]
    code = run(["evaluate", "shortest", "--level", "race-4", "--lifelong"])
    out, err = capsys.readouterr()
    assert code == 2 and err.strip().splitlines() == [
        "babyrobot-marl: error: --lifelong: new targets replace reached ones, so it needs --goals own"
    ]
