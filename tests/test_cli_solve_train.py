"""``babyrobot-marl solve`` and ``babyrobot-marl train``."""

from __future__ import annotations

import json

import pytest

from tests.cli_run import run


def test_solve_prints_the_value_grid_and_the_policy_arrows(capsys):
    assert run(["solve", "--level", "default", "--decimals", "0"]) == 0
    out = capsys.readouterr().out
    values = out.split("values\n")[1].split("\n\n")[0].splitlines()
    assert [row.split() for row in values] == [["-3", "-2", "-1"], ["-2", "-1", "0"], ["-1", "0", "0"]]
    assert out.split("policy\n")[1].splitlines()[:3] == ["→ → ↓", "→ → ↓", "→ → E"]
    assert "optimal return from the start (0, 0): -3" in out


def test_solve_by_policy_iteration_with_discount_and_blocked_cells(capsys):
    assert run(["solve", "--level", "blocked", "--method", "policy", "--gamma", "0.9"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("policy iteration on blocked (5x5), gamma 0.9")
    assert "#" in out.split("policy\n")[1]


@pytest.mark.parametrize(("argv", "message"), [
    (["solve", "--gamma", "0"], "--gamma: must be a number in (0, 1]"),
    (["solve", "--theta", "-1"], "--theta: must be a number > 0"),
    (["solve", "--level", "nowhere"], "unknown level 'nowhere'"),
    (["train", "--level", "default"], "--steps"),
])
def test_bad_input_is_one_line_and_status_2(argv, message, capsys):
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_train_without_the_extra_says_how_to_install_it(monkeypatch, capsys):
    from babyrobot_marl import training

    def missing(*modules):
        raise training.MissingTrainExtraError("training needs supersuit (the 'train' extra): pip install 'babyrobot_marl[train]'")

    monkeypatch.setattr(training, "require_train", missing)
    assert run(["train", "--steps", "10"]) == 2  # one line, as any error the user can fix
    assert "pip install 'babyrobot_marl[train]'" in capsys.readouterr().err


def test_train_names_a_bad_flag_before_asking_for_the_extra(monkeypatch, capsys):
    from babyrobot_marl import training

    def missing(*modules):
        raise training.MissingTrainExtraError("training needs torch (the 'train' extra)")

    monkeypatch.setattr(training, "require_train", missing)  # as on a machine without torch
    assert run(["train", "--level", "default"]) == 2
    err = capsys.readouterr().err
    assert "--steps" in err and "extra" not in err


def test_train_single_robot_end_to_end_saves_the_model_and_a_gif(tmp_path, capsys):
    pytest.importorskip("stable_baselines3", reason="needs the train extra")  # CI installs it (train extra)
    pytest.importorskip("imageio", reason="needs the train extra")
    gif, saved = tmp_path / "p.gif", tmp_path / "m"
    argv = ["train", "--backend", "sb3", "--level", "default", "--steps", "256", "--episodes", "2", "--gif", str(gif),
            "--save", str(saved)]
    assert run(argv) == 0
    out = capsys.readouterr().out
    assert "sb3 PPO on default: greedy return" in out and "optimal -3" in out
    assert f"model saved to {saved}\n" in out and not (tmp_path / "m.zip").exists()  # the message is the file
    assert gif.stat().st_size > 0 and saved.stat().st_size > 0
    figures = json.loads(out.strip().splitlines()[-1])
    assert figures["backend"] == "sb3" and figures["optimal_return"] == -3 and figures["timesteps"] >= 256
    from stable_baselines3 import PPO

    assert PPO.load(saved, device="cpu").num_timesteps == figures["timesteps"]


def test_train_race_end_to_end(capsys):
    pytest.importorskip("supersuit", reason="needs the train extra")  # CI installs it (train extra)
    assert run(["train", "--backend", "sb3", "--level", "race-2", "--robots", "2", "--steps", "512", "--episodes", "2"]) == 0
    out = capsys.readouterr().out
    assert "vs random: win rate" in out and "vs shortest: win rate" in out
    figures = json.loads(out.strip().splitlines()[-1])
    assert figures["opponents"] == ["random"] and 0 <= figures["win_rate"] <= 1 and figures["races"] == 2
    assert run(["train", "--level", "race-2", "--robots", "2", "--steps", "10", "--algo", "dqn"]) == 2
