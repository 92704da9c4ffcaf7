"""A crowd's training settings from the command line: ``train --blocked-cost``, the crowd defaults (near radius 2,
blocked cost 0.5 for several robots that stop each other's moves), saved in the policy file and shown by ``evaluate``."""

from __future__ import annotations

import json

import pytest

from babyrobot_marl.training.crowd import CROWD_DEFAULTS, crowd_defaults
from tests.cli_run import run

SMALL = ["--n-envs", "16", "--n-steps", "16", "--batch-size", "128", "--eval-every", "512"]


@pytest.mark.parametrize(("robots", "collisions", "applies"), [
    (2, None, True), (2, "block", True), (32, "bounce", True), (2, "pass", False), (1, None, False),
])
def test_the_crowd_defaults_apply_to_several_robots_that_stop_each_other(robots, collisions, applies):
    assert crowd_defaults(robots, collisions, {}) == (CROWD_DEFAULTS if applies else {})


def test_a_setting_the_user_gave_keeps_its_value():
    assert crowd_defaults(4, "bounce", {"near_radius": 1, "blocked_cost": None}) == {"blocked_cost": 0.5}
    assert crowd_defaults(4, "bounce", {"near_radius": 3, "blocked_cost": 0.0}) == {}


def test_robots_reading_a_smaller_window_see_the_robots_within_it_by_default():
    assert crowd_defaults(4, "soft", {}, view_radius=1) == {"near_radius": 1, "blocked_cost": 0.5}
    assert crowd_defaults(4, "soft", {}, view_radius=3) == CROWD_DEFAULTS
    assert crowd_defaults(4, "soft", {"near_radius": 0}, view_radius=1) == {"blocked_cost": 0.5}


# ---------------------------------------------------------------------------- the command line
def trained_config(tmp_path, capsys, *flags: str) -> tuple[dict, str]:
    """Train a tiny policy with ``flags``; its saved settings and what train printed."""
    torch = pytest.importorskip("torch", reason="needs the train extra")
    path = tmp_path / "p.pt"
    assert run(["train", *flags, "--steps", "512", "--episodes", "4", "--save", str(path), "--no-progress", *SMALL]) == 0
    return torch.load(path, weights_only=False)["config"], capsys.readouterr().out


@pytest.mark.parametrize("flags", [
    ["--level", "race-2", "--robots", "2"],  # one level, the global rows, collisions "block" (the env's default)
    ["--level", "maze:6..6", "--robots", "3", "--observe", "local", "--hint", "--collisions", "bounce"],
])
def test_a_crowd_trains_with_the_crowd_defaults_and_says_so(tmp_path, capsys, flags):
    config, out = trained_config(tmp_path, capsys, *flags)
    assert config["near_radius"] == 2 and config["blocked_cost"] == 0.5
    summary = [line for line in out.splitlines() if line.startswith("fast PPO, one policy for")]
    assert len(summary) == 1 and "crowd defaults near_radius 2, blocked_cost 0.5" in summary[0]


def test_given_settings_and_pass_collisions_train_without_the_crowd_defaults(tmp_path, capsys):
    config, out = trained_config(tmp_path, capsys, "--level", "race-2", "--robots", "2", "--near-radius", "1",
                                 "--blocked-cost", "0.25")
    assert config["near_radius"] == 1 and config["blocked_cost"] == 0.25 and "crowd defaults" not in out
    config, out = trained_config(tmp_path, capsys, "--level", "maze:6..6", "--robots", "2", "--observe", "local",
                                 "--collisions", "pass")
    assert config["near_radius"] == 1 and config["blocked_cost"] == 0.0 and "crowd defaults" not in out
    config, out = trained_config(tmp_path, capsys, "--level", "race-2", "--robots", "2", "--blocked-cost", "0")
    assert config["near_radius"] == 2 and config["blocked_cost"] == 0.0
    assert "crowd defaults near_radius 2;" in out  # only the one the user left unset


def test_a_crowd_reading_a_3x3_window_trains_seeing_the_robots_in_it_and_a_wider_near_radius_is_refused(tmp_path,
                                                                                                       capsys):
    flags = ["--level", "maze:6..6", "--robots", "3", "--observe", "local", "--view-radius", "1"]
    config, out = trained_config(tmp_path, capsys, *flags)
    assert config["near_radius"] == 1 and "crowd defaults near_radius 1, blocked_cost 0.5" in out
    assert run(["train", *flags, "--near-radius", "2", "--steps", "512", *SMALL]) == 2
    assert "--near-radius: a robot sees the robots within its window; --near-radius 2 exceeds --view-radius 1" in (
        capsys.readouterr().err)


def test_evaluate_shows_the_settings_a_policy_was_trained_with(tmp_path, capsys):
    trained_config(tmp_path, capsys, "--level", "maze:6..6", "--robots", "2", "--observe", "local", "--hint",
                   "--blocked-cost", "0.75")
    path = str(tmp_path / "p.pt")
    assert run(["evaluate", path, "--level", "maze:6..6", "--robots", "2", "--episodes", "2"]) == 0
    lines = capsys.readouterr().out.splitlines()
    said = [line for line in lines if line.startswith(f"{path}: trained ")]
    assert len(said) == 1 and "near_radius 2, blocked_cost 0.75" in said[0] and "with 2 robot(s)" in said[0]
    assert set(json.loads(lines[-1])) == {"policy", "shortest", "random"}  # the JSON stays the last line


@pytest.mark.parametrize(("argv", "message"), [
    (["--blocked-cost", "-1"], "--blocked-cost: must be a number >= 0, got '-1'"),
    (["--blocked-cost", "nan"], "--blocked-cost: must be a number >= 0, got 'nan'"),
    (["--blocked-cost", "inf"], "--blocked-cost: must be a number >= 0, got 'inf'"),
    (["--blocked-cost", "0.5"], "--blocked-cost: a lone robot (--robots 1) is never stopped by another"),
    (["--robots", "2", "--level", "race-2", "--backend", "sb3", "--blocked-cost", "0.5"],
     "--blocked-cost: only the fast backend trains with it"),
])
def test_a_bad_blocked_cost_is_one_line_naming_the_flag(argv, message, capsys):
    assert run(["train", "--steps", "10", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
