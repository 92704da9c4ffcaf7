"""The planning model against the simulator, and the dynamic-programming algorithms against
independent answers (BFS distances, a linear solve, the Bellman equations)."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv, Rules, compile_level, levels
from babyrobot_marl.cli import main as cli_main
from babyrobot_marl.core.actions import N_ACTIONS
from babyrobot_marl.core.model import transition_arrays
from babyrobot_marl.planning import model, policy_evaluation, policy_iteration, q_from_values, value_iteration
from tests.strategies import exit_distances

Z = 5.5  # a deviation this many standard deviations off: false alarm about 4e-8 per comparison


@pytest.mark.parametrize("name", ["puddles", "glass"])
def test_empirical_transitions_of_the_simulator_match_the_model(name):
    """Every state and action, stepped 2,000 times through the env from a seeded reset: the
    frequencies of the next cells match p(s' | s, a), and each reward is the reward of s'."""
    m = model(name)
    env = BabyRobotEnv(level=name)
    env.reset(seed=12345)
    w, n = env.level.width, 2000
    P, _ = m.dense()
    rewards = m.table.reward
    for s in np.flatnonzero(~m.terminal):
        start = (int(s % w), int(s // w))
        for a in range(N_ACTIONS):
            counts = np.zeros(m.n_states)
            for _ in range(n):
                env.reset(options={"start": start})
                obs, r, *_ = env.step(a)
                s2 = int(obs[1]) * w + int(obs[0])
                counts[s2] += 1
                assert r == rewards[s2]
            p = P[s, a]
            bound = Z * np.sqrt(n * p * (1 - p)) + 1.0
            assert (np.abs(counts - n * p) <= bound).all(), (name, start, a, counts, n * p)
            assert counts[p == 0].sum() == 0  # never a next cell the model says is impossible


@pytest.mark.parametrize("name", ["default", "puddles", "glass", "mixed-8x8", "race-2"])
def test_dense_model_is_a_distribution_and_agrees_with_the_core_tables(name):
    m = model(name)
    P, R = m.dense()
    assert np.allclose(P.sum(axis=2), 1.0) and (P >= 0).all()
    P_core, R_core = transition_arrays(m.table)
    assert np.allclose(P, P_core) and np.allclose(R, R_core)


def test_the_frozenlake_style_dict_of_the_env_agrees_with_the_model():
    env = BabyRobotEnv(level="mixed-8x8")
    m = model(env)
    P, _ = m.dense()
    for s, by_action in env.P.items():
        for a, outcomes in by_action.items():
            got = np.zeros(m.n_states)
            for p, s2, _, _ in outcomes:
                got[s2] += p
            assert np.allclose(got, P[s, a])


@pytest.mark.parametrize("name", ["default", "walls", "maze-8x8", "maze-64x64"])
def test_values_on_deterministic_levels_are_minus_the_steps_before_the_exit(name):
    """Reward -1 per step and 0 for the step into the exit: v(s) = -(d(s) - 1), d from a BFS."""
    level = levels.get(name)
    sol = value_iteration(model(level), gamma=1.0)
    for (x, y), d in exit_distances(level).items():
        expected = 0.0 if d == 0 else -(d - 1)
        assert sol.value_grid[y, x] == pytest.approx(expected), (x, y)


@pytest.mark.parametrize("name", ["puddles", "glass", "mixed-8x8"])
@pytest.mark.parametrize("gamma", [1.0, 0.9])
def test_value_iteration_solves_the_bellman_optimality_equations(name, gamma):
    m = model(name)
    sol = value_iteration(m, gamma=gamma, theta=1e-11)
    P, R = m.dense()
    q = R + gamma * P @ np.where(m.terminal, 0.0, sol.values)
    q[m.terminal] = 0.0
    assert np.allclose(sol.values, np.where(m.terminal, 0.0, q.max(axis=1)), atol=1e-8)
    assert np.allclose(sol.q, q, atol=1e-8)


@pytest.mark.parametrize("name", ["puddles", "glass", "mixed-8x8"])
def test_policy_iteration_reaches_the_values_of_value_iteration(name):
    m = model(name)
    assert np.allclose(policy_iteration(m, gamma=1.0).values, value_iteration(m, gamma=1.0).values, atol=1e-6)
    assert np.allclose(policy_iteration(m, gamma=0.8).values, value_iteration(m, gamma=0.8).values, atol=1e-6)


def test_policy_evaluation_equals_a_linear_solve():
    """(I - gamma P_pi) v = r_pi on the non-terminal states, for a random stochastic policy."""
    m = model("mixed-8x8")
    rng = np.random.default_rng(0)
    pi = rng.random((m.n_states, N_ACTIONS))
    pi /= pi.sum(axis=1, keepdims=True)
    gamma = 0.9
    sol = policy_evaluation(m, pi, gamma=gamma, theta=1e-12)
    P, R = m.dense()
    P_pi = np.einsum("sa,sat->st", pi, P)
    r_pi = (pi * R).sum(axis=1)
    live = ~m.terminal
    A = np.eye(live.sum()) - gamma * P_pi[np.ix_(live, live)]
    v = np.linalg.solve(A, r_pi[live])
    assert np.allclose(sol.values[live], v, atol=1e-8)


def test_a_policy_that_never_reaches_the_exit_has_no_value_at_gamma_one():
    m = model("walls")
    with pytest.raises(RuntimeError, match="gamma < 1"):
        policy_evaluation(m, np.zeros(m.n_states, dtype=np.int64), gamma=1.0, max_iterations=2000)
    stay = policy_evaluation(m, np.zeros(m.n_states, dtype=np.int64), gamma=0.5)
    assert np.allclose(stay.values[~m.terminal], -1.0 / (1 - 0.5))  # -1 forever, discounted


def test_solution_grids_mark_blocked_cells_and_exits():
    level = levels.get("blocked")
    sol = value_iteration(model(level))
    for x, y in level.blocked:
        assert np.isnan(sol.value_grid[y, x]) and sol.policy_grid[y, x] == -1
        assert not sol.best_actions[y, x].any()
    for x, y in level.exits:
        assert sol.value_grid[y, x] == 0.0 and sol.policy_grid[y, x] == -1
    ys, xs = np.nonzero(sol.policy_grid >= 0)
    assert sol.best_actions[ys, xs, sol.policy_grid[ys, xs]].all()  # the greedy action is among the best


def test_the_model_follows_the_rules_given():
    slippery = model("puddles", rules=Rules(small_puddle_move_prob=0.1, large_puddle_move_prob=0.1))
    plain = model("puddles")
    assert not np.allclose(slippery.prob, plain.prob)
    env = BabyRobotEnv(level="puddles", small_puddle_move_prob=0.1, large_puddle_move_prob=0.1)
    assert np.allclose(model(env).prob, slippery.prob)
    with pytest.raises(ValueError, match="^rules"):
        model(env, rules=Rules())


def test_q_from_values_of_the_optimal_values_is_the_solution_q():
    m = model("glass")
    sol = value_iteration(m, gamma=0.95)
    assert np.allclose(q_from_values(m, sol.values, 0.95), sol.q)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda m: value_iteration(m, gamma=1.5), "gamma"),
        (lambda m: value_iteration(m, gamma=True), "gamma"),
        (lambda m: value_iteration(m, theta=0), "theta"),
        (lambda m: value_iteration(m, max_iterations=0), "max_iterations"),
        (lambda m: policy_evaluation(m, np.zeros(3, dtype=np.int64)), "policy"),
        (lambda m: policy_evaluation(m, np.full(m.n_states, 7)), "policy"),
        (lambda m: policy_evaluation(m, np.full((m.n_states, 5), 0.5)), "policy"),
        (lambda m: model(3.5), "source"),
    ],
)
def test_bad_arguments_are_value_errors_naming_them(call, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        call(model("walls"))


def test_cli_solve_prints_the_values_and_the_arrows(capsys):
    assert cli_main(["solve", "--level", "default"]) == 0
    out = capsys.readouterr().out
    sol = value_iteration(model("default"))
    assert f"{sol.value_grid[0, 0]:.2f}" in out and ("→" in out or "↓" in out)
    assert "E" in out.split("policy")[1]
    with pytest.raises(SystemExit) as bad:
        cli_main(["solve", "--level", "default", "--gamma", "1.5"])
    assert bad.value.code == 2 and "--gamma" in capsys.readouterr().err


def test_compile_level_and_model_share_the_table_layout():
    t = compile_level(levels.get("mixed-8x8"))
    m = model("mixed-8x8")
    assert np.array_equal(m.table.target, t.target) and m.shape == (8, 8)
