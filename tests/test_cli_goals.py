"""``race``, ``play`` and ``evaluate`` with ``--goals own``, ``--lifelong`` and ``--collisions soft``: what they show,
the errors of every combination they refuse (one line naming the flag, before any episode), and that the fix each
error recommends runs."""

from __future__ import annotations

import re
import shlex

import pytest

from babyrobot_marl.envs.race import RaceEnv
from babyrobot_marl.experiments.races import OwnGoalRobot
from tests.cli_run import run

GRID = "....#\n....."  # a grid map: 9 free cells, no exit


def cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = run(list(argv))
    got = capsys.readouterr()
    return code, got.out, got.err


def played(level: str, n: int, seed: int, steps: int | None = None, **kw) -> RaceEnv:
    """The race the command plays: shortest-path robots to their own targets, from ``start="fill"``."""
    env = RaceEnv(level=level, n_robots=n, goals="own", start="fill", max_cycles=steps, **kw)
    obs, _ = env.reset(seed=seed)
    robots = [OwnGoalRobot(env, k) for k in range(n)]
    while env.agents:
        obs, *_ = env.step({a: robots[env.possible_agents.index(a)](obs[a]) for a in env.agents})
    return env


def table_rows(out: str, first: str) -> list[list[str]]:
    """The results table's rows (split on runs of spaces) after its header line starting with ``first``."""
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(first))
    rows = []
    for line in lines[start + 1:]:
        if not line.strip():
            break
        rows.append(re.split(r"\s{2,}", line.strip()))
    return rows


# ------------------------------------------------------------------------ race
def test_race_with_own_goals_shows_each_robots_target_and_whether_it_reached_it(capsys):
    code, out, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "3", "--goals", "own", "--collisions", "soft",
                         "--seed", "1")
    assert code == 0, err
    env = RaceEnv(level="maze-8x8", n_robots=3, goals="own", start="fill", collisions="soft")
    env.reset(seed=1)
    first = env.goals  # the targets of the first frame, drawn from the seed
    assert f"targets: A {first['robot_0']}  B {first['robot_1']}  C {first['robot_2']}" in out
    assert "collisions soft, own goals, seed 1" in out
    assert "A reached its target 2nd" in out  # the footer's key
    rows = table_rows(out, "rank  robot")
    done = played("maze-8x8", 3, 1, collisions="soft")
    assert len(rows) == 3
    for rank, robot, policy, target, reached, *_ in rows:
        k = int(robot.split("_")[1])
        assert target == str(first[f"robot_{k}"]) and policy == "shortest"
        assert reached == ("yes" if done.goals_reached[k] else "no") and (rank != "-") == (reached == "yes")


def test_race_lifelong_counts_each_robots_targets_and_the_throughput(capsys):
    code, out, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "3", "--goals", "own", "--lifelong",
                         "--max-cycles", "60", "--seed", "2")
    assert code == 0, err
    done = played("maze-8x8", 3, 2, 60, lifelong=True)
    rows = table_rows(out, "robot  ")
    assert [int(r[2]) for r in rows] == done.goals_reached and sum(done.goals_reached) > 0
    total = sum(done.goals_reached)
    assert f"throughput: {total / 60:.3f} targets reached per step ({total} targets in 60 steps)" in out
    assert "a new one once it is reached" in out


def test_race_runs_own_goal_races_and_lifelong_throughput_with_races(capsys):
    code, out, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "2", "--goals", "own", "--races", "3",
                         "--seed", "0")
    assert code == 0, err
    assert "finish rate" in out and "all finished" in out
    code, out, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "2", "--goals", "own", "--lifelong",
                         "--races", "3", "--seed", "0", "--max-cycles", "40")
    assert code == 0, err
    assert "targets reached" in out and re.search(r"^throughput: 0\.\d+", out, re.M), out


