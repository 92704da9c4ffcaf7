"""PPO on the race through RLlib: one iteration with a local and with a remote env runner,
a checkpoint that restores and acts, and seeded env runners (same seed, same run)."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from ray.rllib.algorithms.algorithm import Algorithm
from ray.rllib.env.multi_agent_env_runner import MultiAgentEnvRunner

from babyrobot_marl.integrations.rllib import (
    SHARED_POLICY,
    RaceMultiAgentEnv,
    greedy_policy,
    per_robot_config,
    race_config,
    shared_policy_config,
)

RACE = {"level": "race-2", "n_robots": 2, "max_cycles": 40}
SMALL = {"train_batch_size_per_learner": 200, "minibatch_size": 100, "num_epochs": 1}


def weights(algo, module_id):
    return [p.detach().clone() for p in algo.get_module(module_id).parameters()]


def changed(before, after):
    return any(not torch.equal(a, b) for a, b in zip(before, after))


def one_iteration(config):
    algo = config.training(**SMALL).build_algo()
    before = {m: weights(algo, m) for m in algo.config.policies}
    result = algo.train()
    return algo, before, result


def test_one_iteration_local_env_runner_shared_policy(ray_local):
    algo, before, result = one_iteration(shared_policy_config(RACE, num_env_runners=0, seed=0))
    try:
        assert set(algo.config.policies) == {SHARED_POLICY}
        runners = result["env_runners"]
        assert runners["num_env_steps_sampled"] >= SMALL["train_batch_size_per_learner"]
        assert set(runners["agent_episode_returns_mean"]) == {"robot_0", "robot_1"}  # both robots fed one policy
        assert result["learners"][SHARED_POLICY]["num_module_steps_trained"] > 0
        assert changed(before[SHARED_POLICY], weights(algo, SHARED_POLICY))
    finally:
        algo.stop()


@pytest.fixture(scope="module")
def remote_per_robot(ray_local):
    algo, before, result = one_iteration(per_robot_config(RACE, num_env_runners=1, seed=1))
    yield algo, before, result
    algo.stop()


def test_one_iteration_remote_env_runner_per_robot(remote_per_robot):
    algo, before, result = remote_per_robot
    assert set(algo.config.policies) == {"robot_0", "robot_1"}
    assert result["fault_tolerance"]["num_healthy_workers"] == 1
    assert result["env_runners"]["num_env_steps_sampled"] >= SMALL["train_batch_size_per_learner"]
    for robot in ("robot_0", "robot_1"):  # each robot trains its own policy
        assert result["learners"][robot]["num_module_steps_trained"] > 0
        assert changed(before[robot], weights(algo, robot))


def observations(n=40, seed=0):
    env = RaceMultiAgentEnv(RACE)
    space = env.observation_spaces["robot_0"]
    space.seed(seed)
    return space, [space.sample() for _ in range(n)]


def test_checkpoint_restores_and_acts(remote_per_robot, tmp_path):
    algo, _, _ = remote_per_robot
    path = algo.save_to_path(str(tmp_path / "ckpt"))
    restored = Algorithm.from_checkpoint(path)
    try:
        space, obs = observations()
        for robot in ("robot_0", "robot_1"):
            mine, theirs = greedy_policy(algo.get_module(robot), space), greedy_policy(restored.get_module(robot), space)
            assert [mine(o) for o in obs] == [theirs(o) for o in obs]
        # the restored robots race to the end of an episode
        env = RaceMultiAgentEnv(RACE)
        policies = {r: greedy_policy(restored.get_module(r), space) for r in env.possible_agents}
        ob, _ = env.reset(seed=0)
        racing, steps = list(ob), 0
        while True:
            actions = {a: policies[a](ob[a]) for a in racing}
            assert all(0 <= v < 5 for v in actions.values())
            ob, _, terms, truncs, _ = env.step(actions)
            steps += 1
            if terms["__all__"] or truncs["__all__"]:
                break
            racing = [a for a in racing if not (terms[a] or truncs[a])]
        assert steps <= RACE["max_cycles"]
    finally:
        restored.stop()


def test_greedy_policy_is_the_module_argmax(remote_per_robot):
    """greedy_policy flattens as FlattenObservations does in training: one-hot per entry."""
    algo, _, _ = remote_per_robot
    space, obs = observations(5)
    module = algo.get_module("robot_0")
    act = greedy_policy(module, space)
    for o in obs:
        onehot = np.concatenate([np.eye(n)[v] for n, v in zip(space.nvec, o)]).astype(np.float32)
        logits = module.forward_inference({"obs": torch.as_tensor(onehot[None])})["action_dist_inputs"][0]
        assert act(o) == int(torch.argmax(logits))


def sampled(config, worker_index):
    runner = MultiAgentEnvRunner(config=config, worker_index=worker_index)
    try:
        episodes = runner.sample(num_timesteps=60, random_actions=False)
        return [
            (np.asarray(e.agent_episodes[a].get_observations()).tolist(), list(e.agent_episodes[a].get_actions()))
            for e in episodes
            for a in sorted(e.agent_episodes)
        ]
    finally:
        runner.stop()


def test_seeded_env_runners_repeat_and_differ(ray_local):
    config = race_config({**RACE, "start": "random"}, seed=3)
    first = sampled(config, 1)
    assert first == sampled(config, 1)  # same seed, same runner: the same run, actions included
    assert first != sampled(config, 2)  # another runner plays other races


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"shared": "yes"}, TypeError, "shared"),
        ({"num_env_runners": -1}, ValueError, "num_env_runners"),
        ({"seed": -3}, ValueError, "seed"),
        ({"seed": 2.0}, ValueError, "seed: must be an integer >= 0"),
        ({"num_env_runners": 1.0}, ValueError, "num_env_runners: must be an integer >= 0"),
        ({"hiddens": (64, 0)}, ValueError, "hiddens: must be an integer >= 1"),
        ({"hiddens": (64, 1.5)}, ValueError, "hiddens: must be an integer >= 1"),
        ({"hiddens": "64"}, ValueError, "hiddens: expected a tuple of layer widths"),
        ({"env_config": {"level": "nope"}}, ValueError, "level"),
    ],
)
def test_bad_config_arguments_are_clear_errors(kwargs, error, words):
    with pytest.raises(error, match=words):
        race_config(**kwargs)


def test_numpy_integer_counts_are_accepted_as_everywhere_else():
    """One rule for integer arguments (checks.check_int): numpy integers count as integers."""
    config = race_config(RACE, num_env_runners=np.int64(0), seed=np.int32(3), hiddens=(np.int64(16),))
    assert config.num_env_runners == 0 and config.seed == 3
