"""The SuperSuit race vec env: the 3.11 pitfalls are handled (copies differ, PPO(seed=...) works,
truncation is marked), and a short shared-policy PPO run trains and evaluates end to end."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("stable_baselines3", reason="needs the train extra")  # CI installs it (test extra)
ss = pytest.importorskip("supersuit", reason="needs the train extra")

from babyrobot_marl.training.race import evaluate_race, make_race_vec_env, train_race  # noqa: E402


def trajectories(venv, steps: int = 40, seed: int = 5) -> np.ndarray:
    """Observations of every slot over ``steps`` steps of the same fixed action sequence."""
    rng = np.random.default_rng(seed)
    obs = [venv.reset()]
    for _ in range(steps):
        a = np.tile(rng.integers(0, 5, size=4), venv.num_envs // 4)  # every copy gets the same actions
        obs.append(venv.step(a)[0])
    return np.stack(obs)  # [t, slot, feature]


def test_copies_of_the_supersuit_race_play_different_episodes():
    venv = make_race_vec_env("race-4", n_robots=4, n_envs=3, seed=0, start="random")
    obs = trajectories(venv).reshape(41, 3, 4, -1)  # [t, copy, robot, feature]
    assert not np.array_equal(obs[:, 0], obs[:, 1]) and not np.array_equal(obs[:, 1], obs[:, 2])


def test_same_seed_same_races_and_seed_method_sets_the_next_reset():
    a = trajectories(make_race_vec_env("race-4", n_envs=2, seed=7, start="random"))
    b = trajectories(make_race_vec_env("race-4", n_envs=2, seed=7, start="random"))
    np.testing.assert_array_equal(a, b)
    venv = make_race_vec_env("race-4", n_envs=2, seed=1, start="random")
    assert venv.seed(7) == [7] * 4 + [8] * 4  # one seed per race, given for each of its robots' slots
    np.testing.assert_array_equal(trajectories(venv), a)


def test_truncation_is_marked_for_robots_cut_off_by_max_cycles():
    venv = make_race_vec_env("race-4", n_robots=4, n_envs=2, seed=0, max_cycles=3)
    venv.reset()
    for t in range(3):
        _, _, dones, infos = venv.step(np.zeros(8, dtype=np.int64))  # everyone stays: nobody finishes
        assert dones.all() == (t == 2)
        assert [i["TimeLimit.truncated"] for i in infos] == [t == 2] * 8


def test_ppo_with_a_seed_trains_on_it_and_evaluates_against_scripted_opponents():
    agent = train_race("race-4", n_robots=4, steps=1024, seed=0, n_envs=2, n_steps=128, batch_size=256, n_epochs=1)
    assert agent.num_timesteps >= 1024
    res = evaluate_race(agent, "race-4", n_robots=4, opponent="shortest", races=3, seed=0)
    assert res.races == 3 and 0 <= res.wins <= 3 and 0 <= res.finished <= 3
    with pytest.raises(ValueError, match="opponent"):
        evaluate_race(agent, opponent="greedy")
    with pytest.raises(ValueError, match="backend"):
        make_race_vec_env(backend="ray")
