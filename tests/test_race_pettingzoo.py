"""PettingZoo's own checks on the race, in every collision mode and both ``finished`` options;
the registry; SuperSuit vectorisation (why ``finished="freeze"`` exists)."""

from __future__ import annotations

import functools
import re
import types
import warnings
from contextlib import contextmanager

import numpy as np
import pettingzoo
import pytest

import babyrobot_marl  # noqa: F401  (registers babyrobot_marl/Race-v0)
from babyrobot_marl import race_v0
from babyrobot_marl.envs.race import RaceEnv

with warnings.catch_warnings():
    # importing pettingzoo.test warns that the old env creation API is deprecated
    warnings.simplefilter("ignore", DeprecationWarning)
    from pettingzoo.test import (
        api_test,
        max_cycles_test,
        parallel_api_test,
        parallel_seed_test,
        render_test,
        seed_test,
        state_test,
    )

MODES = ("block", "bounce", "pass")
FINISHED = ("remove", "freeze")
# DESIGN.md makes the observations MultiDiscrete; api_test only suggests Box or Discrete.
MULTIDISCRETE_HINT = "Observation space for each agent probably should be gymnasium.spaces.box or gymnasium.spaces.discrete"
# api_test plays random actions (unseeded): a robot in cell (0, 0) with its rival there too ("pass")
# or finished at (0, 0) observes all zeros, a valid state that api_test flags as suspicious
ALL_ZEROS = "Observation numpy array is all zeros."
# the api tests reset with options={"options": 1}: an unknown option, ignored with this warning
PROBE = "options: unknown option 'options' ignored; known options are 'starts'"


@contextmanager
def strict_warnings():
    """Every warning is an error, except api_test's hints above and the options probe's warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.filterwarnings("ignore", message=re.escape(MULTIDISCRETE_HINT))
        warnings.filterwarnings("ignore", message=re.escape(ALL_ZEROS))
        warnings.filterwarnings("ignore", message=re.escape(PROBE))
        yield


def test_strict_warnings_turns_other_warnings_into_errors():
    with strict_warnings():
        warnings.warn(MULTIDISCRETE_HINT, stacklevel=1)  # let through
        with pytest.raises(UserWarning):
            warnings.warn("Action space for each agent probably should be gymnasium.spaces.box", stacklevel=1)
        with pytest.raises(UserWarning):
            warnings.warn("Live agent was not given observation", stacklevel=1)


CONFIGS = [pytest.param({"collisions": m, "finished": f}, id=f"{m}-{f}") for m in MODES for f in FINISHED]
# race-2 (two robots, puddles) and race-corridor (four robots queueing): collisions happen often
LEVELS = [pytest.param({"level": "race-2"}, id="race-2"), pytest.param({"level": "race-corridor", "n_robots": 4}, id="corridor")]


def test_the_api_tests_options_probe_is_ignored_with_a_warning_naming_starts():
    """PettingZoo's api tests reset with ``options={"options": 1}``: accepted, with a UserWarning, and ignored."""
    probed, plain = (
        race_v0.parallel_env(level="race-4", n_robots=4, start="random"),
        race_v0.parallel_env(level="race-4", n_robots=4, start="random"),
    )
    with pytest.warns(UserWarning, match="unknown option 'options' ignored; known options are 'starts'"):
        obs, _ = probed.reset(seed=3, options={"options": 1})
    assert {a: o.tolist() for a, o in obs.items()} == {a: o.tolist() for a, o in plain.reset(seed=3)[0].items()}
    aec = race_v0.env()
    with pytest.warns(UserWarning, match="unknown option 'options' ignored; known options are 'starts'"):
        aec.reset(seed=0, options={"options": 1})
    assert aec.agents == ["robot_0", "robot_1"]


def test_an_unknown_option_beside_starts_is_ignored_and_starts_still_applies():
    env = race_v0.parallel_env(level="race-4", n_robots=4)
    starts = [(0, 1), (1, 1), (2, 1), (3, 1)]
    with pytest.warns(UserWarning, match="unknown option 'begin', 'x' ignored; known options are 'starts'"):
        obs, _ = env.reset(seed=0, options={"starts": starts, "begin": 1, "x": 2})
    assert [tuple(o[:2].tolist()) for o in obs.values()] == starts


def test_a_known_option_with_a_bad_value_stays_an_error():
    env = race_v0.parallel_env(level="race-4", n_robots=4)
    with pytest.warns(UserWarning, match="'options' ignored"), pytest.raises(ValueError, match=r'options\["starts"\]'):
        env.reset(options={"starts": [(0, 1)] * 4, "options": 1})


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("config", CONFIGS)
def test_parallel_api_test_passes(config, level):
    with strict_warnings():
        parallel_api_test(race_v0.parallel_env(**config, **level), num_cycles=300)


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("config", CONFIGS)
def test_aec_api_test_passes(config, level):
    with strict_warnings():
        api_test(race_v0.env(**config, **level), num_cycles=300)


@pytest.mark.parametrize("config", CONFIGS)
def test_seed_test_passes(config):
    with strict_warnings():
        seed_test(functools.partial(race_v0.env, level="race-4", n_robots=4, **config), num_cycles=100)


@pytest.mark.parametrize("config", CONFIGS)
def test_parallel_seed_test_passes(config):
    with strict_warnings():
        parallel_seed_test(functools.partial(race_v0.parallel_env, level="race-4", n_robots=4, **config), num_cycles=100)


