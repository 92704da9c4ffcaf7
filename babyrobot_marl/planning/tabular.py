"""Tabular learning from the simulator: Q-learning and SARSA on a ``BabyRobot-v0`` env.

The learner sees only what the env returns (observations ``[x, y]``, rewards, terminations);
the model is not used. Exploring starts (each episode begins on a random open cell drawn
from the learner's own seeded generator) make every state visited; the step size of each
``(s, a)`` decays as ``1 / n(s, a) ** alpha_decay`` so the estimates settle even where
puddles make the steps random.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS


def q_learning(
    env: Any, steps: int = 100_000, gamma: float = 1.0, epsilon: float = 0.2, alpha_decay: float = 0.7, seed: int = 0
) -> np.ndarray:
    """``Q[s, a]`` learnt by Q-learning (off-policy: the target is ``max_a' Q(s', a')``)."""
    return _learn(env, steps, gamma, epsilon, alpha_decay, seed, sarsa=False)


def sarsa(
    env: Any, steps: int = 100_000, gamma: float = 1.0, epsilon: float = 0.2, alpha_decay: float = 0.7, seed: int = 0
) -> np.ndarray:
    """``Q[s, a]`` learnt by SARSA (on-policy: the target is ``Q(s', a')`` of the next action taken).

    Exploration fades linearly from ``epsilon`` to 0 over the steps (greedy in the limit), so
    the values learnt become those of the greedy policy rather than of an exploring one."""
    return _learn(env, steps, gamma, epsilon, alpha_decay, seed, sarsa=True)


def _check(steps: int, gamma: float, epsilon: float, alpha_decay: float) -> None:
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise ValueError(f"steps: must be a positive integer, got {steps!r}")
    bounds = (("gamma", gamma, 0.0, 1.0), ("epsilon", epsilon, 0.0, 1.0), ("alpha_decay", alpha_decay, 0.5, 1.0))
    for name, value, lo, hi in bounds:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= value <= hi:
            raise ValueError(f"{name}: must be a number in [{lo}, {hi}], got {value!r}")


def _learn(env: Any, steps: int, gamma: float, epsilon: float, alpha_decay: float, seed: int, sarsa: bool) -> np.ndarray:
    _check(steps, gamma, epsilon, alpha_decay)
    u = env.unwrapped
    width, n_states = u.level.width, u.table.n_cells
    starts = [tuple(c) for c in u.level.free_cells() if not u.table.is_exit[u.table.cell_id(c)]]
    rng = np.random.default_rng(seed)
    q = np.zeros((n_states, N_ACTIONS))
    visits = np.zeros((n_states, N_ACTIONS))

    eps = epsilon

    def act(s: int) -> int:
        if rng.random() < eps:
            return int(rng.integers(N_ACTIONS))
        best = np.flatnonzero(q[s] == q[s].max())
        return int(best[rng.integers(len(best))])  # ties broken at random: no bias to low actions

    def begin() -> tuple[int, int]:
        start = starts[int(rng.integers(len(starts)))]
        obs, _ = env.reset(options={"start": start})
        s = int(obs[1]) * width + int(obs[0])
        return s, act(s)

    env.reset(seed=seed)
    s, a = begin()
    for t in range(steps):
        if sarsa:
            eps = epsilon * (1.0 - t / steps)
        obs, reward, terminated, truncated, _ = env.step(a)
        s2 = int(obs[1]) * width + int(obs[0])
        a2 = act(s2)
        target = reward if terminated else reward + gamma * (q[s2, a2] if sarsa else q[s2].max())
        visits[s, a] += 1
        q[s, a] += (target - q[s, a]) / visits[s, a] ** alpha_decay
        if terminated or truncated:
            s, a = begin()
        else:
            s, a = s2, a2
    return q
