"""A Stable-Baselines3 ``VecEnv`` over a batch vector env (``babyrobot_marl.sb3_vec_env`` makes it).

A module of its own, imported only when ``sb3_vec_env`` is called: it needs stable-baselines3.
The class lives at module level so that the standard ``pickle`` (and ``copy.deepcopy``) can
find it.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import VecEnv

from .checks import check_actions, check_options, seed_list
from .vector_reset import restart, seed_envs


class BabyRobotSB3VecEnv(VecEnv):
    """A Stable-Baselines3 ``VecEnv`` over a Gymnasium batch vector env (see ``sb3_vec_env``)."""

    def __init__(self, venv: gym.vector.VectorEnv):  # a vector.BabyRobotVectorEnv or RaceVectorEnv
        self.venv_gym = venv
        self._actions: np.ndarray | None = None
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)

    def reset(self) -> np.ndarray:
        v, r = self.venv_gym, self.venv_gym.n_robots
        envs = np.arange(v.n_envs)
        seeds = [self._seeds[i * r] for i in envs]
        options = [self._options[i * r] or {} for i in envs]
        # every option checked before any change
        starts = [v._start_option(check_options(o, v._options_known)) for o in options]
        seed_envs(v._batch, list(zip(envs.tolist(), seed_list(seeds, v.n_envs))))
        restart(v._batch, envs, starts)
        v._autoreset[:] = False
        v._started = True
        self._reset_seeds()
        self._reset_options()
        self.reset_infos = [{} for _ in range(self.num_envs)]
        return v._encoded(v._observations())

    def seed(self, seed: int | None = None) -> list[int | None]:
        if seed is None:
            seed = int(np.random.randint(0, np.iinfo(np.uint32).max, dtype=np.uint32))
        r = self.venv_gym.n_robots
        self._seeds = [int(seed) + k // r for k in range(self.num_envs)]
        return list(self._seeds)

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        v = self.venv_gym
        acts = check_actions(self._actions, v.n_envs, v.n_robots)
        if not v._started:
            raise RuntimeError("step: call reset() before the first step()")
        b = v._batch
        rewards, _, _, _, over = b.step(acts)
        obs = v._encoded(v._observations())
        dones = np.repeat(over, v.n_robots)
        truncated = (over[:, None] & b.racing).reshape(-1)
        infos: list[dict[str, Any]] = [{"TimeLimit.truncated": t} for t in truncated.tolist()]
        if over.any():
            for k in np.flatnonzero(dones).tolist():
                infos[k]["terminal_observation"] = obs[k]
            b.reset_envs(np.flatnonzero(over))
            obs = v._encoded(v._observations())
        return obs, rewards.reshape(-1).astype(np.float32), dones, infos

    def close(self) -> None:
        self.venv_gym.close()

    def get_attr(self, attr_name: str, indices=None) -> list[Any]:
        """Attributes of the env each slot copies (``level``, ``render_mode``, ...): one value for all."""
        value = getattr(self.venv_gym, attr_name)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
        raise NotImplementedError("set_attr: the envs share one batch engine; make a new env with other settings")

    def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list[Any]:
        raise NotImplementedError("env_method: the envs share one batch engine and have no env objects")

    def env_is_wrapped(self, wrapper_class: type, indices=None) -> list[bool]:
        return [False for _ in self._get_indices(indices)]

    def get_images(self) -> list[np.ndarray]:
        """Each slot's env frame (``render_mode="rgb_array"``)."""
        v = self.venv_gym
        if v.render_mode != "rgb_array":
            raise ValueError(f"get_images: needs render_mode='rgb_array', got {v.render_mode!r}")
        frames = v.render()
        return [frames[k // v.n_robots] for k in range(self.num_envs)]
