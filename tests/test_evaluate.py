"""``experiments.evaluate`` and ``babyrobot-marl evaluate`` (issue 27, item 4): a policy beside the
shortest-path and random robots on the same seeded episodes, POGEMA's metrics with 95% intervals."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from babyrobot_marl import policies
from babyrobot_marl.experiments import Episode, crowd_metrics, evaluate
from babyrobot_marl.levels.sources import EVAL_MAZE_SEEDS
from tests.cli_run import run

KEYS = [f"{m}{s}" for m in ("success_rate", "all_reached_rate", "sum_of_costs", "makespan") for s in ("", "_low", "_high")]


def inside_ranges(m: dict, n_robots: int, limit: int) -> None:
    assert sorted(m) == sorted(KEYS)
    for name, top in (("success_rate", 1), ("all_reached_rate", 1), ("sum_of_costs", n_robots * limit), ("makespan", limit)):
        low, v, high = m[f"{name}_low"], m[name], m[f"{name}_high"]
        assert all(math.isfinite(x) for x in (low, v, high)), (name, m)
        assert 0 <= low <= v <= high <= top, (name, low, v, high, top)


def test_metrics_by_hand():
    eps = [Episode(0, "a", 10, [3, 10]), Episode(1, "b", 20, [0, 5])]  # robot 0 of episode 1 did not finish
    m = crowd_metrics(eps, 2, 20)
    assert m["success_rate"] == 0.75 and m["all_reached_rate"] == 0.5
    assert m["sum_of_costs"] == (13 + 25) / 2 and m["makespan"] == (10 + 20) / 2
    inside_ranges(m, 2, 20)
    one = crowd_metrics(eps[:1], 2, 20)  # one episode: the mean's interval is the whole range
    assert (one["makespan_low"], one["makespan"], one["makespan_high"]) == (0.0, 10, 20)


class Shortest:
    """A crowd of shortest-path robots as a policy to evaluate: bound to each episode's env."""

    def for_env(self, env):
        return policies.make("shortest", env.table)

    def __call__(self, obs):
        raise AssertionError("bound first")


def test_shortest_robots_all_reach_random_ones_are_bounded_and_every_crowd_plays_the_same_episodes():
    ev = evaluate(Shortest(), level="maze:5..8", n_robots=4, episodes=12, seed=3)
    assert list(ev.metrics) == ["policy", "shortest", "random"]
    s, r = ev.metrics["shortest"], ev.metrics["random"]
    assert s["success_rate"] == 1.0 and s["all_reached_rate"] == 1.0 and s["success_rate_low"] > 0.9
    assert ev.metrics["policy"] == s  # the same robots on the same episodes: the same figures
    assert r["success_rate"] < 1 and r["makespan"] <= ev.limit and r["makespan"] > s["makespan"]
    assert ev.limit == 4 * 8 * 8
    for m in ev.metrics.values():
        inside_ranges(m, 4, ev.limit)
    levels = [[e.level for e in eps] for eps in ev.episodes.values()]
    assert levels[0] == levels[1] == levels[2] and len(set(levels[0])) >= 8
    assert all(int(name.rsplit("-s", 1)[1]) in EVAL_MAZE_SEEDS for name in levels[0])  # never trained on
    again = evaluate(None, level="maze:5..8", n_robots=4, episodes=12, seed=3)
    assert again.metrics == {k: ev.metrics[k] for k in ("shortest", "random")}  # same seed, same figures


def test_a_plain_callable_reads_its_own_observation_form():
    seen = []

    def stay(obs):
        seen.append(np.asarray(obs).shape)
        return 0

    ev = evaluate(stay, level="race-corridor", n_robots=2, episodes=3, seed=0, policy_env={"observe": "local", "hint": True},
                  max_cycles=20)
    assert ev.metrics["policy"]["success_rate"] == 0.0 and ev.metrics["policy"]["makespan"] == 20
    assert set(seen) == {(2 + 6 * 25 + 5,)}  # the local window and the hint


def cli(capsys, *argv):
    code = run(["evaluate", *argv])
    got = capsys.readouterr()
    return code, got.out, got.err


def test_the_command_prints_a_table_and_the_json_last_line(capsys, tmp_path):
    png = tmp_path / "ev.png"
    code, out, err = cli(capsys, "shortest", "--level", "maze:6..8", "--robots", "3", "--episodes", "6", "--seed", "1",
                         "--collisions", "bounce", "--plot", str(png))
    assert code == 0, err
    lines = out.strip().splitlines()
    assert lines[0].startswith("6 episodes on maze:6..8, 3 robots, collisions bounce")
    last = json.loads(lines[-1])
    assert list(last) == ["policy", "shortest", "random"] and last["policy"]["success_rate"] == 1.0
    for m in last.values():
        inside_ranges(m, 3, 4 * 8 * 8)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(("argv", "flag"), [
    (["shortest", "--episodes", "0"], "--episodes"),
    (["shortest", "--robots", "0"], "--robots"),
    (["shortest", "--level", "maze:9..2"], "--level"),
    (["shortest", "--collisions", "through"], "--collisions"),
    (["no-such-policy.pt"], "POLICY"),
    (["shortest", "--level", "maze-4x4", "--robots", "40"], "--robots"),
    (["shortest", "--level", "no-such-level"], "level"),
    (["shortest", "--plot", "/no/such/folder/x.png"], "--plot"),
    (["shortest", "--seed", "-1"], "--seed"),
])
def test_bad_arguments_are_one_line_naming_the_flag(capsys, argv, flag):
    code, out, err = cli(capsys, *argv)
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert flag in err


