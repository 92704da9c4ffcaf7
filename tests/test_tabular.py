"""Tabular learning from the simulator reaches the optimal policy of value iteration."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.planning import model, policy_evaluation, q_learning, sarsa, value_iteration


def greedy_is_optimal(name: str, q: np.ndarray) -> float:
    """The largest loss, over all states, of following the greedy policy of ``q`` instead of
    the optimal one (evaluated exactly on the model): 0 when the learnt policy is optimal."""
    m = model(name)
    best = value_iteration(m, gamma=1.0)
    learnt = policy_evaluation(m, np.where(m.terminal, 0, q.argmax(axis=1)), gamma=1.0, max_iterations=50_000)
    return float(np.abs(learnt.values - best.values)[~m.terminal].max())


@pytest.mark.parametrize("name", ["default", "walls", "puddles"])
def test_q_learning_reaches_the_optimal_policy(name):
    q = q_learning(BabyRobotEnv(level=name), steps=100_000, seed=0)
    assert greedy_is_optimal(name, q) < 1e-9


def test_sarsa_reaches_the_optimal_policy_on_the_default_level():
    q = sarsa(BabyRobotEnv(level="default"), steps=100_000, seed=0)
    assert greedy_is_optimal("default", q) < 1e-9


def test_too_little_learning_is_not_optimal_on_puddles():
    """The check above can fail: a few hundred steps do not find the optimal policy."""
    q = q_learning(BabyRobotEnv(level="puddles"), steps=300, seed=0)
    try:
        loss = greedy_is_optimal("puddles", q)
    except RuntimeError:  # the greedy policy never reaches the exit from some cell
        loss = float("inf")
    assert loss > 1e-9


def test_learning_is_seeded():
    a = q_learning(BabyRobotEnv(level="walls"), steps=2000, seed=3)
    b = q_learning(BabyRobotEnv(level="walls"), steps=2000, seed=3)
    c = q_learning(BabyRobotEnv(level="walls"), steps=2000, seed=4)
    assert np.array_equal(a, b) and not np.array_equal(a, c)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(steps=0), "steps"),
        (dict(gamma=2.0), "gamma"),
        (dict(epsilon=-0.1), "epsilon"),
        (dict(alpha_decay=0.2), "alpha_decay"),
    ],
)
def test_bad_arguments_are_value_errors_naming_them(kwargs, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        q_learning(BabyRobotEnv(level="default"), **kwargs)
