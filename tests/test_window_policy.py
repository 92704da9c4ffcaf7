"""A level family's saved policy (``WindowPolicy``): watched by ``race`` and ``play`` in the observation form it
reads, and its action cache bounded however long it plays."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("torch", reason="needs the train extra")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.envs.single import BabyRobotEnv  # noqa: E402
from babyrobot_marl.experiments import evaluate  # noqa: E402
from babyrobot_marl.training import trained as trained_module  # noqa: E402
from babyrobot_marl.training.policy import load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, train_ppo  # noqa: E402
from tests.cli_run import run  # noqa: E402


@pytest.fixture(scope="module")
def crowd(tmp_path_factory):
    """A barely trained family policy of 2 robots that reads the hint and its last action."""
    path = tmp_path_factory.mktemp("crowd") / "crowd.pt"
    cfg = PPOConfig(n_envs=8, n_steps=8, batch_size=64, eval_every=0, atlas_size=4, hint=True, memory=True)
    train_ppo("maze:5..6", 2, 64, seed=0, config=cfg).save(path)
    return path


def test_race_shows_a_family_policy_its_own_observations(crowd, capsys):
    argv = ["race", "--level", "maze:6..8", "--robots", "2", "--start", "random", "--policies", str(crowd), "--seed", "1",
            "--no-delay"]
    assert run(argv) == 0
    assert str(crowd) in capsys.readouterr().out
    assert run(["race", "--level", "maze:6..8", "--robots", "3", "--start", "random", "--policies",
                f"{crowd},shortest,random", "--races", "3", "--seed", "1"]) == 0
    assert "3 races on maze:6..8" in capsys.readouterr().out


def test_race_refuses_saved_policies_that_read_different_windows(crowd, tmp_path, capsys):
    other = tmp_path / "other.pt"
    cfg = PPOConfig(n_envs=8, n_steps=8, batch_size=64, eval_every=0, atlas_size=4, view_radius=1)
    train_ppo("maze:5..6", 2, 64, seed=0, config=cfg).save(other)
    code = run(["race", "--level", "maze:6..8", "--robots", "2", "--start", "random", "--policies", f"{crowd},{other}"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--policies" in err and "--view-radius 1" in err


def test_play_runs_a_family_policy_on_one_robots_window(crowd, capsys):
    assert run(["play", "--level", "maze:6..8", "--policy", str(crowd), "--seed", "3", "--no-delay"]) == 0
    assert f"policy {crowd}, seed 3" in capsys.readouterr().out


def test_a_lone_robots_window_is_the_one_race_v0_shows_it(crowd):
    single = BabyRobotEnv(level="maze-7x7-s5", start="random")
    race = race_v0.parallel_env(level="maze-7x7-s5", n_robots=1, start="random", observe="local", hint=True)
    rows = load_policy(crowd).for_env(single).encoder
    for seed in range(6):
        obs, _ = race.reset(seed=seed)
        x, y = obs["robot_0"][:2]
        assert np.array_equal(rows.decode(np.array([x, y])), obs["robot_0"])


def test_the_action_cache_stays_bounded_over_a_long_evaluation(crowd, monkeypatch):
    monkeypatch.setattr(trained_module, "PROBS_CACHE", 16)
    policy = load_policy(crowd, deterministic=False, seed=0)
    computed = []
    put = policy._probs.put
    monkeypatch.setattr(policy._probs, "put", lambda key, value: (computed.append(key), put(key, value)))
    evaluate(policy, level="maze:6..8", n_robots=2, episodes=6, seed=0, policy_env=policy.observation)
    assert len(set(computed)) > 16  # more distinct inputs than it keeps
    assert len(policy._probs) == 16