def test_race_saves_a_lifelong_run_as_a_gif_one_picture_per_step(capsys, tmp_path):
    iio = pytest.importorskip("imageio.v3", reason="the video extra is not installed")
    path = tmp_path / "lifelong.gif"
    code, out, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "3", "--goals", "own", "--lifelong",
                         "--collisions", "soft", "--max-cycles", "12", "--seed", "0", "--gif", str(path))
    assert code == 0, err
    assert f"GIF of the race (13 pictures): {path}" in out
    frames = iio.imread(path, index=None)
    assert frames.shape[0] == 13 and frames.shape[-1] == 3
    assert any((frames[k] != frames[k + 1]).any() for k in range(12))  # the robots move


# ------------------------------------------------------------------------ play
def test_play_with_own_goals_drives_the_robot_to_its_own_target(capsys):
    code, out, err = cli(capsys, "play", "--level", "maze-8x8", "--goals", "own", "--seed", "3")
    assert code == 0, err
    env = played("maze-8x8", 1, 3)
    target = RaceEnv(level="maze-8x8", n_robots=1, goals="own", start="fill")
    target.reset(seed=3)
    steps = env.elapsed_steps
    assert out.rstrip().endswith(f"seed 3: {steps} steps, return {env.returns[0]!r}, reached its target "
                                 f"{target.goals['robot_0']}")
    assert env.robot_cells[0] == target.goals["robot_0"]  # the shortest path ends on it


def test_play_with_own_goals_among_other_robots_under_soft_collisions(capsys):
    code, out, err = cli(capsys, "play", "--level", "maze-8x8", "--goals", "own", "--robots", "3", "--collisions", "soft",
                         "--seed", "3", "--policy", "random", "--max-steps", "30")
    assert code == 0, err
    rows = table_rows(out, "rank  robot")
    assert sorted(r[2] for r in rows) == ["random", "shortest", "shortest"]
    assert re.search(r"policy random, seed 3: 30 steps, return -?\d+\.\d, did not reach its target \(\d, \d\) "
                     r"\(truncated after 30 steps\)$|reached its target", out.rstrip())


def test_play_lifelong_reports_the_targets_reached(capsys):
    code, out, err = cli(capsys, "play", "--level", "maze-8x8", "--goals", "own", "--lifelong", "--seed", "3",
                         "--max-steps", "80")
    assert code == 0, err
    k = played("maze-8x8", 1, 3, 80, lifelong=True).goals_reached[0]
    assert k >= 1 and out.rstrip().endswith(f"reached {k} target(s) in 80 steps (throughput {k / 80:.3f} per step)")


# ------------------------------------------------------------------------ refused combinations
REFUSED = {
    "race lifelong without own goals": (["race", "--lifelong"], "--lifelong: new targets replace reached ones, so it "
                                        "needs --goals own"),
    "play lifelong without own goals": (["play", "--lifelong"], "--lifelong: "),
    "evaluate lifelong without own goals": (["evaluate", "shortest", "--lifelong"], "--lifelong: "),
    "race to exits on a grid map": (["race", "--level", GRID, "--robots", "2"], "--level: has no exit; use --goals own"),
    "play to the exit on a grid map": (["play", "--level", GRID], "--level: has no exit; use --goals own"),
    "evaluate exits on a grid map": (["evaluate", "shortest", "--level", GRID], "--level: has no exit; use --goals own"),
    "race: more robots than free cells": (["race", "--level", GRID, "--goals", "own", "--robots", "10"],
                                          "--robots: 10 robots do not fit"),
    "play: more robots than free cells": (["play", "--level", GRID, "--goals", "own", "--robots", "10"],
                                          "--robots: 10 robots do not fit"),
    "evaluate: more robots than free cells": (["evaluate", "shortest", "--level", GRID, "--goals", "own", "--robots", "10"],
                                              "--robots: 10 robots do not fit on this --level, which has 9 free cells"),
    "play: other robots without own goals": (["play", "--robots", "3"], "--robots: play drives one robot to the exit"),
    "play: collisions for a lone robot": (["play", "--collisions", "soft", "--goals", "own"],
                                          "--collisions: a lone robot (--robots 1) meets nobody"),
    "play keys without a terminal": (["play", "--goals", "own", "--policy", "keys"],
                                     "--policy keys: the keyboard game needs an interactive terminal"),
    "a GIF of many races": (["race", "--gif", "race.gif", "--races", "3"], "--gif: a GIF shows one race; drop --races"),
    "a GIF of a race you drive": (["race", "--gif", "race.gif", "--human", "0"], "--gif: not for a race you drive"),
}