torch = pytest.importorskip("torch", reason="the train extra is not installed")


def test_a_saved_policy_is_evaluated_and_refused_by_name_on_levels_it_cannot_read(capsys, tmp_path):
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "p.pt"
    train_ppo("maze-8x8", 2, 1024, seed=0, config=PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)).save(path)
    code, out, err = cli(capsys, str(path), "--level", "maze-8x8", "--robots", "2", "--episodes", "4")
    assert code == 0, err
    last = json.loads(out.strip().splitlines()[-1])
    inside_ranges(last["policy"], 2, 4 * 8 * 8)
    assert last["shortest"]["success_rate"] == 1.0
    code, out, err = cli(capsys, str(path), "--level", "maze:8..16", "--robots", "2")  # trained on one 8x8 level
    assert code == 2 and out == "" and err.count("\n") == 1 and "POLICY: trained on a 8x8 level" in err


def test_a_saved_policy_samples_by_default_seeded_by_seed_and_takes_its_argmax_with_greedy(capsys, tmp_path):
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "p.pt"  # barely trained: its distribution is wide, so sampling and argmax act apart
    train_ppo("maze-8x8", 2, 512, seed=0, config=PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)).save(path)

    def policy_metrics(*flags: str) -> dict:
        code, out, err = cli(capsys, str(path), "--level", "maze-8x8", "--robots", "2", "--episodes", "3", *flags)
        assert code == 0, err
        return json.loads(out.strip().splitlines()[-1])["policy"]

    sampled = policy_metrics("--seed", "5")
    assert policy_metrics("--seed", "5") == sampled  # same seed, same sampled actions
    greedy = policy_metrics("--seed", "5", "--greedy")
    assert policy_metrics("--seed", "5", "--greedy") == greedy
    assert greedy != sampled


def test_a_policy_file_of_format_1_or_2_is_evaluated_as_play_runs_it(capsys, tmp_path):
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    config = PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)
    for robots, version in ((1, 1), (2, 2)):
        path = tmp_path / f"p{robots}.pt"
        train_ppo("maze-8x8", robots, 512, seed=0, config=config).save(path)
        data = torch.load(path, weights_only=True)
        del data["observation"]  # files of format 1 and 2 had none: they read the global rows
        torch.save({**data, "version": version}, path)
        assert run(["play", "--level", "maze-8x8", "--policy", str(path), "--seed", "0", "--no-delay"]) == 0
        capsys.readouterr()
        code, out, err = cli(capsys, str(path), "--level", "maze-8x8", "--robots", str(robots), "--episodes", "2")
        assert code == 0, err
        inside_ranges(json.loads(out.strip().splitlines()[-1])["policy"], robots, 4 * 8 * 8)


def test_a_maze_family_by_size_is_evaluated_on_unseen_mazes_and_named_as_given(capsys):
    ev = evaluate(None, level="maze-6x6-*", n_robots=2, episodes=12, seed=0)
    names = [e.level for e in ev.episodes["shortest"]]
    assert ev.level == "maze-6x6-*" and len(set(names)) >= 8
    assert all(int(name.rsplit("-s", 1)[1]) in EVAL_MAZE_SEEDS for name in names)  # never a training seed
    code, out, err = cli(capsys, "shortest", "--level", "maze-6x6-*", "--robots", "2", "--episodes", "3")
    assert code == 0, err
    assert out.startswith("3 episodes on maze-6x6-*, 2 robots")


def test_the_table_names_each_crowd_and_shows_a_baseline_policy_once(capsys, tmp_path):
    code, out, err = cli(capsys, "shortest", "--level", "maze:6..8", "--robots", "2", "--episodes", "4")
    assert code == 0, err
    rows = [line.split("  ")[0] for line in out.splitlines()[2:-1]]
    assert rows == ["shortest-path robots (the policy)", "random robots"]
    last = json.loads(out.strip().splitlines()[-1])
    assert list(last) == ["policy", "shortest", "random"] and last["policy"] == last["shortest"]


def test_the_json_rounds_to_four_significant_digits(capsys):
    code, out, err = cli(capsys, "random", "--level", "maze:6..8", "--robots", "3", "--episodes", "7", "--seed", "2")
    assert code == 0, err
    figures = [v for m in json.loads(out.strip().splitlines()[-1]).values() for v in m.values()]
    assert all(float(f"{v:.4g}") == v for v in figures)
    assert any(len(repr(v).replace(".", "").strip("0")) > 2 for v in figures)  # not all round numbers anyway


def test_a_saved_policy_row_is_named_by_its_file(capsys, tmp_path):
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "p.pt"
    train_ppo("maze-8x8", 2, 512, seed=0, config=PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)).save(path)
    code, out, err = cli(capsys, str(path), "--level", "maze-8x8", "--robots", "2", "--episodes", "2")
    assert code == 0, err
    rows = [line.split("  ")[0] for line in out.splitlines()[2:5]]  # then the training settings line, then the JSON
    assert rows == [f"policy robots ({path})", "shortest-path robots", "random robots"]
    assert out.splitlines()[5].startswith(f"{path}: trained 512 timesteps")
