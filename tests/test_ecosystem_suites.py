"""PettingZoo's and Gymnasium's own test suites, run unmodified on every env form in several
configurations: the parallel race and its AEC form (``api_test``, ``parallel_api_test``,
``seed_test``, ``parallel_seed_test``, ``max_cycles_test``, ``render_test``, ``state_test``,
``performance_benchmark``), the race as a Gymnasium env and the single-robot env (``check_env``).

No test here patches a suite: the envs are built as a user would and handed over. Every warning
is an error except the few listed in ``suite_warnings`` (each one explained).
"""

from __future__ import annotations

import functools
import re
import types
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import gymnasium
import pettingzoo
import pytest
from gymnasium.utils.env_checker import check_env

import babyrobot_marl  # noqa: F401  (registers the ids)
from babyrobot_marl import race_v0

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)  # importing pettingzoo.test warns about the old env creation API
    from pettingzoo.test import (
        api_test,
        max_cycles_test,
        parallel_api_test,
        parallel_seed_test,
        performance_benchmark,
        render_test,
        seed_test,
        state_test,
    )

# Eight robots race down to the exit; every start is at least 5 steps from it, so that no robot
# can finish within max_cycles_test's 4 cycles (the test's agent counts assume so). Puddles and
# a glass wall on the way: skids and failed passes happen.
EIGHT = """\
+-+-+-+-+-+-+-+-+
|0 1 2 3 4 5 6 7|
+ + + + + + + + +
|  p         P  |
+ + + +*+ + + + +
|        #      |
+ + + + + + + + +
|    p     p    |
+ + + + + + + + +
|               |
+ + + + + + + + +
|E              |
+-+-+-+-+-+-+-+-+
"""

# One configuration per line: every observe mode, every encoding, both finished modes, every
# collision mode, 1, 2, 4 and 8 robots.
RACES = {
    "default": {},
    "one-robot-local-freeze": dict(n_robots=1, observe="local", view_radius=1, finished="freeze"),
    "four-local-box-bounce-freeze": dict(
        level="race-4", n_robots=4, observe="local", view_radius=2, obs_encoding="box", collisions="bounce", finished="freeze"
    ),
    "four-nearest-onehot-pass": dict(
        level="race-4", n_robots=4, observe="nearest", k=2, obs_encoding="onehot", collisions="pass"
    ),
    "eight-global-block-remove": dict(level=EIGHT, n_robots=8),
    "eight-nearest-box-bounce-freeze": dict(
        level=EIGHT, n_robots=8, observe="nearest", k=3, obs_encoding="box", collisions="bounce", finished="freeze"
    ),
    "eight-local-onehot-pass-remove": dict(
        level=EIGHT, n_robots=8, observe="local", view_radius=1, obs_encoding="onehot", collisions="pass"
    ),
    # the goal hint; level families by spec: a maze of a new size at each reset (issue 27)
    "four-local-hint-bounce": dict(level="race-4", n_robots=4, observe="local", hint=True, collisions="bounce"),
    "four-family-local-hint-onehot": dict(
        level="maze:6..10", n_robots=4, start="random", observe="local", view_radius=1, hint=True, obs_encoding="onehot"
    ),
    "four-family-global-freeze": dict(level="maze:5..8", n_robots=4, start="random", finished="freeze"),
    "four-family-nearest-box": dict(level="maze:5..8", n_robots=4, start="random", observe="nearest", k=2, obs_encoding="box"),
    # own goals: each robot its own target, drawn at reset (frozen robots keep max_cycles_test's counts whole; the
    # removing one has eight robots, so that its median robot is still out when a few reach their goals early)
    "four-own-local-hint-freeze": dict(level="race-4", n_robots=4, goals="own", observe="local", hint=True, finished="freeze"),
    "eight-own-global-bounce-remove": dict(level=EIGHT, n_robots=8, goals="own", collisions="bounce"),
    "four-own-lifelong-local-hint-bounce": dict(
        level="race-4", n_robots=4, goals="own", lifelong=True, observe="local", hint=True, collisions="bounce"
    ),
    "four-family-own-nearest-onehot-freeze": dict(
        level="maze:5..8", n_robots=4, start="random", goals="own", observe="nearest", k=2, obs_encoding="onehot",
        finished="freeze",
    ),
    # POGEMA's on_target="nothing": robots stay on their targets, every agent present until the race ends
    "four-own-local-soft-stay": dict(level="maze-8x8", n_robots=4, start="random", goals="own", observe="local",
                                     collisions="soft", finished="stay"),
}
RACE_IDS = list(RACES)

# The suites' hints that do not apply: DESIGN.md makes observations MultiDiscrete (api_test suggests
# Box or Discrete); a robot at (0, 0) with nothing near observes all zeros, and one robot there
# alone has the state [0, 0, 0]: valid states.
HINTS = (
    "Observation space for each agent probably should be gymnasium.spaces.box or gymnasium.spaces.discrete",
    "Observation numpy array is all zeros.",
    "State numpy array is all zeros.",
)
# the api tests' reset(options={"options": 1}) probe: the option is ignored with this warning
PROBE = "options: unknown option 'options' ignored; known options are 'starts'"


