"""Deep RL for one robot: Stable-Baselines3 PPO or DQN on ``BabyRobot-v0``, judged against value iteration.

Training runs on ``babyrobot_marl.sb3_vec_env`` (the batch engine as an SB3 ``VecEnv``: ``n_envs``
copies seeded ``seed + i``). Evaluation plays whole episodes on a plain ``BabyRobotEnv``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.checks import check_int
from ..core.level import Level
from ..envs.single import BabyRobotEnv
from ..planning import model, value_iteration
from .deps import require_train

ALGOS = ("ppo", "dqn")
DEFAULT_LEVEL = "maze-8x8"

# Settings that learn an 8x8 level within the benchmark's budget (see benchmarks/bench_learning.py).
ALGO_KWARGS: dict[str, dict[str, Any]] = {
    "ppo": {"n_steps": 128, "batch_size": 256, "n_epochs": 10, "learning_rate": 1e-3, "gamma": 0.99, "ent_coef": 0.01},
    "dqn": {"learning_rate": 1e-3, "buffer_size": 50_000, "learning_starts": 1000, "train_freq": 4,
            "target_update_interval": 500, "exploration_fraction": 0.3, "exploration_final_eps": 0.05, "gamma": 0.99},
}


@dataclass(frozen=True)
class Evaluation:
    """Mean and standard deviation of the return over ``episodes`` evaluation episodes, and how
    many reached the exit."""

    mean: float
    std: float
    episodes: int
    reached_exit: int


def optimal_return(env: BabyRobotEnv) -> float:
    """The best expected return from the env's start (the mean over its random starts if it has no
    fixed one), from value iteration on the exact model."""
    env = getattr(env, "unwrapped", env)
    values = value_iteration(model(env)).values
    t = env.table
    if env.random_start:
        return float(np.mean([values[c] for c in env._free]))
    return float(values[t.cell_id(env.level.starts[0])])


def within(ret: float, optimum: float, fraction: float = 0.95) -> bool:
    """``ret`` reaches ``fraction`` of the optimum: for the (negative) returns of Baby Robot,
    no more than ``(1 - fraction) * |optimum|`` below it."""
    return ret >= optimum - (1.0 - fraction) * abs(optimum)


FEATURES = ("cell", "xy")


def cell_features_class() -> type:
    """An SB3 features extractor: the robot's cell as one one-hot of ``width * height``.

    SB3 turns a ``MultiDiscrete([W, H])`` observation into a one-hot of ``x`` beside a one-hot of
    ``y``; an MLP must then learn each cell as a conjunction of the two. One one-hot per cell
    makes a maze's policy a table lookup: PPO reaches the optimum of maze-8x8 in 45k-60k
    timesteps with it, and not within 100k without it (benchmarks/bench_learning.py).
    """
    (th,) = require_train("torch")
    from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

    class CellFeatures(BaseFeaturesExtractor):
        def __init__(self, observation_space: Any, width: int, height: int):
            super().__init__(observation_space, features_dim=width * height)
            self.width, self.height = width, height

        def forward(self, obs: Any) -> Any:
            x = obs[:, : self.width].argmax(dim=1)
            y = obs[:, self.width : self.width + self.height].argmax(dim=1)
            return th.nn.functional.one_hot(y * self.width + x, self.width * self.height).float()

    return CellFeatures


def make_algo(algo: str, venv: Any, seed: int, verbose: int = 0, **overrides: Any) -> Any:
    """A Stable-Baselines3 ``PPO`` or ``DQN`` with ``ALGO_KWARGS[algo]`` and ``overrides``."""
    if algo not in ALGOS:
        raise ValueError(f"algo: must be one of {', '.join(map(repr, ALGOS))}, got {algo!r}")
    (sb3,) = require_train("stable_baselines3")
    cls = sb3.PPO if algo == "ppo" else sb3.DQN
    return cls("MlpPolicy", venv, seed=seed, verbose=verbose, device="cpu", **{**ALGO_KWARGS[algo], **overrides})


def train_single(
    level: str | Level = DEFAULT_LEVEL,
    algo: str = "ppo",
    steps: int = 100_000,
    seed: int = 0,
    n_envs: int = 8,
    progress_bar: bool = False,
    callback: Any = None,
    env_kwargs: dict[str, Any] | None = None,
    features: str = "cell",
    threads: int | None = 1,
    **algo_kwargs: Any,
) -> Any:
    """Train PPO or DQN for ``steps`` timesteps on ``n_envs`` copies of ``BabyRobot-v0`` on ``level``;
    returns the SB3 model. ``env_kwargs`` go to ``BabyRobotEnv`` (``max_steps``, rules, ...).
    ``features``: ``"cell"`` (one one-hot per cell, ``cell_features_class``) or ``"xy"`` (SB3's
    own one-hots of ``x`` and ``y``). ``threads``: torch threads while training (default 1: more
    stall for minutes on a busy machine; None: torch's setting), restored afterwards."""
    from ..envs.vector import sb3_vec_env
    from .ppo.loop import torch_threads

    check_int(steps, "steps", 1)
    if features not in FEATURES:
        raise ValueError(f"features: must be one of {', '.join(map(repr, FEATURES))}, got {features!r}")
    (sb3,) = require_train("stable_baselines3")
    # VecMonitor: SB3 keeps the training episodes' returns (ep_info_buffer) only from its "episode" infos
    venv = sb3.common.vec_env.VecMonitor(sb3_vec_env(level, n_envs=1 if algo == "dqn" else n_envs, **(env_kwargs or {})))
    if features == "cell" and "policy_kwargs" not in algo_kwargs:
        w, h = (int(n) for n in venv.observation_space.nvec)
        algo_kwargs["policy_kwargs"] = {
            "features_extractor_class": cell_features_class(),
            "features_extractor_kwargs": {"width": w, "height": h},
        }
    with torch_threads(threads):
        agent = make_algo(algo, venv, seed, **algo_kwargs)
        agent.learn(total_timesteps=int(steps), progress_bar=progress_bar, callback=callback)
    return agent


def evaluate_single(agent: Any, env: BabyRobotEnv, episodes: int = 20, seed: int = 0, deterministic: bool = True) -> Evaluation:
    """Play ``episodes`` episodes (seeds ``seed``, ``seed + 1``, ...) with ``agent.predict``."""
    returns, reached = [], 0
    for i in range(episodes):
        obs, _ = env.reset(seed=seed + i)
        total, done = 0.0, False
        while not done:
            action, _ = agent.predict(obs, deterministic=deterministic)
            obs, r, terminated, truncated, _ = env.step(int(action))
            total += r
            done = terminated or truncated
        returns.append(total)
        reached += bool(terminated)
    return Evaluation(float(np.mean(returns)), float(np.std(returns)), episodes, reached)
