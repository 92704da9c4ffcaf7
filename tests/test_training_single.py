"""Single-robot deep RL: short seeded PPO/DQN runs end to end, the optimum they are judged against,
the GIF of a policy, and the message when the train extra is missing."""

from __future__ import annotations

import builtins

import numpy as np
import pytest

pytest.importorskip("stable_baselines3", reason="needs the train extra")  # CI installs it (test extra)

from babyrobot_marl import BabyRobotEnv, levels  # noqa: E402
from babyrobot_marl.policies.shortest import distances  # noqa: E402
from babyrobot_marl.training import MissingTrainExtraError, require_train  # noqa: E402
from babyrobot_marl.training.single import evaluate_single, optimal_return, train_single, within  # noqa: E402


def test_optimal_return_is_the_shortest_path_on_a_maze_and_the_mean_over_random_starts():
    env = BabyRobotEnv(level="maze-8x8")
    d = distances(env.table)[env.table.cell_id(levels.get("maze-8x8").starts[0])]
    assert optimal_return(env) == -(d - 1)
    rnd = BabyRobotEnv(level="default", start="random")
    free = [c for c in range(9) if c not in (8,)]  # every cell but the exit is a free floor cell
    assert optimal_return(rnd) == pytest.approx(np.mean([-(distances(rnd.table)[c] - 1) for c in free]))


def test_within_reads_95_percent_of_a_negative_optimum():
    assert within(-21.0, -20.0) and not within(-21.5, -20.0) and within(-19.0, -20.0)


@pytest.mark.parametrize("algo", ["ppo", "dqn"])
def test_a_short_seeded_run_trains_and_evaluates(algo):
    extra = {"n_steps": 64, "batch_size": 128, "n_epochs": 1} if algo == "ppo" else {"learning_starts": 100}
    agent = train_single("default", algo, steps=512, seed=0, n_envs=2, **extra)
    assert agent.num_timesteps >= 512
    ev = evaluate_single(agent, BabyRobotEnv(level="default", max_steps=20), episodes=2)
    assert ev.episodes == 2 and -20 <= ev.mean <= -3 and 0 <= ev.reached_exit <= 2


def test_same_seed_same_policy():
    a = train_single("default", "ppo", steps=256, seed=3, n_envs=2, n_steps=64, batch_size=128, n_epochs=1)
    b = train_single("default", "ppo", steps=256, seed=3, n_envs=2, n_steps=64, batch_size=128, n_epochs=1)
    for pa, pb in zip(a.policy.parameters(), b.policy.parameters()):
        assert np.array_equal(pa.detach().numpy(), pb.detach().numpy())


def test_bad_training_arguments():
    with pytest.raises(ValueError, match="algo"):
        train_single("default", "a2c", steps=10)
    with pytest.raises(ValueError, match="steps"):
        train_single("default", "ppo", steps=0)


def test_missing_train_extra_is_a_clear_error(monkeypatch):
    real_import = builtins.__import__

    def fake_import(name, *args, **kwargs):
        if name.startswith("supersuit"):
            raise ImportError("No module named 'supersuit'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", fake_import)
    monkeypatch.delitem(__import__("sys").modules, "supersuit", raising=False)
    with pytest.raises(MissingTrainExtraError, match=r"supersuit .*pip install 'babyrobot_marl\[train\]'"):
        require_train("supersuit")


def test_cell_features_give_each_cell_its_own_one_hot():
    """SB3's one-hots of x and y in, one one-hot per cell out: every cell distinct, at y * W + x."""
    th = pytest.importorskip("torch", reason="needs the train extra")
    from gymnasium import spaces

    from babyrobot_marl.training.single import cell_features_class

    w, h = 5, 3
    extractor = cell_features_class()(spaces.MultiDiscrete([w, h]), width=w, height=h)
    xs, ys = np.meshgrid(np.arange(w), np.arange(h))
    one_hot = th.nn.functional.one_hot
    obs = th.cat([one_hot(th.as_tensor(xs.ravel()), w), one_hot(th.as_tensor(ys.ravel()), h)], 1)
    out = extractor(obs.float()).numpy()
    assert out.shape == (w * h, w * h)
    assert (out.argmax(axis=1) == ys.ravel() * w + xs.ravel()).all() and (out.sum(axis=1) == 1).all()


def test_ppo_with_cell_features_trains_saves_and_loads(tmp_path):
    pytest.importorskip("stable_baselines3", reason="needs the train extra")
    from stable_baselines3 import PPO

    from babyrobot_marl.training.single import train_single

    agent = train_single("walls", "ppo", steps=512, seed=0, n_envs=2)
    agent.save(tmp_path / "m.zip")
    back = PPO.load(tmp_path / "m.zip", device="cpu")
    obs = np.array([2, 3])
    assert int(back.predict(obs, deterministic=True)[0]) == int(agent.predict(obs, deterministic=True)[0])
    with pytest.raises(ValueError, match="^features"):
        train_single("walls", "ppo", steps=64, features="pixels")


def test_sb3_training_runs_on_one_torch_thread_and_restores_the_setting():
    """Under CPU load torch's OpenMP threads stall SB3 for minutes; one thread slows it in proportion."""
    import torch
    from stable_baselines3.common.callbacks import BaseCallback

    seen = []

    class Threads(BaseCallback):
        def _on_step(self) -> bool:
            seen.append(torch.get_num_threads())
            return True

    before = torch.get_num_threads()
    train_single("default", "ppo", steps=128, seed=0, n_envs=2, n_steps=64, batch_size=64, n_epochs=1, callback=Threads())
    assert seen and set(seen) == {1} and torch.get_num_threads() == before
