"""TorchRL, BenchMARL, Tianshou, SuperSuit, CleanRL-style PPO and SB3, each a short real run of the README snippet."""

from __future__ import annotations

import numpy as np
import pytest
import supersuit as ss
import torch
from conftest import readme_has
from torchrl.envs import GymEnv, GymWrapper, PettingZooWrapper, check_env_specs

import babyrobot_marl  # noqa: F401
from babyrobot_marl import race_v0
from babyrobot_marl.envs.vector import BabyRobotVectorEnv, RaceVectorEnv

SNIPPETS = ["torchrl_snippet", "benchmarl_snippet", "tianshou_snippet", "supersuit_snippet", "cleanrl_snippet", "sb3_snippet"]


@pytest.mark.parametrize("name", SNIPPETS)
def test_readme_shows_the_snippet_this_test_runs(name):
    assert readme_has(name)


def test_torchrl_snippet_runs_gym_env_vector_env_and_pettingzoo_with_a_collector(snippet):
    out = snippet("torchrl_snippet")
    assert [line for line in out.splitlines() if line.startswith("torch.Size")] == ["torch.Size([64, 4])"] * 2


def test_benchmarl_mappo_runs_its_iterations_on_the_race_task(snippet):
    assert snippet("benchmarl_snippet").strip().splitlines()[-1] == "2"


def test_tianshou_dqn_trains_and_tests_on_the_single_robot(snippet):
    assert float(snippet("tianshou_snippet").strip().splitlines()[-1]) <= 0.0  # a return: rewards are <= 0


def test_supersuit_observation_wrappers_run_on_the_box_encoding(snippet):
    lines = snippet("supersuit_snippet").strip().splitlines()
    # 3 stacked frames of 11 numbers, plus a one-hot indicator of the 4 agents, the same for every robot
    assert lines[0] == str({f"robot_{i}": (3 * 11 + 4,) for i in range(4)})
    assert lines[1] == "(8,)"


def test_cleanrl_style_loop_sees_episode_statistics(snippet):
    assert snippet("cleanrl_snippet").strip()  # at least one finished episode reported by RecordEpisodeStatistics


def test_sb3_ppo_learns_on_the_pickled_vec_env(snippet):
    snippet("sb3_snippet")


@pytest.mark.parametrize("mode", ["next-step", "same-step", "disabled"])
def test_torchrl_gym_wrapper_of_the_vector_env_rolls_out_in_every_autoreset_mode(mode):
    venv = BabyRobotVectorEnv(3, level="default", max_steps=5, autoreset_mode=mode)
    if mode == "next-step":  # TorchRL reads the mode and refuses next-step, which it cannot batch
        with pytest.raises(RuntimeError, match="auto-reset mode must be one of SAME_STEP or DISABLED"):
            GymWrapper(venv)
        return
    env = GymWrapper(venv)
    check_env_specs(env)
    rollout = env.rollout(12, break_when_any_done=False)
    assert rollout["next", "done"].any()  # episodes of 5 steps ended and restarted within 12


def test_torchrl_reads_numeric_infos_of_the_race_vector_env():
    env = GymWrapper(RaceVectorEnv(2, level="race-4", n_robots=4, obs_encoding="box", autoreset_mode="same-step"))
    check_env_specs(env)
    td = env.rollout(8)
    assert td["next", "observation"].dtype == torch.float32


def test_torchrl_gym_env_makes_the_registered_env_dropping_frameskip():
    env = GymEnv("babyrobot_marl/BabyRobotRace-v0", level="race-4", opponents=["random"] * 3, obs_encoding="onehot")
    check_env_specs(env)


@pytest.mark.parametrize("encoding", ["multidiscrete", "box", "onehot"])
@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_torchrl_pettingzoo_wrapper_passes_check_env_specs(encoding, finished):
    env = PettingZooWrapper(race_v0.parallel_env(level="race-4", n_robots=4, finished=finished, obs_encoding=encoding))
    check_env_specs(env)
    env.rollout(30, break_when_any_done=False)


@pytest.mark.parametrize("encoding", ["box", "onehot"])
def test_supersuit_vectorises_the_box_race_for_sb3(encoding):
    race = race_v0.parallel_env(level="race-4", n_robots=4, finished="freeze", obs_encoding=encoding)
    env = ss.pettingzoo_env_to_vec_env_v1(race)
    venv = ss.concat_vec_envs_v1(env, 2, num_cpus=0, base_class="stable_baselines3")
    obs = venv.reset()
    assert obs.dtype == np.float32 and obs.shape[0] == 8