@pytest.mark.parametrize("config", CONFIGS)
def test_max_cycles_test_passes(config):
    # On race-2 every robot is at least 4 steps from the exit, and max_cycles_test runs 4 cycles:
    # no robot can finish early, which the test's agent counts assume.
    module = types.SimpleNamespace(
        parallel_env=functools.partial(race_v0.parallel_env, **config),
        env=functools.partial(race_v0.env, **config),
    )
    with strict_warnings():
        max_cycles_test(module)


def test_max_cycles_test_passes_on_the_module_itself():
    with strict_warnings():
        max_cycles_test(race_v0)


@pytest.mark.parametrize("config", CONFIGS)
def test_render_test_passes(config, capsys):
    with strict_warnings():
        render_test(functools.partial(race_v0.env, **config))
    assert "step 0/" in capsys.readouterr().out  # "human" printed the text frame


@pytest.mark.parametrize("config", CONFIGS)
def test_state_test_passes(config):
    with strict_warnings():
        state_test(race_v0.env(level="race-4", n_robots=4, **config), race_v0.parallel_env(level="race-4", n_robots=4, **config))


def test_ansi_render_shows_the_robots_and_the_step():
    env = race_v0.parallel_env(level="race-2", render_mode="ansi")
    env.reset(seed=0)
    frame = env.render()
    assert isinstance(frame, str) and "step 0/" in frame
    env.step({"robot_0": 0, "robot_1": 0})
    assert "step 1/" in env.render()


def test_metadata_names_the_env_and_its_render_modes():
    meta = RaceEnv.metadata
    assert meta["name"] == "babyrobot_race_v0"
    assert set(meta["render_modes"]) >= {"ansi", "human"}
    assert meta["is_parallelizable"] is True


# ------------------------------------------------------------------------ registry
def test_pettingzoo_make_parallel_builds_the_race_with_its_arguments():
    env = pettingzoo.make("parallel", "babyrobot_marl/Race-v0", level="race-4", n_robots=4, collisions="bounce")
    assert isinstance(env.unwrapped, RaceEnv)
    assert env.unwrapped.collisions == "bounce" and env.unwrapped.level.name == "race-4"
    obs, _ = env.reset(seed=0)
    assert sorted(obs) == [f"robot_{i}" for i in range(4)]
    env.step(dict.fromkeys(env.agents, 0))


def test_pettingzoo_make_aec_builds_the_wrapped_aec_race():
    env = pettingzoo.make("aec", "babyrobot_marl/Race-v0", level="race-4", n_robots=4, max_cycles=6)
    assert isinstance(env, pettingzoo.AECEnv)
    env.reset(seed=0)
    assert env.possible_agents == [f"robot_{i}" for i in range(4)]
    turns = 0
    for _agent in env.agent_iter():
        _, _, term, trunc, _ = env.last()
        env.step(None if term or trunc else 0)
        turns += 1
    assert turns == 4 * 6 + 4  # six cycles, then one last turn each to leave


def test_aec_env_rejects_an_out_of_range_action_naming_the_agent_and_goes_on():
    env = race_v0.env()
    env.reset(seed=0)
    first = env.agent_selection
    with pytest.raises(ValueError, match=f"action of '{first}'"):  # checked before PettingZoo's assert
        env.step(7)
    assert env.agent_selection == first  # nothing was stored: the same agent acts next
    env.step(0)


# ------------------------------------------------------------------------ SuperSuit
def _vec(finished: str, max_cycles: int = 30):
    supersuit = pytest.importorskip("supersuit", reason="needs the train extra (SuperSuit)")
    pytest.importorskip("stable_baselines3", reason="needs the train extra (Stable-Baselines3)")
    env = race_v0.parallel_env(level="race-2", finished=finished, max_cycles=max_cycles)
    vec = supersuit.pettingzoo_env_to_vec_env_v1(env)
    return supersuit.concat_vec_envs_v1(vec, 2, num_cpus=0, base_class="stable_baselines3")


def test_supersuit_vectorises_the_frozen_race_through_several_races():
    vec = _vec("freeze", max_cycles=30)
    assert vec.num_envs == 4  # two copies of two robots
    obs = vec.reset()
    space = race_v0.parallel_env(level="race-2").observation_space("robot_0")
    g = np.random.default_rng(0)
    dones = 0
    for _ in range(300):
        obs, rewards, done, _ = vec.step(g.integers(5, size=vec.num_envs))
        assert obs.shape == (4, 5) and rewards.shape == (4,)
        assert all(space.contains(o.astype(np.int64)) for o in obs)
        dones += int(done.sum())
    # each race lasts at most 30 steps: at least 10 race ends per copy, each ending both robots
    assert dones >= 2 * 2 * 10
    vec.close()


def test_supersuit_cannot_vectorise_the_race_that_removes_finished_robots():
    """The reason for finished="freeze": SuperSuit needs every agent at every step."""
    vec = _vec("remove", max_cycles=30)
    obs = vec.reset()
    table = race_v0.parallel_env(level="race-2").table
    from babyrobot_marl.policies import ShortestPathPolicy

    runner = ShortestPathPolicy(table)
    with pytest.raises(AssertionError, match="varying numbers of active agents"):
        for _ in range(60):  # robot_0 of each copy runs to the exit while robot_1 waits: it finishes alone
            obs, *_ = vec.step(np.array([runner(obs[0]), 0, runner(obs[2]), 0]))
