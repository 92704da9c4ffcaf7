"""``finished="stay"`` (POGEMA's ``on_target="nothing"``): robots stay on their own targets, racing on.
Stepped against POGEMA itself in ``tests_integrations/test_pogema_soft.py``."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level
from babyrobot_marl.envs.race_goals import towards_own_goal
from babyrobot_marl.experiments import evaluate
from babyrobot_marl.planning import goal_actions
from tests.batch_twins import batch_beside

ROW = Level.from_grid(".....")
STAY, EAST, WEST = 0, 2, 4


def staying(level=ROW, n_robots=2, **kw):
    kw = {"goals": "own", "finished": "stay", "start": "random", "collisions": "soft", **kw}
    return race_v0.parallel_env(level=level, n_robots=n_robots, **kw)


def test_a_robot_on_its_target_stays_racing_earns_nothing_and_may_leave():
    env = staying(max_cycles=20)
    env.reset(seed=0, options={"starts": [(0, 0), (4, 0)], "goals": [(1, 0), (3, 0)]})
    _, rewards, terms, truncs, infos = env.step({"robot_0": EAST, "robot_1": STAY})
    assert env.agents == ["robot_0", "robot_1"] and env.robot_cells == [(1, 0), (4, 0)]
    assert rewards == {"robot_0": 0.0, "robot_1": -1.0} and not any(terms.values()) and not any(truncs.values())
    assert [infos[a]["finished"] for a in env.agents] == [True, False] and env.goals_reached == [1, 0]
    _, rewards, _, _, infos = env.step({"robot_0": EAST, "robot_1": STAY})  # it leaves its target again
    assert env.robot_cells == [(2, 0), (4, 0)] and rewards["robot_0"] == -1.0
    assert not infos["robot_0"]["finished"] and env.goals_reached == [0, 0]


def test_the_race_ends_when_every_robot_stands_on_its_target_at_once():
    env = staying(max_cycles=20)
    env.reset(seed=0, options={"starts": [(0, 0), (4, 0)], "goals": [(1, 0), (3, 0)]})
    env.step({"robot_0": EAST, "robot_1": STAY})
    _, rewards, terms, truncs, infos = env.step({"robot_0": STAY, "robot_1": WEST})
    assert terms == {"robot_0": True, "robot_1": True} and truncs == {"robot_0": False, "robot_1": False}
    assert rewards == {"robot_0": 0.0, "robot_1": 0.0} and all(i["finished"] for i in infos.values())
    assert env.agents == [] and env.step({}) == ({}, {}, {}, {}, {})


def test_at_the_step_limit_every_robot_is_truncated_on_its_target_or_not():
    env = staying(max_cycles=2)
    env.reset(seed=0, options={"starts": [(0, 0), (4, 0)], "goals": [(1, 0), (2, 0)]})
    env.step({"robot_0": EAST, "robot_1": STAY})
    _, _, terms, truncs, infos = env.step({"robot_0": STAY, "robot_1": STAY})
    assert terms == {"robot_0": False, "robot_1": False} and truncs == {"robot_0": True, "robot_1": True}
    assert [infos[a]["finished"] for a in ("robot_0", "robot_1")] == [True, False] and env.agents == []


def test_a_robot_on_its_target_blocks_the_robot_behind_it():
    # robot 0 sits on its target (1, 0); robot 1, bound for (0, 0), cannot pass it in the one-cell corridor
    env = staying(max_cycles=6)
    env.reset(seed=0, options={"starts": [(0, 0), (2, 0)], "goals": [(1, 0), (0, 0)]})
    env.step({"robot_0": EAST, "robot_1": WEST})  # both want (1, 0): the lower number gets it (soft)
    assert env.robot_cells == [(1, 0), (2, 0)]
    for _ in range(3):
        _, _, _, _, infos = env.step({"robot_0": STAY, "robot_1": WEST})
        assert env.robot_cells == [(1, 0), (2, 0)] and infos["robot_1"]["blocked"]
    remove = race_v0.parallel_env(level=ROW, n_robots=2, goals="own", start="random", collisions="soft")
    remove.reset(seed=0, options={"starts": [(0, 0), (2, 0)], "goals": [(1, 0), (0, 0)]})
    remove.step({"robot_0": EAST, "robot_1": WEST})
    remove.step({"robot_1": WEST})
    assert remove.robot_cells[1] == (1, 0)  # finished="remove": the finisher's cell is free at once


def test_local_rows_mark_each_staying_robots_target_as_pogema_does_on_and_off_it():
    level, r = "maze-8x8", 2
    env = staying(level, n_robots=6, observe="local", view_radius=r, max_cycles=200)
    obs, _ = env.reset(seed=3)
    goals = [env.goals[a] for a in env.possible_agents]
    towards = [goal_actions(env.level, goal) for goal in goals]
    g, stayed, side = np.random.default_rng(0), 0, 2 * r + 1
    while env.agents:
        acts = {}
        for k, a in enumerate(env.possible_agents):
            x, y = env.robot_cells[k]
            best = np.flatnonzero(towards[k][y, x])
            acts[a] = int(best[0]) if best.size and g.random() < 0.9 else int(g.integers(0, 5))
        obs, _, _, _, infos = env.step(acts)
        stayed += sum(i["finished"] for i in infos.values())
        for k, a in enumerate(env.possible_agents):
            (x, y), (gx, gy) = env.robot_cells[k], goals[k]
            expected = np.zeros((side, side), dtype=int)
            expected[min(max(gy - y, -r), r) + r, min(max(gx - x, -r), r) + r] = 1  # POGEMA's clamped offsets
            assert obs[a][-side * side :].reshape(side, side).tolist() == expected.tolist()
    assert stayed >= 20  # robots stood on their targets (the centre marked) many times


def test_stay_needs_own_goals_without_lifelong():
    with pytest.raises(ValueError, match=r"^finished: 'stay' keeps robots on their own targets.*goals='exit'"):
        race_v0.parallel_env(level="race-4", n_robots=2, finished="stay")
    with pytest.raises(ValueError, match=r"^finished: .*lifelong=True"):
        race_v0.parallel_env(level="race-4", n_robots=2, goals="own", lifelong=True, finished="stay")
    with pytest.raises(ValueError, match=r"^finished: must be one of 'remove', 'freeze', 'stay', got 'sit'"):
        race_v0.parallel_env(level="race-4", n_robots=2, goals="own", finished="sit")


HALL = Level.from_grid("\n".join(["............", "..#......#..", "............", "......#.....", "............",
                                   "....#.......", "............", "............"]))
STAY_RACES = [  # level, robots, step limit, observation; each under three collision rules
    ("race-4", 2, 8, {}),
    ("mixed-8x8", 4, 30, {"observe": "local", "view_radius": 1, "hint": True}),
    ("race-corridor", 3, 30, {}),
    (HALL, 8, 60, {"observe": "nearest", "k": 2}),
    (HALL, 16, 60, {"observe": "local", "view_radius": 2}),
]


@pytest.mark.parametrize("collisions", ["soft", "block", "bounce"])
@pytest.mark.parametrize(("level", "n_robots", "limit", "kw"), STAY_RACES)
def test_the_batch_engine_plays_the_staying_races_of_parallel_env_step_for_step(level, n_robots, limit, kw, collisions):
    n_envs, seed0 = 4, 30
    envs = [staying(level, n_robots, collisions=collisions, max_cycles=limit, **kw) for _ in range(n_envs)]
    batch = batch_beside(envs, seed0)
    rng = np.random.default_rng(5)
    solved = truncated = left = 0
    for _ in range(300):  # toward each robot's target, now and then a random step (rarely on it): robots arrive, leave
        on = batch.cells == batch.goals
        wander = rng.random(on.shape) < np.where(on, 0.4 / n_robots, 0.3)
        actions = np.array([[int(rng.integers(0, 5)) if wander[i, k] else towards_own_goal(env, k)
                             for k in range(n_robots)] for i, env in enumerate(envs)])
        rewards, finishing, _, _, over = batch.step(actions)
        obs = batch.observations()
        left += int((on & (batch.cells != batch.goals) & ~over[:, None]).sum())
        for i, env in enumerate(envs):
            o, r, term, trunc, info = env.step({a: int(actions[i, k]) for k, a in enumerate(env.agents)})
            assert [env.table.cell_id(c) for c in env.robot_cells] == batch.cells[i].tolist()
            for k, agent in enumerate(env.possible_agents):
                assert r[agent] == rewards[i, k]
                assert np.array_equal(o[agent], obs[i, k])
                assert term[agent] == finishing[i, k] and trunc[agent] == (over[i] and not finishing[i, k])
                assert info[agent]["finished"] == (batch.cells[i, k] == batch.goals[i, k])
            assert (not env.agents) == over[i]
            if not env.agents:
                solved += all(term.values())
                truncated += all(trunc.values())
                env.reset()
        done = np.flatnonzero(over)
        if done.size:
            batch.reset_envs(done)
    assert truncated > 0 and left > 0  # races cut at the step limit, robots that left their targets
    assert solved > 0 or n_robots > 8  # and races that all robots finished (16 robots rarely stand still all at once)


def test_evaluate_counts_robots_on_their_targets_at_the_end_and_their_last_arrival():
    ev = evaluate(None, level="maze-8x8", n_robots=4, episodes=6, seed=0, goals="own", finished="stay")
    shortest = ev.episodes["shortest"]
    for e in shortest:  # an episode ends early only when every robot stands on its target
        assert (e.steps < ev.limit) == all(e.finish_steps)
    assert ev.metrics["shortest"]["all_reached_rate"] == sum(all(e.finish_steps) for e in shortest) / 6
    # a robot that left its target is not counted: random robots wander on and off theirs
    random_eps = ev.episodes["random"]
    assert all(f <= e.steps for e in random_eps for f in e.finish_steps)


def test_same_seed_same_staying_episode():
    runs = []
    for _ in range(2):
        env = staying("maze-8x8", n_robots=4, observe="local", max_cycles=40)
        obs, _ = env.reset(seed=7)
        g, cells = np.random.default_rng(1), []
        while env.agents:
            env.step({a: int(g.integers(0, 5)) for a in env.agents})
            cells.append(list(env.robot_cells))
        runs.append((env.goals, cells))
    assert runs[0] == runs[1]


# ---------------------------------------------------------------------------- the command line
def cli(capsys, *argv: str) -> tuple[int, str, str]:
    from tests.cli_run import run

    code = run(list(argv))
    got = capsys.readouterr()
    return code, got.out, got.err


def test_evaluate_finished_stay_runs_the_published_rule_and_matches_the_python_api(capsys):
    argv = ("evaluate", "shortest", "--level", "maze-8x8", "--robots", "4", "--goals", "own", "--collisions", "soft",
            "--episodes", "12", "--seed", "3")
    code, out, err = cli(capsys, *argv, "--finished", "stay")
    assert code == 0 and err == ""
    ev = evaluate(None, level="maze-8x8", n_robots=4, episodes=12, seed=3, collisions="soft", goals="own", finished="stay")
    shown = out.splitlines()[2].split()
    assert shown[:4] == ["shortest-path", "robots", "(the", "policy)"]
    assert float(shown[4]) == pytest.approx(ev.metrics["shortest"]["success_rate"], abs=5e-4)
    _, leaving, _ = cli(capsys, *argv)  # the default: robots leave at their targets, the others pass
    assert leaving.splitlines()[2] != out.splitlines()[2]


@pytest.mark.parametrize(("extra", "message"), [
    (("--finished", "stay"),
     "--finished: 'stay' keeps robots on their own targets (--goals own, no --lifelong), got --goals exit"),
    (("--finished", "stay", "--goals", "own", "--lifelong"),
     "--finished: 'stay' keeps robots on their own targets (--goals own, no --lifelong), got --lifelong"),
])
def test_evaluate_refuses_finished_stay_without_own_goals_in_one_line(extra, message, capsys):
    code, out, err = cli(capsys, "evaluate", "shortest", "--level", "maze-8x8", "--episodes", "2", *extra)
    assert code == 2 and out == "" and err.strip().splitlines() == [f"babyrobot-marl: error: {message}"]
