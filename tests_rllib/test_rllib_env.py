"""The race as an RLlib MultiAgentEnv: RLlib's own check, episode ends, finished robots, seeding."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from ray.rllib.env.env_context import EnvContext
from ray.rllib.utils.pre_checks.env import check_multiagent_environments

from babyrobot_marl import race_v0
from babyrobot_marl.integrations.rllib import RaceMultiAgentEnv, register_race, win_rate
from babyrobot_marl.policies import ShortestPathPolicy

CONFIGS = [
    {},
    {"level": "race-4", "n_robots": 4},
    {"level": "race-corridor", "n_robots": 4, "collisions": "bounce"},
    {"level": "race-4", "n_robots": 3, "collisions": "pass", "start": "random"},
]


@pytest.mark.parametrize("config", CONFIGS)
def test_passes_rllib_env_check(config):
    check_multiagent_environments(RaceMultiAgentEnv(config))


def play(env, seed, actions_seed=0, max_steps=10_000):
    """One episode of random actions, as RLlib plays it: the reset and step results, each
    followed by ``env.agents`` at that point."""
    rng = np.random.default_rng(actions_seed)
    obs, infos = env.reset(seed=seed)
    steps = [(obs, None, None, None, infos, list(env.agents))]
    racing = list(obs)
    for _ in range(max_steps):
        out = env.step({a: int(rng.integers(5)) for a in racing})
        steps.append((*out, list(env.agents)))
        _, _, terms, truncs, _ = out
        if terms["__all__"] or truncs["__all__"]:
            return steps
        racing = [a for a in racing if not (terms[a] or truncs[a])]  # done robots act no more
    raise AssertionError("episode did not end")


@pytest.mark.parametrize("config", CONFIGS)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_episode_follows_rllib_conventions(config, seed):
    env = RaceMultiAgentEnv({**config, "max_cycles": 60})
    steps = play(env, seed)
    done: set[str] = set()
    acting = set(steps[0][0])
    assert acting == set(env.possible_agents)
    for k, (obs, rewards, terms, truncs, infos, agents) in enumerate(steps[1:], start=1):
        last = k == len(steps) - 1
        assert set(obs) == set(rewards) == set(infos) == acting  # the agents that acted, no others
        assert set(terms) == set(truncs) == acting | {"__all__"}
        assert not (set(obs) & done)  # a done robot never comes back
        assert all(isinstance(r, float) for r in rewards.values())
        for a in acting:
            assert obs[a] in env.observation_spaces[a]
            assert not (terms[a] and truncs[a])
        finished_now = {a for a in acting if terms[a] or truncs[a]}
        done |= finished_now
        assert set(agents) == acting  # the robots of this step's dicts
        acting -= finished_now
        assert (terms["__all__"] or truncs["__all__"]) == last
        assert not (terms["__all__"] and truncs["__all__"])
    assert not env.race.agents
    # truncated only at max_cycles, and then every robot that was still racing is truncated
    final_truncs = steps[-1][3]
    assert final_truncs["__all__"] == (len(steps) - 1 == 60 and any(v for a, v in final_truncs.items() if a != "__all__"))


def test_race_cut_while_a_robot_finishes_is_truncated():
    # robot_0 reaches the exit in the very step that hits max_cycles, robot_1 is still racing:
    # the episode must end (ParallelPettingZooEnv sets neither __all__ here)
    env = RaceMultiAgentEnv({"level": "race-2", "max_cycles": 1})
    env.reset(seed=0)
    exit_cell = min(env.race.level.exits)
    env.race.set_cells([(exit_cell[0] - 1, exit_cell[1]), (0, 0)])
    _, rewards, terms, truncs, _ = env.step({"robot_0": 2, "robot_1": 0})  # EAST into the exit
    assert terms == {"robot_0": True, "robot_1": False, "__all__": False}
    assert truncs == {"robot_0": False, "robot_1": True, "__all__": True}
    assert env.race.agents == []


def test_all_robots_finishing_terminates_the_episode():
    env = RaceMultiAgentEnv({"level": "race-2", "collisions": "pass"})  # both may enter the exit at once
    env.reset(seed=0)
    exit_x, exit_y = min(env.race.level.exits)
    env.race.set_cells([(exit_x - 1, exit_y), (exit_x + 1, exit_y)])
    _, _, terms, truncs, _ = env.step({"robot_0": 2, "robot_1": 4})
    assert terms["__all__"] and not truncs["__all__"]
    assert terms["robot_0"] and terms["robot_1"]


def test_is_the_race_step_for_step():
    """Differential: the RLlib env plays exactly race_v0 seeded with its derived seed."""
    env = RaceMultiAgentEnv({"level": "race-4", "n_robots": 4, "max_cycles": 80})
    steps = play(env, seed=5, actions_seed=9)
    derived = int(np.random.SeedSequence([5, 0]).generate_state(1, np.uint64)[0])
    ref = race_v0.parallel_env(level="race-4", n_robots=4, max_cycles=80)
    obs, _ = ref.reset(seed=derived)
    rng = np.random.default_rng(9)
    for k, mine in enumerate(steps):
        if k:
            out = ref.step({a: int(rng.integers(5)) for a in ref.agents})
            obs = out[0]
            assert out[1] == mine[1]
            assert out[2] == {a: v for a, v in mine[2].items() if a != "__all__"}
            assert out[3] == {a: v for a, v in mine[3].items() if a != "__all__"}
        assert obs.keys() == mine[0].keys()
        for a in obs:
            np.testing.assert_array_equal(obs[a], mine[0][a])
    assert not ref.agents


def trajectory(worker_index: int, seed: int | None) -> list:
    env = RaceMultiAgentEnv(EnvContext({"level": "race-4", "n_robots": 4, "start": "random"}, worker_index=worker_index))
    return [(sorted((a, o.tolist()) for a, o in s[0].items()), s[1]) for s in play(env, seed)]


def test_same_seed_same_episode():
    assert trajectory(1, 7) == trajectory(1, 7)


def test_env_runners_play_different_episodes():
    # RLlib seeds runner k's sub-env i with seed + k + i: (k=1, i=1) and (k=2, i=0) both get
    # seed + 2, yet must not play the same races
    base = 100
    runs = [trajectory(k, base + k + i) for k in (1, 2) for i in (0, 1)]
    starts = [tuple(map(tuple, (o for _, o in run[0][0]))) for run in runs]
    assert len(set(starts)) == len(starts)


def test_unseeded_envs_differ():
    assert trajectory(1, None) != trajectory(1, None)  # fresh entropy: equal only by a one-in-billions chance


@pytest.mark.parametrize(
    ("config", "error", "words"),
    [
        ({"finished": "freeze"}, ValueError, "finished"),
        ("race-2", TypeError, "config"),
        ({"n_robots": 0}, ValueError, "n_robots"),
        ({"colisions": "block"}, TypeError, "colisions"),
    ],
)
def test_bad_config_is_a_clear_error(config, error, words):
    with pytest.raises(error, match=words):
        RaceMultiAgentEnv(config)


@pytest.mark.parametrize("seed", [-1, 1.5, "0", True])
def test_bad_seed_is_a_clear_error_and_env_stays_usable(seed):
    env = RaceMultiAgentEnv({})
    with pytest.raises(ValueError, match="seed"):
        env.reset(seed=seed)
    obs, _ = env.reset(seed=0)
    assert set(obs) == {"robot_0", "robot_1"}


def test_register_race_makes_the_env_by_name(ray_local):
    from ray.tune.registry import ENV_CREATOR, _global_registry

    name = register_race("babyrobot_test_race")
    env = _global_registry.get(ENV_CREATOR, name)({"level": "race-4", "n_robots": 4})
    assert isinstance(env, RaceMultiAgentEnv) and env.possible_agents == [f"robot_{i}" for i in range(4)]
    with pytest.raises(ValueError, match="name"):
        register_race("")


def test_core_does_not_import_ray():
    code = "import sys, babyrobot_marl, babyrobot_marl.race_v0, babyrobot_marl.integrations; print('ray' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_win_rate_tells_good_from_bad_drivers():
    config = {"level": "race-4", "n_robots": 4, "max_cycles": 60}
    shortest = ShortestPathPolicy(RaceMultiAgentEnv(config).race.table)
    assert win_rate(lambda obs: 0, config, "random", races=5) == 0.0  # a robot that stays never wins
    assert win_rate(shortest, config, "random", races=20) > 0.5  # the planner beats random robots
    assert win_rate(shortest, config, "random", races=20, seed=4) == win_rate(shortest, config, "random", races=20, seed=4)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"opponent": "smart"}, "opponent"),
        ({"races": 0}, "races"),
        ({"races": 2.0}, "races: must be an integer >= 1"),
        ({"seed": -1}, "seed: must be an integer >= 0"),
        ({"seed": "0"}, "seed: must be an integer >= 0"),
        ({"seed": 1.5}, "seed: must be an integer >= 0"),
    ],
)
def test_win_rate_bad_arguments(kwargs, words):
    with pytest.raises(ValueError, match=words):
        win_rate(lambda obs: 0, **kwargs)


def test_win_rate_takes_numpy_integer_counts():
    config = {"level": "race-4", "n_robots": 4, "max_cycles": 30}
    assert win_rate(lambda obs: 0, config, "random", races=np.int64(2), seed=np.int64(1)) == 0.0
