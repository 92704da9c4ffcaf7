"""BabyRobotRace-v0: robot 0 races scripted opponents as a single-agent Gymnasium env."""

from __future__ import annotations

import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import babyrobot_marl  # noqa: F401  (registers babyrobot_marl/BabyRobotRace-v0)
from babyrobot_marl.envs.race_gym import BabyRobotRaceEnv
from babyrobot_marl.policies import ShortestPathPolicy

ENV_ID = "babyrobot_marl/BabyRobotRace-v0"
MODES = ("block", "bounce", "pass")
STAY = 0


def make(**kwargs):
    kwargs.setdefault("level", "race-4")
    kwargs.setdefault("opponents", ["shortest", "random", "random"])
    return gymnasium.make(ENV_ID, **kwargs)


@pytest.mark.parametrize("mode", MODES)
def test_gymnasium_check_env_passes_without_warnings(mode):
    env = make(collisions=mode)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)  # the checker itself asks for the unwrapped env


@pytest.mark.parametrize("mode", MODES)
def test_stable_baselines3_check_env_passes_without_warnings(mode):
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker", reason="needs the train extra (Stable-Baselines3)")
    env = make(collisions=mode)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sb3_checker.check_env(env.unwrapped, warn=True)


def test_make_builds_the_race_env_with_robot_0_as_learner():
    env = make(level="race-2", opponents=["random"])
    race_env = env.unwrapped
    assert isinstance(race_env, BabyRobotRaceEnv)
    assert race_env.race.n_robots == 2
    assert race_env.observation_space == race_env.race.observation_space("robot_0")
    assert env.action_space == gymnasium.spaces.Discrete(5)
    obs, info = env.reset(seed=0)
    assert obs.tolist() == [0, 0, 4, 4, 0]  # robot 0 at its start, then robot 1 racing at its start
    assert info["ranks"].tolist() == [0, 0] and info["rank"] == 0


def test_an_unknown_reset_option_warns_once_naming_starts_and_is_ignored():
    env, plain = (BabyRobotRaceEnv(level="race-4", opponents=["random"] * 3) for _ in range(2))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        obs, _ = env.reset(seed=2, options={"options": 1})
    # once: the race inside is given only the known options
    assert [str(w.message) for w in caught] == ["options: unknown option 'options' ignored; known options are 'starts'"]
    assert obs.tolist() == plain.reset(seed=2)[0].tolist()
    for _ in range(20):
        assert env.step(1)[0].tolist() == plain.step(1)[0].tolist()


def test_bad_starts_beside_an_unknown_option_are_still_a_value_error():
    env = BabyRobotRaceEnv(level="race-4", opponents=["random"] * 3)
    with pytest.warns(UserWarning, match="'options' ignored"), pytest.raises(ValueError, match=r'options\["starts"\]'):
        env.reset(options={"starts": [(0, 1)] * 4, "options": 1})


def test_bad_opponents_are_a_value_error_naming_the_argument():
    for bad in ("random", ["random", "clever"], [3]):
        with pytest.raises(ValueError, match="opponents"):
            BabyRobotRaceEnv(level="race-4", opponents=bad)


def _learner(env) -> ShortestPathPolicy:
    return ShortestPathPolicy(env.unwrapped.race.table)


def test_episode_terminates_in_the_step_robot_0_finishes():
    env = make()
    policy = _learner(env)
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        terminated = truncated = False
        steps = 0
        while not (terminated or truncated):
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            steps += 1
            assert terminated == info["finished"]
            assert terminated == (tuple(obs[:2]) in env.unwrapped.level.exits)
        assert terminated and not truncated
        assert info["ranks"][0] >= 1 and info["rank"] == info["ranks"][0]
        assert reward == (10.0 if info["rank"] == 1 else 0.0)  # the exit's 0, plus the bonus if first
        with pytest.raises(RuntimeError):
            env.unwrapped.step(0)  # the episode is over


def test_episode_goes_on_when_an_opponent_finishes_and_is_truncated_at_max_cycles():
    env = make(level="race-2", opponents=["shortest"], max_cycles=20)
    env.reset(seed=0)
    for t in range(1, 21):
        obs, reward, terminated, truncated, info = env.step(STAY)  # robot 0 never moves
        assert not terminated and truncated == (t == 20)
        assert reward == -1.0  # robot 0's floor cell, every step
    assert info["ranks"][1] == 1 and info["ranks"][0] == 0  # the opponent won meanwhile
    assert obs[4] == 1  # and robot 0 sees it finished


def test_shortest_path_learner_usually_beats_random_opponents():
    env = make(level="race-4", opponents=["random", "random", "random"])
    policy = _learner(env)
    episodes, wins = 40, 0
    for seed in range(episodes):
        obs, _ = env.reset(seed=seed)
        done = False
        while not done:
            obs, _, terminated, truncated, info = env.step(policy(obs))
            done = terminated or truncated
        wins += info["ranks"][0] == 1
    # a random robot needs far more than the shortest path's ~10 steps to find the centre
    assert wins >= 0.8 * episodes


def _trajectory(env, seed: int, n_steps: int = 60):
    obs, info = env.reset(seed=seed)
    out = [(obs.tolist(), tuple(info["cell"].tolist()), info["ranks"].tolist())]
    g = np.random.default_rng(1)
    for _ in range(n_steps):
        obs, reward, terminated, truncated, info = env.step(int(g.integers(5)))
        out.append((obs.tolist(), reward, terminated, truncated, info["cell"].tolist(), info["outcome"], info["ranks"].tolist()))
        if terminated or truncated:
            break
    return out


def test_seeding_reproduces_episodes_and_different_seeds_differ():
    a, b = make(), make()
    for seed in (0, 5):
        assert _trajectory(a, seed) == _trajectory(b, seed)
        assert _trajectory(a, seed) == _trajectory(a, seed)  # reseeding the same env repeats it
    runs = [_trajectory(a, seed) for seed in range(6)]
    assert any(r != runs[0] for r in runs[1:])


def test_unseeded_resets_continue_the_seeded_sequence():
    a, b = make(), make()
    a.reset(seed=3)
    b.reset(seed=3)
    g = np.random.default_rng(0)
    for _ in range(3):
        for _ in range(30):
            act = int(g.integers(5))
            ra, rb = a.step(act), b.step(act)
            assert ra[0].tolist() == rb[0].tolist() and ra[1:4] == rb[1:4]
            if ra[2] or ra[3]:
                break
        oa, _ = a.reset()
        ob, _ = b.reset()
        assert oa.tolist() == ob.tolist()
