"""Tabular Q-learning and SARSA reach the optimal policy of value iteration (seeded, short runs)."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.planning import model, value_iteration
from babyrobot_marl.training import q_learning, sarsa


def optimal_everywhere(env: BabyRobotEnv, policy: np.ndarray) -> np.ndarray:
    """For each cell with a choice: is the learnt action one of value iteration's best (ties allowed)?"""
    sol = value_iteration(model(env))
    best = sol.best_actions.reshape(-1, 5)
    return best[np.arange(len(policy)), policy][sol.active]


@pytest.mark.parametrize(("level", "episodes"), [("default", 500), ("walls", 3000), ("puddles", 15000)])
def test_q_learning_learns_the_optimal_policy(level, episodes):
    env = BabyRobotEnv(level=level)
    res = q_learning(env, episodes, seed=0)
    ok = optimal_everywhere(env, res.policy)
    assert ok.all(), f"{np.count_nonzero(~ok)} of {ok.size} cells not optimal"
    sol = value_iteration(model(env))
    np.testing.assert_allclose(res.q.max(axis=1)[sol.active], sol.values[sol.active], atol=0.5)


@pytest.mark.parametrize(("level", "episodes"), [("default", 1000), ("walls", 6000)])
def test_sarsa_learns_the_optimal_policy_on_deterministic_levels(level, episodes):
    env = BabyRobotEnv(level=level)
    res = sarsa(env, episodes, epsilon=0.5, alpha_power=0.6, seed=0)
    assert optimal_everywhere(env, res.policy).all()


def test_an_untrained_agent_is_not_optimal_so_the_check_can_fail():
    env = BabyRobotEnv(level="walls")
    res = q_learning(env, 3, seed=0)
    assert not optimal_everywhere(env, res.policy).all()


def test_same_seed_same_learning_and_different_seeds_differ():
    a = q_learning(BabyRobotEnv(level="puddles"), 200, seed=3)
    b = q_learning(BabyRobotEnv(level="puddles"), 200, seed=3)
    c = q_learning(BabyRobotEnv(level="puddles"), 200, seed=4)
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.returns, b.returns)
    assert not np.array_equal(a.q, c.q)
    assert a.returns.shape == (200,) and a.steps >= 200


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"episodes": 0}, "episodes"), ({"episodes": 2.5}, "episodes"), ({"gamma": 0.0}, "gamma"),
     ({"epsilon": 1.5}, "epsilon"), ({"alpha_power": 0.3}, "alpha_power")],
)
def test_bad_arguments_are_value_errors_naming_them(kwargs, match):
    args = {"episodes": 10, **kwargs}
    with pytest.raises(ValueError, match=match):
        q_learning(BabyRobotEnv(), **args)
    with pytest.raises(TypeError, match="env"):
        q_learning("default", 10)
