"""Every registered id works with Gymnasium's time-aware wrappers: ``env.spec.max_episode_steps``
is the step at which the env truncates itself, for any ``level=`` (and ``max_steps=``/``max_cycles=``)."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.wrappers import TimeAwareObservation, TimeLimit

import babyrobot_marl  # noqa: F401  (registers the ids)
from babyrobot_marl.envs.single import default_max_steps

IDS = sorted(i for i in gymnasium.registry if i.startswith("babyrobot_marl/"))
# per id: the keyword that sets the env's own limit, and levels of several sizes (limits 100 and up)
LIMIT_ARG = {"babyrobot_marl/BabyRobot-v0": "max_steps", "babyrobot_marl/BabyRobotRace-v0": "max_cycles"}
LEVELS = {
    "babyrobot_marl/BabyRobot-v0": ["default", "puddles", "maze-8x8", "maze-16x16"],
    "babyrobot_marl/BabyRobotRace-v0": ["race-2", "race-4", "maze-16x16", "maze-8x8-*"],  # *: a new maze each reset
}
CASES = [(i, level) for i in IDS for level in LEVELS.get(i, [None])]
STAY = 0


def test_every_registered_id_has_its_cases():
    assert IDS == sorted(LIMIT_ARG) == sorted(LEVELS)  # a new id: add it above


def make(env_id: str, level: str | None, **kwargs):
    if env_id == "babyrobot_marl/BabyRobotRace-v0":
        kwargs.setdefault("opponents", ["random"])  # an opponent that may finish: robot 0 goes on alone
        if level and level.startswith("maze"):
            kwargs["start"] = "fill"  # one start on a maze: the opponent's drawn
    return gymnasium.make(env_id, **({"level": level} if level else {}), **kwargs)


def own_limit(env) -> int:
    u = env.unwrapped
    return u.max_steps if hasattr(u, "max_steps") else u.race.max_cycles


def stay_until_done(env) -> tuple[int, list]:
    """STAY from a level's start never reaches the exit: the episode ends by truncation."""
    obs, _ = env.reset(seed=0)
    observations, steps = [obs], 0
    while True:
        obs, _, terminated, truncated, _ = env.step(STAY)
        observations.append(obs)
        steps += 1
        assert not terminated
        if truncated:
            return steps, observations


@pytest.mark.parametrize(("env_id", "level"), CASES)
def test_spec_max_episode_steps_is_the_levels_own_limit(env_id, level):
    env = make(env_id, level)
    assert env.spec.max_episode_steps == own_limit(env) == default_max_steps(env.unwrapped.level)
    assert gymnasium.spec(env_id).max_episode_steps is None  # the registry's: no TimeLimit cutting big levels short


@pytest.mark.parametrize("env_id", IDS)
def test_spec_follows_the_limit_argument(env_id):
    env = make(env_id, None, **{LIMIT_ARG[env_id]: 17})
    assert env.spec.max_episode_steps == 17
    assert stay_until_done(env)[0] == 17


@pytest.mark.parametrize(("env_id", "level"), CASES)
def test_time_aware_observation_counts_to_the_step_the_env_truncates(env_id, level):
    env = TimeAwareObservation(make(env_id, level))
    steps, observations = stay_until_done(env)
    assert steps == own_limit(env)
    assert [o[-1] for o in observations] == list(range(steps + 1))  # the time: last of the flattened entries
    assert all(env.observation_space.contains(o) for o in observations)  # the last one too: the limit is the spec's


@pytest.mark.parametrize(("env_id", "level"), CASES)
def test_time_limit_reading_the_spec_truncates_with_the_env(env_id, level):
    inner = make(env_id, level)
    env = TimeLimit(inner, inner.spec.max_episode_steps)
    assert stay_until_done(env)[0] == own_limit(env)


@pytest.mark.parametrize("env_id", IDS)
def test_make_with_max_episode_steps_still_sets_a_shorter_limit(env_id):
    env = make(env_id, None, max_episode_steps=9)
    assert env.spec.max_episode_steps == 9
    time_aware = TimeAwareObservation(env)
    steps, observations = stay_until_done(time_aware)
    assert steps == 9 and observations[-1][-1] == 9


@pytest.mark.parametrize("env_id", IDS)
def test_an_env_made_from_its_own_spec_has_the_same_limit(env_id):
    env = make(env_id, "maze-16x16")
    again = gymnasium.make(env.spec)
    assert again.spec.max_episode_steps == env.spec.max_episode_steps == default_max_steps(env.unwrapped.level)
    assert stay_until_done(again)[0] == env.spec.max_episode_steps


def test_make_vec_still_builds_the_vector_envs():
    for mode in ("sync", "vector_entry_point"):
        envs = gymnasium.make_vec("babyrobot_marl/BabyRobot-v0", num_envs=2, vectorization_mode=mode, level="walls")
        obs, _ = envs.reset(seed=0)
        obs, *_ = envs.step(np.zeros(2, dtype=np.int64))
        assert obs.shape == (2, 2)
        envs.close()
