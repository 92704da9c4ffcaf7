"""Tabular TD control on ``BabyRobotEnv``: Q-learning and SARSA, numpy only.

Both learn ``q[s, a]`` (states ``s = y * width + x``, the layout of ``planning.Solution.q``)
from the env's own steps. Episodes start on a random open cell (exploring starts, through
``reset(options={"start": ...})``) so every state is visited; actions are epsilon-greedy with
ties broken at random; the step size of each (s, a) is ``visits ** -alpha_power``, which
satisfies the Robbins-Monro conditions for ``0.5 < alpha_power <= 1``. A truncated episode
bootstraps from its last state (truncation is not termination).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.checks import check_int
from ..envs.single import BabyRobotEnv


@dataclass(frozen=True, eq=False)
class TabularResult:
    """``q[s, a]``, its greedy ``policy[s]`` (``int64``), the return of every episode and the steps taken."""

    q: np.ndarray
    policy: np.ndarray
    returns: np.ndarray
    steps: int


def q_learning(
    env: BabyRobotEnv, episodes: int, gamma: float = 1.0, epsilon: float = 0.8, alpha_power: float = 0.7, seed: int = 0
) -> TabularResult:
    """Off-policy TD control: ``q[s, a] += alpha * (r + gamma * max_a' q[s', a'] - q[s, a])``."""
    return _td_control(env, episodes, gamma, epsilon, alpha_power, seed, expected=False)


def sarsa(
    env: BabyRobotEnv, episodes: int, gamma: float = 1.0, epsilon: float = 0.8, alpha_power: float = 0.7, seed: int = 0
) -> TabularResult:
    """On-policy TD control: ``q[s, a] += alpha * (r + gamma * q[s', a'] - q[s, a])``, ``a'`` the
    next epsilon-greedy action. Epsilon decays as ``epsilon / sqrt(1 + episode / 100)`` so the
    learnt policy tends to the greedy optimum (GLIE)."""
    return _td_control(env, episodes, gamma, epsilon, alpha_power, seed, expected=True)


def _td_control(
    env: BabyRobotEnv, episodes: int, gamma: float, epsilon: float, alpha_power: float, seed: int, expected: bool
) -> TabularResult:
    env = getattr(env, "unwrapped", env)
    if not isinstance(env, BabyRobotEnv):
        raise TypeError(f"env: expected a BabyRobotEnv (or a wrapper of one), got {type(env).__name__}")
    check_int(episodes, "episodes", 1)
    if not 0.0 < gamma <= 1.0:
        raise ValueError(f"gamma: must be a number in (0, 1], got {gamma!r}")
    if not 0.0 <= epsilon <= 1.0:
        raise ValueError(f"epsilon: must be a number in [0, 1], got {epsilon!r}")
    if not 0.5 < alpha_power <= 1.0:
        raise ValueError(f"alpha_power: must be a number in (0.5, 1], got {alpha_power!r}")
    t = env.table
    n = t.n_cells
    reach = {t.cell_id(c) for c in t.level.cells_reaching_exit()}
    starts = [t.cell_xy(c) for c in range(n) if c in reach and not t.is_exit[c] and not t.blocked[c]]
    rng = random.Random(seed)  # Python's generator: a step's few draws cost less than numpy calls
    q = [[0.0] * N_ACTIONS for _ in range(n)]  # lists: faster than arrays for one row at a time
    visits = [[0] * N_ACTIONS for _ in range(n)]
    returns = np.zeros(episodes)
    w = t.width
    steps = 0
    actions = range(N_ACTIONS)

    def act(s: int, eps: float) -> int:
        if rng.random() < eps:
            return rng.randrange(N_ACTIONS)
        row = q[s]
        best = max(row)
        ties = [b for b in actions if row[b] == best]
        return ties[0] if len(ties) == 1 else rng.choice(ties)

    env.reset(seed=rng.randrange(2**31))
    for ep in range(episodes):
        eps = epsilon / math.sqrt(1.0 + ep / 100.0) if expected else epsilon
        obs, _ = env.reset(options={"start": starts[rng.randrange(len(starts))]})
        s = int(obs[1]) * w + int(obs[0])
        a = act(s, eps)
        done = False
        total = 0.0
        while not done:
            obs, r, terminated, truncated, _ = env.step(a)
            s2 = int(obs[1]) * w + int(obs[0])
            total += r
            steps += 1
            a2 = act(s2, eps)
            target = r if terminated else r + gamma * (q[s2][a2] if expected else max(q[s2]))
            row, count = q[s], visits[s]
            count[a] += 1
            row[a] += (target - row[a]) * count[a] ** -alpha_power
            s, a = s2, a2
            done = terminated or truncated
        returns[ep] = total
    q = np.array(q)
    policy = np.argmax(q, axis=1).astype(np.int64)
    return TabularResult(q, policy, returns, steps)
