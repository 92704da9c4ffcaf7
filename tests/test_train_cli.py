"""``babyrobot-marl train`` with the fast trainer, and saved policies replayed by ``play`` and ``race``."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("torch", reason="needs the train extra")  # CI installs it (test extra)

from babyrobot_marl.training.policy import load_policy  # noqa: E402
from babyrobot_marl.training.ppo import near_offsets  # noqa: E402
from tests.cli_run import run  # noqa: E402

SMALL = ["--n-envs", "16", "--n-steps", "16", "--batch-size", "128", "--eval-every", "512"]


def last_json(out: str) -> dict:
    return json.loads(out.strip().splitlines()[-1])


def test_one_robot_prints_evaluation_lines_and_ends_with_the_json_figures(tmp_path, capsys):
    policy, curve = tmp_path / "m", tmp_path / "curve.png"
    argv = ["train", "--level", "default", "--steps", "4096", "--save", str(policy), "--curve", str(curve), *SMALL]
    assert run(argv) == 0
    out = capsys.readouterr().out
    figures = last_json(out)
    assert set(figures) >= {"env_steps_per_second", "timesteps", "seconds", "optimal_return", "final_return",
                            "timesteps_to_95", "seconds_to_95"}
    assert figures["backend"] == "fast" and figures["optimal_return"] == -3 and figures["timesteps"] >= 4096
    assert figures["final_return"] == -3 and 0 < figures["timesteps_to_95"] <= figures["timesteps"]
    # seconds are printed to 4 decimals: a short run's rate computed back from them is off by more than 0.1%
    assert figures["timesteps"] / figures["env_steps_per_second"] == pytest.approx(figures["seconds"], abs=1e-4)
    assert sum(" steps/s " in line and "eval greedy return" in line for line in out.splitlines()) >= 4  # not a terminal
    assert f"policy saved to {policy}\n" in out and policy.is_file() and not (tmp_path / "m.zip").exists()
    assert curve.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the saved policy plays, and training can go on from it
    assert run(["play", "--level", "default", "--policy", str(policy), "--seed", "0", "--no-delay"]) == 0
    assert "policy " + str(policy) in capsys.readouterr().out
    assert run(["train", "--level", "default", "--steps", "256", "--load", str(policy), "--no-progress", *SMALL]) == 0
    assert last_json(capsys.readouterr().out)["final_return"] == -3


def test_a_race_reports_win_and_tie_rates_and_its_policy_races(tmp_path, capsys):
    policy = tmp_path / "racer.pt"
    argv = ["train", "--level", "race-2", "--robots", "2", "--steps", "2048", "--episodes", "20", "--save", str(policy),
            "--no-progress", *SMALL]
    assert run(argv) == 0
    out = capsys.readouterr().out
    figures = last_json(out)
    assert figures["opponents"] == ["random"] and figures["vs_shortest"]["opponents"] == ["shortest"]
    assert 0 <= figures["tie_rate"] <= figures["win_rate"] <= 1 and figures["races"] == 20
    assert "eval" not in out  # --no-progress: no evaluation lines
    argv = ["race", "--level", "race-2", "--robots", "2", "--policies", f"{policy},shortest", "--seed", "0", "--no-delay"]
    assert run(argv) == 0
    assert str(policy) in capsys.readouterr().out
    # a race policy reads the robots near it: it races with more robots than it trained with, and
    # training goes on from it with the radius it was saved with
    argv = ["race", "--level", "race-2", "--robots", "3", "--policies", f"{policy},{policy},random", "--no-delay"]
    assert run(argv) == 0
    capsys.readouterr()
    wide = tmp_path / "wide.pt"
    assert run(["train", "--level", "race-2", "--robots", "2", "--steps", "512", "--near-radius", "2", "--save", str(wide),
                "--episodes", "5", "--no-progress", *SMALL]) == 0
    assert run(["train", "--level", "race-2", "--robots", "3", "--steps", "512", "--load", str(wide), "--episodes", "5",
                "--no-progress", *SMALL]) == 0
    assert load_policy(wide).inputs.near == near_offsets(2)


@pytest.mark.parametrize(("argv", "message"), [
    (["train", "--steps", "10", "--algo", "dqn"], "--algo dqn: only for one robot with --backend sb3"),
    (["train", "--steps", "10", "--load", "nowhere.pt"], "--load: no such file 'nowhere.pt'"),
    (["train", "--steps", "10", "--backend", "sb3", "--load", __file__],
     "--load: starting from a saved policy needs --backend fast"),
    (["train", "--steps", "10", "--net-arch", "64,x"], "--net-arch: must be layer sizes"),
    (["train", "--steps", "10", "--gamma", "2"], "--gamma: must be a number in [0, 1]"),
    (["train", "--steps", "10", "--backend", "sb3", "--near-radius", "2"], "--near-radius: only the fast backend"),
    (["train", "--steps", "10", "--near-radius", "-1"], "--near-radius: "),
    (["play", "--policy", "missing.pt"], "--policy: no such file 'missing.pt'"),
    (["train"], "--seconds: give either --steps N (timesteps) or --seconds SECONDS (a wall-clock budget), not neither"),
    (["train", "--steps", "10", "--seconds", "5"], "--seconds: give either --steps N (timesteps) or --seconds SECONDS"),
    (["train", "--seconds", "5", "--backend", "sb3"], "--seconds: only the fast backend has it"),
    (["train", "--level", "maze:8..16", "--robots", "4", "--seconds", "5"], "--observe: a level family (maze:8..16) trains"),
    (["train", "--level", "maze:8..16", "--robots", "4", "--seconds", "5", "--observe", "local", "--collisions", "x"],
     "--collisions: invalid choice: 'x'"),
    (["train", "--level", "maze:9..8", "--robots", "4", "--seconds", "5", "--observe", "local"], "--level: "),
    (["train", "--steps", "10", "--hint"], "--hint: only with --observe local"),
    (["train", "--steps", "10", "--memory"], "--memory: only with --observe local"),
    (["train", "--steps", "10", "--collisions", "bounce"], "--collisions: a lone robot (--robots 1) meets nobody"),
    (["train", "--level", "maze:8..8", "--robots", "2", "--steps", "10", "--observe", "local", "--view-radius", "9"],
     "--view-radius"),
])
def test_bad_train_input_is_one_line_and_status_2(argv, message, capsys):
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_a_policy_for_another_level_size_is_refused_by_play(tmp_path, capsys):
    policy = tmp_path / "p.pt"
    assert run(["train", "--level", "default", "--steps", "256", "--save", str(policy), "--no-progress", *SMALL]) == 0
    capsys.readouterr()
    assert run(["play", "--level", "walls", "--policy", str(policy), "--no-delay"]) == 2
    assert "was trained on default (3x3); this level is 5x5" in capsys.readouterr().err


@pytest.mark.parametrize("algo", ["ppo", "dqn"])
def test_the_sb3_backend_names_its_algorithm_and_reports_its_training_return(algo, capsys):
    pytest.importorskip("stable_baselines3", reason="needs the train extra")
    argv = ["train", "--backend", "sb3", "--algo", algo, "--level", "default", "--steps", "2048", "--eval-every", "1024"]
    assert run(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    progress = [line for line in lines if "training return" in line]
    assert progress and "nan" not in progress[-1]  # SB3's own episode returns, as the fast backend shows its own
    assert any(line.startswith(f"sb3 {algo.upper()} on ") for line in lines)


def test_a_family_trains_within_its_seconds_and_its_policy_races_on_the_env(tmp_path, capsys):
    """--level maze:A..B --observe local --hint --seconds T: one policy on an atlas of mazes, stopped by the wall-clock
    budget, judged on mazes of the evaluation seeds; the saved file runs on race_v0 with observe='local', hint=True."""
    from babyrobot_marl import race_v0

    policy = tmp_path / "p.pt"
    argv = ["train", "--level", "maze:8..10", "--robots", "3", "--observe", "local", "--hint", "--seconds", "1",
            "--collisions", "bounce", "--episodes", "10", "--save", str(policy), "--no-progress", *SMALL]
    assert run(argv) == 0
    out = capsys.readouterr().out
    figures = last_json(out)
    assert figures["level"] == "maze:8..10" and figures["episodes"] == 10 and figures["timesteps"] > 0
    assert 1.0 <= figures["seconds"] < 30  # stopped after the rollout that crossed 1 s
    assert 0 <= figures["success_rate"] <= 1 and figures["makespan"] > 0
    env = race_v0.parallel_env(level="maze:9..9", n_robots=3, observe="local", hint=True, start="random", collisions="bounce")
    agent = load_policy(policy, env=env)
    obs, _ = env.reset(seed=0)
    while env.agents:
        obs, *_ = env.step({a: agent(obs[a]) for a in env.agents})


def test_train_memory_saves_a_policy_that_reads_its_last_action_and_evaluate_runs_it(tmp_path, capsys):
    """--memory: the saved policy's net also reads the robot's last action; `evaluate` binds one per robot."""
    from babyrobot_marl.training.policy import load_checkpoint

    policy = tmp_path / "m.pt"
    argv = ["train", "--level", "maze:8..8", "--robots", "2", "--observe", "local", "--memory", "--steps", "2048",
            "--episodes", "10", "--save", str(policy), "--no-progress", *SMALL]
    assert run(argv) == 0
    assert "(view_radius 2, memory; crowd defaults near_radius 2, blocked_cost 0.5)" in capsys.readouterr().out
    assert load_checkpoint(policy)["config"]["memory"] is True
    assert run(["evaluate", str(policy), "--level", "maze:8..8", "--robots", "2", "--episodes", "3"]) == 0
    assert 0 <= last_json(capsys.readouterr().out)["policy"]["success_rate"] <= 1