@pytest.mark.parametrize(("argv", "message"), REFUSED.values(), ids=REFUSED.keys())
def test_a_refused_combination_is_one_line_naming_the_flag(argv, message, capsys):
    code, out, err = cli(capsys, *argv)
    assert code == 2 and "Traceback" not in err and err.count("\n") == 1, err
    assert err.startswith("babyrobot-marl: error: ") and message in err, err
    assert out == ""  # before any episode: no frame, no table
    assert not re.search(r"\b(goals|lifelong|n_robots)=", err)  # the flags, not Python's arguments


# ------------------------------------------------------------------------ each error's fix runs
def recommended(err: str) -> list[str] | None:
    """The command an error line quotes ('babyrobot-marl ...'), as arguments, or None."""
    m = re.search(r"babyrobot-marl ((?:race|play|evaluate|levels|solve)[^)';]*)", err.partition("error: ")[2])
    return shlex.split(m[1]) if m else None


FIXES = {  # an error, then the command its advice makes of it
    "add --goals own (lifelong)": (["race", "--lifelong", "--max-cycles", "20"], "needs --goals own", ["--goals", "own"], []),
    "add --goals own (grid map)": (["race", "--level", GRID, "--robots", "2"], "use --goals own", ["--goals", "own"], []),
    "pass --start fill": (["race", "--level", "race-2", "--robots", "3", "--start", "level"], "pass --start fill",
                          ["--start", "fill"], ["--start", "level"]),
    "drop --collisions": (["play", "--collisions", "soft", "--goals", "own"], "drop --collisions", [], ["--collisions", "soft"]),
    "--robots 2 or more": (["play", "--collisions", "soft", "--goals", "own"], "--robots 2 or more", ["--robots", "2"], []),
    "give --policy shortest": (["play", "--goals", "own", "--policy", "keys"], "give --policy shortest", [],
                               ["--policy", "keys"]),
    "leave out --human": (["race", "--human", "0"], "leave out --human", [], ["--human", "0"]),
    "drop --races (for --gif)": (["race", "--gif", "{tmp}/r.gif", "--races", "3"], "drop --races", [], ["--races", "3"]),
    "drop --human (for --races)": (["race", "--human", "0", "--races", "3"], "drop --races (N races without frames) or "
                                   "--human", [], ["--human", "0"]),
}


def _without(argv: list[str], drop: list[str]) -> list[str]:
    if not drop:
        return list(argv)
    i = next(i for i in range(len(argv)) if argv[i:i + len(drop)] == drop)
    return argv[:i] + argv[i + len(drop):]


@pytest.mark.parametrize(("argv", "advice", "add", "drop"), FIXES.values(), ids=FIXES.keys())
def test_the_fix_an_error_recommends_runs(argv, advice, add, drop, capsys, tmp_path):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    code, _, err = cli(capsys, *argv)
    assert code == 2 and advice in err, err
    fixed = _without(argv, drop) + add + ["--seed", "0"] * ("--seed" not in argv)
    code, out, err = cli(capsys, *fixed)
    assert code == 0, (fixed, err)


def test_a_quoted_command_in_an_error_runs(capsys):
    code, _, err = cli(capsys, "play", "--robots", "3")  # "... (or watch a race: babyrobot-marl race --robots 3)"
    command = recommended(err)
    assert code == 2 and command == ["race", "--robots", "3"], err
    code, out, err = cli(capsys, *command, "--seed", "0")
    assert code == 0 and "race on race-4, 3 robots" in out, err