@contextmanager
def suite_warnings() -> Iterator[None]:
    """Every warning is an error, except the suites' hints above and the probe's own warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for text in (*HINTS, PROBE):
            warnings.filterwarnings("ignore", message=re.escape(text))
        yield


def test_suite_warnings_lets_through_only_the_listed_ones():
    with suite_warnings():
        warnings.warn(PROBE, UserWarning, stacklevel=1)
        with pytest.raises(UserWarning):
            warnings.warn("options: unknown option 'begin' ignored; known options are 'starts'", UserWarning, stacklevel=1)
        with pytest.raises(UserWarning):
            warnings.warn("Live agent was not given observation", UserWarning, stacklevel=1)


def parallel(name: str, **extra: Any):
    return race_v0.parallel_env(**RACES[name], **extra)


def aec(name: str, **extra: Any):
    return race_v0.env(**RACES[name], **extra)


# ------------------------------------------------------------------------ PettingZoo
@pytest.mark.parametrize("name", RACE_IDS)
def test_parallel_api_test(name):
    with suite_warnings():
        parallel_api_test(parallel(name), num_cycles=300)


@pytest.mark.parametrize("name", RACE_IDS)
def test_api_test(name):
    with suite_warnings():
        api_test(aec(name), num_cycles=200)


@pytest.mark.parametrize("name", RACE_IDS)
def test_seed_test(name):
    with suite_warnings():
        seed_test(functools.partial(aec, name), num_cycles=200)


@pytest.mark.parametrize("name", RACE_IDS)
def test_parallel_seed_test(name):
    with suite_warnings():
        parallel_seed_test(functools.partial(parallel, name), num_cycles=200)


@pytest.mark.parametrize("name", RACE_IDS)
def test_max_cycles_test(name):
    # max_cycles_test takes a module with parallel_env and env accepting max_cycles=
    module = types.SimpleNamespace(parallel_env=functools.partial(parallel, name), env=functools.partial(aec, name))
    with suite_warnings():
        max_cycles_test(module)


def test_max_cycles_test_on_the_race_v0_module_itself():
    with suite_warnings():
        max_cycles_test(race_v0)


@pytest.mark.parametrize("name", RACE_IDS)
def test_render_test(name, capsys):
    with suite_warnings():
        render_test(functools.partial(aec, name))
    assert "step 0/" in capsys.readouterr().out  # "human" outside Jupyter prints the text frame


@pytest.mark.parametrize("name", RACE_IDS)
def test_state_test(name):
    with suite_warnings():
        state_test(aec(name), parallel(name))


@pytest.mark.skipif(not hasattr(pettingzoo, "make"), reason="PettingZoo < 1.26 has no registry (babyrobot_marl registers none)")
def test_api_tests_on_the_envs_pettingzoo_make_builds():
    kwargs = RACES["eight-nearest-box-bounce-freeze"]
    with suite_warnings():
        parallel_api_test(pettingzoo.make("parallel", "babyrobot_marl/Race-v0", **kwargs), num_cycles=300)
        api_test(pettingzoo.make("aec", "babyrobot_marl/Race-v0", **kwargs), num_cycles=200)


# performance_benchmark steps for 5 s of wall time whatever the load: two configurations only
@pytest.mark.parametrize("name", ["default", "eight-local-onehot-pass-remove"])
def test_performance_benchmark(name, capsys):
    with suite_warnings():
        performance_benchmark(aec(name))
    out = capsys.readouterr().out
    turns = float(re.search(r"([0-9.e+]+) turns per second", out).group(1))
    assert turns > 0 and "Finished performance benchmark" in out


# ------------------------------------------------------------------------ Gymnasium
RACE_GYM = {
    "default": {},
    "one-opponent-local-box": dict(level="race-2", opponents=["random"], observe="local", view_radius=1, obs_encoding="box"),
    "three-nearest-onehot-bounce": dict(
        level="race-4",
        opponents=["shortest", "random", "random"],
        observe="nearest",
        k=2,
        obs_encoding="onehot",
        collisions="bounce",
    ),
    "seven-global-pass": dict(level=EIGHT, opponents=["shortest"] * 3 + ["random"] * 4, collisions="pass"),
    "two-family-local-hint": dict(
        level="maze:6..9", opponents=["shortest", "random"], start="random", observe="local", hint=True
    ),
    "three-own-local-hint": dict(
        level="race-4", opponents=["shortest", "random", "shortest"], goals="own", observe="local", hint=True
    ),
    "two-own-lifelong-local": dict(level="race-4", opponents=["shortest", "random"], goals="own", lifelong=True, observe="local"),
    "one-own-global-box": dict(level="mixed-8x8", opponents=["random"], start="random", goals="own", obs_encoding="box"),
}
SINGLE = {
    "default": {},
    "puddles-box": dict(level="puddles", obs_encoding="box"),
    "glass-onehot-random-start": dict(level="glass", obs_encoding="onehot", start="random"),
    "maze-8x8": dict(level="maze-8x8"),
}
GYM = [("babyrobot_marl/BabyRobotRace-v0", k) for k in RACE_GYM] + [("babyrobot_marl/BabyRobot-v0", k) for k in SINGLE]


@pytest.mark.parametrize(("env_id", "name"), GYM, ids=[f"{i.split('/')[1]}-{n}" for i, n in GYM])
def test_gymnasium_check_env(env_id, name, capsys):
    kwargs = (RACE_GYM if "Race" in env_id else SINGLE)[name]
    env = gymnasium.make(env_id, **kwargs)  # made by gymnasium.make: a spec, so every render mode is checked too
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)  # the checker itself asks for the unwrapped env
    assert "step 0/" in capsys.readouterr().out  # its "human" render check printed the text frame
