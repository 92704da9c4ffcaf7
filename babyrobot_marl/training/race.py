"""One shared PPO policy for every robot of the race, trained through SuperSuit, and judged
against scripted opponents.

The vector env is SuperSuit's ``pettingzoo_env_to_vec_env_v1`` over ``race_v0.parallel_env(
finished="freeze")`` (every agent present at every step, as that wrapper needs) and
``concat_vec_envs_v1(..., base_class="stable_baselines3")``. Three pitfalls of SuperSuit 3.11
are handled here:

1. ``concat_vec_envs_v1`` copies the env with cloudpickle, generator state included, so every copy
   plays the same episodes unless it is seeded after vectorising. ``SuperSuitRaceVecEnv`` seeds
   every ``reset()``: copy ``i`` gets ``seed + i`` (a fresh entropy seed when none was given).
2. ``PPO(seed=...)`` calls ``env.seed``, which SuperSuit's SB3 wrapper forwards to its
   ``ConcatVecEnv``, which has none (``'ConcatVecEnv' object has no attribute 'seed'``).
   ``SuperSuitRaceVecEnv.seed`` stores the seed for the next ``reset()`` instead.
3. ``MarkovVectorEnv`` folds truncation into ``done`` and never sets ``TimeLimit.truncated``, so
   SB3 would treat a race cut off at ``max_cycles`` as a true end. ``TruncationInfo`` (a
   PettingZoo wrapper under SuperSuit) puts ``infos[agent]["TimeLimit.truncated"]`` on every
   step: True exactly for robots truncated (not terminated) by the end of the race.

``make_race_vec_env(..., backend="native")`` gives the same view from the batch engine
(``babyrobot_marl.sb3_vec_env(n_robots=...)``), much faster; SuperSuit stays the default as
the reference path.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import policies
from ..core.checks import check_int
from ..core.level import Level
from ..envs.race import RaceEnv
from .deps import require_train
from .single import make_algo

DEFAULT_RACE_LEVEL = "race-4"
RACE_PPO_KWARGS: dict[str, Any] = {"n_steps": 256, "batch_size": 512, "learning_rate": 1e-3, "ent_coef": 0.01}


def _truncation_info_wrapper() -> type:
    from pettingzoo.utils.wrappers import BaseParallelWrapper

    class TruncationInfo(BaseParallelWrapper):
        """Adds ``infos[agent]["TimeLimit.truncated"]`` (truncated and not terminated) to each step."""

        def step(self, actions):
            obs, rewards, terms, truncs, infos = self.env.step(actions)
            for agent, info in infos.items():
                info["TimeLimit.truncated"] = bool(truncs.get(agent, False) and not terms.get(agent, False))
            return obs, rewards, terms, truncs, infos

    return TruncationInfo


def _sb3_wrapper_class() -> type:
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class SuperSuitRaceVecEnv(VecEnvWrapper):
        """SuperSuit's SB3 vec env with seeding that works (see the module docstring)."""

        def __init__(self, venv: Any, seed: int | None):
            super().__init__(venv)
            self._seed = seed

        def seed(self, seed: int | None = None) -> list[int | None]:
            self._seed = seed
            per_race = self.num_envs // len(self.concat.vec_envs)  # slots per race (its robots)
            return [None if seed is None else seed + k // per_race for k in range(self.num_envs)]

        @property
        def concat(self) -> Any:
            return self.venv.venv  # SB3VecEnvWrapper -> ConcatVecEnv

        def reset(self) -> np.ndarray:
            seed = self._seed if self._seed is not None else int.from_bytes(os.urandom(4), "little")
            self._seed = None  # later resets go on from each copy's own generator
            obs, self.reset_infos = self.concat.reset(seed=seed)  # copy i: seed + i
            return obs

        def step_wait(self):
            return self.venv.step_wait()

    return SuperSuitRaceVecEnv


def make_race_vec_env(
    level: str | Level = DEFAULT_RACE_LEVEL, n_robots: int = 4, n_envs: int = 4, seed: int | None = 0, backend: str = "supersuit",
    **race_kwargs: Any,
) -> Any:
    """An SB3 ``VecEnv`` of ``n_envs`` races of ``n_robots`` robots (``n_envs * n_robots`` slots,
    one shared policy), finished robots frozen until the race ends. ``race_kwargs`` go to
    ``race_v0.parallel_env`` (``collisions``, ``max_cycles``, ``start``, ...)."""
    if backend == "native":
        from ..envs.vector import sb3_vec_env

        venv = sb3_vec_env(level, n_envs=n_envs, n_robots=n_robots, **race_kwargs)
        venv.seed(seed)
        return venv
    if backend != "supersuit":
        raise ValueError(f"backend: must be 'supersuit' or 'native', got {backend!r}")
    (ss,) = require_train("supersuit")
    require_train("stable_baselines3")
    env = _truncation_info_wrapper()(RaceEnv(level=level, n_robots=n_robots, finished="freeze", **race_kwargs))
    vec = ss.pettingzoo_env_to_vec_env_v1(env)
    with warnings.catch_warnings():  # SB3 asks SuperSuit's vector env for a render_mode it never had: not ours to set
        warnings.filterwarnings("ignore", message="The `render_mode` attribute is not defined", category=UserWarning)
        vec = ss.concat_vec_envs_v1(vec, n_envs, num_cpus=0, base_class="stable_baselines3")
        return _sb3_wrapper_class()(vec, seed)


def train_race(
    level: str | Level = DEFAULT_RACE_LEVEL,
    n_robots: int = 4,
    steps: int = 300_000,
    seed: int = 0,
    n_envs: int = 4,
    backend: str = "supersuit",
    progress_bar: bool = False,
    callback: Any = None,
    race_kwargs: dict[str, Any] | None = None,
    threads: int | None = 1,
    **ppo_kwargs: Any,
) -> Any:
    """Train one PPO policy shared by all robots; returns the SB3 model. Robots start on random
    free cells (``start="random"``) unless ``race_kwargs`` say otherwise. ``threads``: torch threads
    while training (default 1: more stall for minutes on a busy machine; None: torch's setting)."""
    from .ppo.loop import torch_threads

    check_int(steps, "steps", 1)
    venv = make_race_vec_env(level, n_robots, n_envs, seed, backend, **{"start": "random", **(race_kwargs or {})})
    with torch_threads(threads):
        agent = make_algo("ppo", venv, seed, **{**RACE_PPO_KWARGS, **ppo_kwargs})
        agent.learn(total_timesteps=int(steps), progress_bar=progress_bar, callback=callback)
    return agent


@dataclass(frozen=True)
class RaceResult:
    """The learnt robot against scripted opponents: races won (rank 1, ties included), its mean
    finishing steps (over races it finished) and the opponents', and the ties among the wins
    (another robot finished first in the same step)."""

    races: int
    wins: int
    finished: int
    mean_steps: float
    opponent_mean_steps: float
    ties: int = 0

    @property
    def win_rate(self) -> float:
        return self.wins / self.races

    @property
    def tie_rate(self) -> float:
        return self.ties / self.races


def evaluate_race(
    agent: Any,
    level: str | Level = DEFAULT_RACE_LEVEL,
    n_robots: int = 4,
    opponent: str = "random",
    races: int = 100,
    seed: int = 0,
    **race_kwargs: Any,
) -> RaceResult:
    """``races`` races (seeds ``seed + i``): robot_0 acts with ``agent.predict`` (deterministic),
    the others with the scripted ``opponent`` policy ("random" or "shortest")."""
    if opponent not in policies.POLICY_NAMES:
        raise ValueError(f"opponent: must be one of {', '.join(policies.POLICY_NAMES)}, got {opponent!r}")
    env = RaceEnv(level=level, n_robots=n_robots, **{"start": "random", **race_kwargs})
    wins = finished = ties = 0
    steps, other_steps = [], []
    for i in range(races):
        obs, _ = env.reset(seed=seed + i)
        others = [policies.make(opponent, env.table, seed=seed * 7919 + i * 31 + k) for k in range(n_robots)]
        finish = [0] * n_robots  # the step each robot finished in (0: not finished)
        while env.agents:
            actions = {}
            for a in env.agents:
                k = env.possible_agents.index(a)
                actions[a] = int(agent.predict(obs[a], deterministic=True)[0]) if k == 0 else others[k](obs[a])
            obs, _, _, _, infos = env.step(actions)
            for a, info in infos.items():
                if info.get("rank"):
                    finish[env.possible_agents.index(a)] = env.elapsed_steps
        wins += env.ranks[0] == 1
        ties += env.ranks[0] == 1 and 1 in env.ranks[1:]
        if finish[0]:
            finished += 1
            steps.append(finish[0])
        other_steps += [f for f in finish[1:] if f]
    return RaceResult(races, wins, finished, float(np.mean(steps)) if steps else float("nan"),
                      float(np.mean(other_steps)) if other_steps else float("nan"), ties)



def race_near_features_class() -> type:
    """An SB3 features extractor giving a race robot's observation the fast trainer's input
    (``training.ppo.Inputs``): the one-hot of its own cell, then one bit per cell of ``near``
    (offsets), set when a racing robot stands there (``W * H + len(near)`` floats).

    SB3 one-hot encodes each ``MultiDiscrete`` entry; this decodes them back to positions. With it,
    SB3 PPO and ``training.ppo`` train the same network on the same input (``bench_train.py``).
    """
    (th,) = require_train("torch")
    from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

    class RaceNearFeatures(BaseFeaturesExtractor):
        def __init__(self, observation_space: Any, width: int, height: int, n_robots: int, near: tuple[tuple[int, int], ...]):
            super().__init__(observation_space, features_dim=width * height + len(near))
            self.width, self.height, self.n_robots = width, height, n_robots
            self.register_buffer("near", th.as_tensor(near, dtype=th.long).reshape(-1, 2), persistent=False)

        def forward(self, obs: Any) -> Any:
            w, h = self.width, self.height

            def xy(at: int) -> tuple[Any, Any]:
                return obs[:, at : at + w].argmax(dim=1), obs[:, at + w : at + w + h].argmax(dim=1)

            x, y = xy(0)
            own = th.nn.functional.one_hot(y * w + x, w * h).float()
            bits = th.zeros(obs.shape[0], self.near.shape[0])
            at = w + h
            for _ in range(self.n_robots - 1):
                ox, oy = xy(at)
                racing = obs[:, at + w + h] > 0.5  # the one-hot of finished == 0
                there = (ox[:, None] == x[:, None] + self.near[:, 0]) & (oy[:, None] == y[:, None] + self.near[:, 1])
                bits = th.maximum(bits, (there & racing[:, None]).float())
                at += w + h + 2
            return th.cat([own, bits], dim=1)

    return RaceNearFeatures