# ------------------------------------------------------------------------ saved policies and the task they learnt
torch = pytest.importorskip("torch", reason="the train extra is not installed")


@pytest.fixture(scope="module")
def exit_policy(tmp_path_factory):
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path_factory.mktemp("policy") / "exit.pt"
    train_ppo("maze-8x8", 2, 512, seed=0, config=PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)).save(path)
    return str(path)


@pytest.mark.parametrize("argv", [
    ["race", "--level", "maze-8x8", "--robots", "2", "--policies", "{p}"],
    ["play", "--level", "maze-8x8", "--policy", "{p}"],
    ["evaluate", "{p}", "--level", "maze-8x8", "--robots", "2", "--episodes", "2"],
], ids=["race", "play", "evaluate"])
def test_a_policy_trained_for_the_exit_race_is_refused_for_own_goals_saying_so(argv, exit_policy, capsys):
    argv = [a.replace("{p}", exit_policy) for a in argv]
    code, out, err = cli(capsys, *argv, "--goals", "own")
    flag = {"race": "--policies", "play": "--policy", "evaluate": "POLICY"}[argv[0]]
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert f"{flag}: {exit_policy} was trained for the race to the exits (--goals exit), not for own targets" in err
    code, out, err = cli(capsys, *argv, "--goals", "exit", "--seed", "0")  # the fix it recommends: pass --goals exit
    assert code == 0, err


def test_a_policy_trained_for_own_goals_is_refused_for_the_exit_race(exit_policy, capsys, monkeypatch):
    from babyrobot_marl.cli import checks

    monkeypatch.setattr(checks, "trained_goals", lambda path: "own")  # a file that records own goals
    code, out, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "2", "--policies", exit_policy)
    assert code == 2 and "was trained for own targets (--goals own), not for the race to the exits" in err
    assert "pass --goals own" in err


def test_the_level_a_saved_policy_asks_for_runs(exit_policy, capsys):
    code, _, err = cli(capsys, "race", "--level", "maze-16x16", "--robots", "2", "--policies", exit_policy)
    assert code == 2 and "(pass --level maze-8x8)" in err, err
    code, _, err = cli(capsys, "race", "--level", "maze-8x8", "--robots", "2", "--policies", exit_policy, "--seed", "0")
    assert code == 0, err


TRAIN = ["train", "--level", "maze-8x8", "--robots", "2", "--steps", "10", "--episodes", "2", "--no-progress"]


def test_the_race_a_local_policy_is_watched_with_runs(capsys, tmp_path):
    saved = str(tmp_path / "local.pt")
    argv = [*TRAIN, "--observe", "local", "--save", saved]
    code, _, err = cli(capsys, *argv, "--gif", str(tmp_path / "x.gif"))
    command = recommended(err)
    assert code == 2 and "train without it" in err and command and command[-2:] == ["--policies", saved], err
    code, _, err = cli(capsys, *argv)  # without --gif, as the error says
    assert code == 0, err
    code, out, err = cli(capsys, *command, "--seed", "0")
    assert code == 0 and "race on maze-8x8, 2 robots" in out, err


@pytest.mark.parametrize(("argv", "advice", "fixed"), [
    (["train", "--level", "maze:8..10", "--robots", "2", "--steps", "10", "--episodes", "2", "--no-progress"],
     "pass --observe local", ["--observe", "local"]),
    (["train", "--level", "maze-8x8", "--steps", "10", "--episodes", "2", "--no-progress", "--collisions", "soft"],
     "drop --collisions or race --robots 2 or more", ["--robots", "2"]),
], ids=["a level family", "collisions of a lone robot"])
def test_the_fix_a_train_error_recommends_runs(argv, advice, fixed, capsys):
    code, _, err = cli(capsys, *argv)
    assert code == 2 and advice in err, err
    code, _, err = cli(capsys, *argv, *fixed)
    assert code == 0, err
