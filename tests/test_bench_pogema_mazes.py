"""POGEMA's maze benchmark (no POGEMA needed): the shipped mazes, starts and goals, the shortest-path
robots' episodes under the soft rule, the table beside the published figures, the flags' errors."""

from __future__ import annotations

import collections
import importlib
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"


@pytest.fixture
def b(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    sys.modules.pop("bench_pogema_mazes", None)
    return importlib.import_module("bench_pogema_mazes")


def distances(rows: list[str], start: tuple[int, int]) -> dict[tuple[int, int], int]:
    """Moves from ``start`` to every free cell it reaches (a breadth-first search of its own)."""
    seen, todo = {start: 0}, collections.deque([start])
    while todo:
        x, y = todo.popleft()
        for nx, ny in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
            if 0 <= ny < len(rows) and 0 <= nx < len(rows[0]) and rows[ny][nx] == "." and (nx, ny) not in seen:
                seen[nx, ny] = seen[x, y] + 1
                todo.append((nx, ny))
    return seen


def test_the_shipped_data_holds_the_128_validation_mazes_and_their_scenarios(b):
    mazes = b.load_mazes()
    assert [m["name"] for m in mazes] == [f"validation-mazes-seed-{s:03d}" for s in range(128)]
    # the benchmark's first maze (02-mazes/maps.yaml), its first and last rows
    first = mazes[0]["grid"].split("\n")
    assert (first[0], first[-1], len(first)) == (".............#.......", "." * 21, 21)
    for m in mazes:
        rows = m["grid"].split("\n")
        assert 17 <= len(rows) <= 21 and {len(r) for r in rows} <= set(range(17, 22))
        region = {}  # free cell -> the first cell of its open region
        for y, row in enumerate(rows):
            for x, ch in enumerate(row):
                if ch == "." and (x, y) not in region:
                    region.update(dict.fromkeys(distances(rows, (x, y)), (x, y)))
        for n in (8, 16, 24, 32, 48, 64):
            s = m["scenarios"][str(n)]
            starts, goals = b.cells(s["starts"]), b.cells(s["goals"])
            assert len(starts) == len(set(starts)) == n and len(goals) == len(set(goals)) == n
            for start, goal in zip(starts, goals):
                assert start in region and region.get(goal) == region[start]  # free, goal reachable


def test_a_lone_robot_finishes_after_its_shortest_path(b):
    grid = ".....\n.###.\n....."
    episode = b.race(grid, [(0, 2)], [(4, 0)])
    assert episode.finish_steps == [6] and episode.steps == 6  # around the wall: 6 moves


def test_robots_meeting_head_on_in_a_corridor_stop_each_other_under_the_soft_rule(b):
    episode = b.race("#####\n.....\n#####", [(0, 1), (4, 1)], [(4, 1), (0, 1)])
    assert episode.finish_steps == [0, 0] and episode.steps == b.STEPS  # swaps revert: nobody passes


def test_with_finished_remove_a_robot_leaves_at_its_goal_and_frees_the_cell(b):
    # robot 0 reaches (2, 0) first; robot 1 then passes over it to (4, 0)
    episode = b.race(".....", [(1, 0), (0, 0)], [(2, 0), (4, 0)], "remove")
    assert episode.finish_steps == [1, 4]


def test_by_default_a_robot_stays_on_its_goal_and_blocks_as_in_the_published_runs(b):
    episode = b.race(".....", [(1, 0), (0, 0)], [(2, 0), (4, 0)])
    assert episode.finish_steps == [1, 0] and episode.steps == b.STEPS  # robot 1 never gets past robot 0
    # one that leaves its goal is counted from its last arrival
    finish = [3, 0]
    b.arrivals(finish, {"robot_0": {"finished": False}, "robot_1": {"finished": True}}, {"robot_0": 0, "robot_1": 1}, 9)
    assert finish == [0, 9]


def test_the_path_table_stays_on_the_goal_and_moves_toward_it(b):
    table = b.path_actions("...\n.#.\n...", (2, 2))
    assert table[2, 2] == 0  # STAY on the goal
    assert table[0, 2] == 3 and table[2, 0] == 2  # SOUTH down the east side, EAST along the south side


def test_the_table_shows_our_figures_with_intervals_beside_the_published_ones(b):
    mazes = b.load_mazes()[:3]
    results = b.run(mazes, (8, 32))
    for n, m in results.items():
        assert m["all_reached_rate_low"] <= m["all_reached_rate"] <= m["all_reached_rate_high"]
        assert m["all_reached_rate"] <= m["success_rate"] and m["makespan"] <= b.STEPS
        assert 0 <= m["sum_of_costs"] <= n * b.STEPS
    text = b.table(results, 3)
    assert b.SOURCE in text and "LaCAM                       1.00 / 0.91" in text
    assert f"{results[32]['all_reached_rate']:.2f} [{results[32]['all_reached_rate_low']:.2f}," in text
    assert "shortest-path robots (ours)" in text.splitlines()[-1]


def test_pibts_crowd_passes_where_shortest_path_robots_stop_each_other(b):
    # two robots trade sides of a ring: both shortest paths go round the top and meet there; PIBT sends one
    # the other way
    grid = "...\n.#.\n..."
    assert b.race(grid, [(0, 1), (2, 1)], [(2, 1), (0, 1)]).finish_steps == [0, 0]
    episode = b.race(grid, [(0, 1), (2, 1)], [(2, 1), (0, 1)], planner="pibt")
    assert all(episode.finish_steps) and episode.steps < b.STEPS


def test_pibts_row_is_printed_beside_ours(b, capsys):
    assert b.main(["--quick", "--pibt"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert any(line.startswith("PIBT (centralised planner)") and "     8  " in line for line in lines)


def test_lacams_row_is_printed_beside_ours_and_in_the_summary(b, capsys):
    assert b.main(["--mazes", "2", "--robots", "32", "--lacam", "--lacam-nodes", "2000"]) == 0
    lines = capsys.readouterr().out.splitlines()
    row = next(line for line in lines if line.startswith("LaCAM (centralised planner)"))
    assert "    32  1.00 [" in row  # 32 robots on 2 mazes: both episodes solved
    assert any(line.strip().startswith("LaCAM (ours, centralised)   1.00 [") for line in lines)


def test_lacam_plans_the_episode_and_the_env_carries_it_out(b):
    # the ring of the PIBT test above, one more robot: LaCAM's plan, stepped under the soft rule
    grid = "...\n.#.\n..."
    episode = b.race(grid, [(0, 1), (2, 1), (1, 0)], [(2, 1), (0, 1), (1, 2)], planner="lacam")
    assert all(episode.finish_steps) and episode.steps < b.STEPS


def test_quick_mode_needs_no_pogema(b, capsys):
    assert b.main(["--quick", "--json"]) == 0
    out = capsys.readouterr().out
    assert "on 4 of POGEMA's validation mazes" in out and out.strip().splitlines()[-1].startswith('{"8": {')


@pytest.mark.parametrize(("argv", "flag"), [(["--robots", "7"], "--robots"), (["--robots", "8,x"], "--robots"),
                                             (["--mazes", "0"], "--mazes"), (["--mazes", "129"], "--mazes"),
                                             (["--regenerate", "--pogema-python", "/no/such/python"], "--pogema-python"),
                                             (["--in-pogema", "--pogema-python", "/no/such/python"], "--pogema-python"),
                                             (["--pibt", "--finished", "remove"], "--pibt"),
                                             (["--shield"], "--shield"),
                                             (["--lacam", "--finished", "remove"], "--lacam"),
                                             (["--lacam", "--lacam-nodes", "0"], "--lacam-nodes"),
                                             (["--lacam", "--lacam-nodes", "x"], "--lacam-nodes"),
                                             (["--lacam-nodes", "100"], "--lacam-nodes")])
def test_bad_flags_are_one_line_naming_the_flag(b, capsys, argv, flag):
    with pytest.raises(SystemExit) as stop:
        b.main(argv)
    err = capsys.readouterr().err
    assert stop.value.code == 2 and flag in err.splitlines()[-1] and "Traceback" not in err


def test_a_policy_that_is_no_policy_file_is_refused_by_flag(b, capsys, tmp_path):
    pytest.importorskip("torch", reason="needs the train extra")
    text = tmp_path / "notes.txt"
    text.write_text("not a policy")
    for path in (str(tmp_path / "missing.pt"), str(text)):
        with pytest.raises(SystemExit) as stop:
            b.main(["--policy", path, "--quick"])
        err = capsys.readouterr().err
        assert stop.value.code == 2 and err.count("\n") == 1 and err.startswith("--policy: ") and path in err


def test_a_policy_trained_for_the_exits_is_refused_before_any_episode(b, capsys, tmp_path, monkeypatch):
    pytest.importorskip("torch", reason="needs the train extra")
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "p.pt"
    train_ppo("maze-8x8", 2, 512, seed=0, config=PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)).save(path)
    monkeypatch.setattr(b, "run", lambda *a: pytest.fail("episodes ran"))
    with pytest.raises(SystemExit) as stop:
        b.main(["--policy", str(path)])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1 and "race to the exits" in err and "own goals" in err


def test_a_policy_of_own_goals_gets_its_row_beside_the_shortest_path_robots(b, capsys, tmp_path):
    """A policy trained with own goals on the package's mazes runs on POGEMA's mazes (the benchmark's starts and
    goals): its row in the table and the JSON, and its row shielded by PIBT (--shield); the same figures for the
    same --seed."""
    pytest.importorskip("torch", reason="needs the train extra")
    import json

    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "own.pt"
    config = PPOConfig(n_envs=16, n_steps=16, batch_size=256, eval_every=0, hint=True, atlas_size=2)
    train_ppo("maze:8..10", 4, 2048, seed=0, config=config, env_kwargs={"goals": "own", "collisions": "soft"}).save(path)
    runs = []
    for _ in range(2):
        assert b.main(["--policy", str(path), "--mazes", "2", "--robots", "8,32", "--json", "--shield"]) == 0
        runs.append(capsys.readouterr().out)
    assert runs[0] == runs[1]
    figures = json.loads(runs[0].splitlines()[-1])
    assert set(figures) == {"shortest", "policy"} and set(figures["policy"]) == {"8", "32"}
    assert 0 <= figures["policy"]["8"]["success_rate"] <= 1
    assert "learnt policy (sampled)" in runs[0] and "learnt policy (ours)" in runs[0]
    assert "shielded by PIBT (sampled)" in runs[0] and "learnt + PIBT shield (ours)" in runs[0]


@pytest.mark.parametrize("memory", [{"recurrent": True}, {"trail": True}, {"recurrent": True, "trail": True},
                                    {"imitate": "pibt", "hint": True, "near_radius": 2}],
                         ids=["recurrent", "trail", "recurrent-trail", "imitation-in-turns"])
def test_a_remembering_policy_acts_as_each_robot_bound_to_the_env_would(b, tmp_path, monkeypatch, memory):
    """A crowd that remembers (a GRU's state per robot, its trail, and its last action), or imitates PIBT deciding
    in turns, steps the benchmark's episode as the package's own policy bound to each robot does: the same
    actions, step by step and robot by robot."""
    pytest.importorskip("torch", reason="needs the train extra")
    import numpy as np
    import torch

    from babyrobot_marl import race_v0
    from babyrobot_marl.training.policy import load_policy
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "rec.pt"
    finished = "stay" if "imitate" in memory else "remove"
    config = PPOConfig(n_envs=16, n_steps=16, batch_size=256, eval_every=0, atlas_size=2, memory=True, **memory)
    env_kwargs = {"goals": "own", "collisions": "soft", **({"finished": "stay", "max_cycles": 16} if "imitate" in memory else {})}
    train_ppo("maze:8..10", 4, 4096, seed=0, config=config, env_kwargs=env_kwargs).save(path)
    policy, maze = load_policy(path), b.load_mazes()[0]
    assert policy.form.turns == ("imitate" in memory)  # an imitation crowd decides in turns
    torch.manual_seed(0)
    with torch.no_grad():  # weights drawn at random: a policy this briefly trained mostly stays put
        for weight in policy.net.parameters():
            weight.normal_(0.0, 1.0)
    starts, goals = (b.cells(maze["scenarios"]["8"][k]) for k in ("starts", "goals"))
    taken: list[list[dict]] = [[], []]
    real = race_v0.parallel_env

    def recorded(**kwargs):
        env = real(**kwargs)
        step = env.step
        env.step = lambda actions: taken[0].append(dict(actions)) or step(actions)
        return env

    monkeypatch.setattr(race_v0, "parallel_env", recorded)
    b.policy_race(policy, maze["grid"], starts, goals, np.random.default_rng(0), greedy=True, finished=finished)
    monkeypatch.setattr(race_v0, "parallel_env", real)

    env = race_v0.parallel_env(level=b.level_of(maze["grid"]), n_robots=8, goals="own", collisions="soft",
                               observe="local", view_radius=policy.form.radius, hint=policy.form.hint, start="random",
                               max_cycles=b.STEPS, finished=finished)
    obs, _ = env.reset(seed=0, options={"starts": starts, "goals": goals})
    robots = {a: policy.for_env(env) for a in env.possible_agents}
    while env.agents:
        taken[1].append({a: robots[a](obs[a]) for a in env.agents})
        obs = env.step(taken[1][-1])[0]
    assert len(taken[1]) > 10 and taken[0] == taken[1]
