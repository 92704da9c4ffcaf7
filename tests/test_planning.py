"""Planning: the sparse model against the reference outcomes and the simulator; DP against exact solutions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from babyrobot_marl import Action, BabyRobotEnv, Level, Rules, levels
from babyrobot_marl.core import compile_level, outcomes
from babyrobot_marl.planning import model, policy_evaluation, policy_iteration, policy_text, value_iteration, value_text
from babyrobot_marl.policies.shortest import distances

RULE_SETS = [
    Rules(),
    Rules(small_puddle_move_prob=0.3, large_puddle_move_prob=0.9, glass_pass_prob=0.2),
    Rules(small_puddle_move_prob=0.0, large_puddle_move_prob=1.0, glass_pass_prob=1.0),
]

# (1, 1) is closed in by walls: no exit can be reached from it.
ENCLOSED = """
+-+-+-+
|S    |
+ +-+ +
| | | |
+ +-+ +
|    E|
+-+-+-+
"""


@pytest.mark.parametrize("rules", RULE_SETS, ids=["default", "odd", "extreme"])
@pytest.mark.parametrize("name", levels.names())
def test_sparse_model_holds_exactly_the_reference_outcomes(name, rules):
    m = model(name, rules)
    t = m.table
    assert m.next.shape == m.prob.shape == m.reward.shape == (t.n_cells, 5, m.next.shape[2])
    for c in range(t.n_cells):
        for a in range(5):
            got = {int(s): p for s, p in zip(m.next[c, a], m.prob[c, a]) if p > 0}
            want = {c: 1.0} if m.terminal[c] else outcomes(t, c, a)
            assert got.keys() == want.keys(), (c, a)
            for s in want:
                assert got[s] == pytest.approx(want[s], abs=1e-12)
                k = list(m.next[c, a]).index(s)
                assert m.reward[c, a, k] == (0.0 if m.terminal[c] else t.reward[s])


def _binomial_surprise(k: np.ndarray, n: int, p: np.ndarray) -> np.ndarray:
    """``n * KL(k/n || p)``: by the Chernoff bound, P(surprise >= x) <= 2 exp(-x) for a binomial count."""
    q = k / n
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(q > 0, q * np.log(q / p), 0.0)
        b = np.where(q < 1, (1 - q) * np.log((1 - q) / (1 - p)), 0.0)
    return n * (a + b)


def _worst_surprise(env: BabyRobotEnv, P: dict, n: int = 3000) -> float:
    """Step ``env`` from every open cell with every action, seeded, and compare with ``P``.

    Returns the largest binomial surprise of any (cell, action, next cell) count divided by the
    Chernoff limit at a false-alarm rate of 1e-9 over all counts (union bound): <= 1 passes.
    Every sampled reward and ``terminated`` must be the model's exactly.
    """
    t = env.table
    env.reset(seed=1234)
    rows = [(c, a) for c in range(t.n_cells) if not (t.is_exit[c] or t.blocked[c]) for a in range(5)]
    limit = math.log(2 * sum(len(P[c][a]) for c, a in rows) / 1e-9)
    worst = 0.0
    for c, a in rows:
        start = t.cell_xy(c)
        table = {s: (p, r, done) for p, s, r, done in P[c][a]}
        draws = n if len(table) > 1 else 30
        counts = dict.fromkeys(table, 0)
        for _ in range(draws):
            env.reset(options={"start": start})  # the env's generator goes on: a fresh draw each time
            obs, r, terminated, _, _ = env.step(a)
            s = t.cell_id((int(obs[0]), int(obs[1])))
            assert s in table, (start, Action(a), t.cell_xy(s))
            assert (r, terminated) == table[s][1:], (start, Action(a))
            counts[s] += 1
        k = np.array(list(counts.values()))
        p = np.array([table[s][0] for s in counts])
        worst = max(worst, float(_binomial_surprise(k, draws, p).max()) / limit)
    return worst


@pytest.mark.parametrize("name", ["puddles", "glass", "mixed-8x8"])
def test_simulator_step_frequencies_match_the_model(name):
    """For every open cell and action: env.step from that cell, seeded, against ``env.unwrapped.P``."""
    env = BabyRobotEnv(level=name, glass_pass_prob=0.35)
    assert _worst_surprise(env, env.unwrapped.P) <= 1.0


@pytest.mark.parametrize(("name", "wrong"), [("glass", {"glass_pass_prob": 0.45}), ("puddles", {"small_puddle_move_prob": 0.5})])
def test_the_frequency_check_catches_a_model_off_by_a_tenth(name, wrong):
    env = BabyRobotEnv(level=name, glass_pass_prob=0.35)
    assert _worst_surprise(env, BabyRobotEnv(level=name, **{"glass_pass_prob": 0.35, **wrong}).P) > 1.0


def _greedy_exact_values(m, policy):
    """Solve ``v = r_pi + P_pi v`` on the non-terminal cells by a dense linear solve."""
    P, R = m.dense
    live = ~m.terminal
    idx = np.flatnonzero(live)
    P_pi = P[idx, policy[idx]][:, idx]
    r_pi = R[idx, policy[idx]]
    v = np.zeros(m.n_states)
    v[idx] = np.linalg.solve(np.eye(len(idx)) - P_pi, r_pi)
    return v


@pytest.mark.parametrize("name", ["default", "walls", "puddles", "glass", "blocked", "mixed-8x8", "race-4"])
def test_value_iteration_satisfies_bellman_optimality_and_agrees_with_policy_iteration(name):
    m = model(name)
    P, R = m.dense
    vi = value_iteration(m, theta=1e-12)
    pi = policy_iteration(m, theta=1e-12)
    live = ~m.terminal
    backup = (R + P @ vi.values).max(axis=1)
    np.testing.assert_allclose(vi.values[live], backup[live], atol=1e-8)
    np.testing.assert_allclose(vi.q, np.where(live[:, None], R + P @ vi.values, 0.0), atol=1e-8)
    np.testing.assert_allclose(pi.values, vi.values, atol=1e-8)
    # the greedy policy's own values, solved exactly, are the optimal ones
    np.testing.assert_allclose(_greedy_exact_values(m, vi.policy), vi.values, atol=1e-6)
    assert np.all(vi.values[m.is_exit] == 0)


@pytest.mark.parametrize("gamma", [0.5, 0.9, 0.99])
def test_discounted_value_iteration_is_the_fixed_point(gamma):
    m = model("mixed-8x8")
    P, R = m.dense
    sol = value_iteration(m, gamma=gamma, theta=1e-12)
    live = ~m.terminal
    np.testing.assert_allclose(sol.values[live], (R + gamma * P @ sol.values).max(axis=1)[live], atol=1e-9)
    ev = policy_evaluation(m, sol.policy, gamma=gamma, theta=1e-12)
    np.testing.assert_allclose(ev.values, sol.values, atol=1e-8)


def test_value_iteration_on_a_64x64_maze_is_minus_the_path_length_plus_one():
    level = levels.get("maze-64x64")
    m = model(level)
    sol = value_iteration(m)
    d = distances(m.table)  # Dijkstra over the table: steps to the exit
    free = ~m.terminal
    np.testing.assert_array_equal(sol.values[free], -(d[free] - 1))
    start = m.table.cell_id(level.starts[0])
    assert sol.values[start] == -(d[start] - 1) < -100


def test_solution_grids_ties_and_overlay_shapes_on_the_default_level():
    sol = value_iteration(model("default"))
    assert sol.value_grid.shape == (3, 3) and sol.policy_grid.shape == (3, 3) and sol.best_actions.shape == (3, 3, 5)
    np.testing.assert_array_equal(sol.value_grid, [[-3, -2, -1], [-2, -1, 0], [-1, 0, 0]])
    # from the top-left corner EAST and SOUTH tie; the policy takes the lower number (EAST)
    assert sol.best_actions[0, 0].tolist() == [False, False, True, True, False]
    assert sol.policy_grid[0, 0] == Action.EAST and sol.policy_grid[2, 2] == -1
    assert not sol.best_actions[2, 2].any()
    assert sol.q.shape == (9, 5) and sol.q[0, Action.STAY] == -1 + sol.values[0]


def test_blocked_cells_are_nan_and_enclosed_cells_have_no_value_with_gamma_one():
    sol = value_iteration(model("blocked"))
    blocked = model("blocked").blocked.reshape(5, 5)
    assert np.isnan(sol.value_grid[blocked]).all() and (sol.policy_grid[blocked] == -1).all()
    m = model(ENCLOSED)
    sol = value_iteration(m)
    assert np.isnan(sol.value_grid[1, 1]) and sol.policy_grid[1, 1] == -1 and not sol.best_actions[1, 1].any()
    assert sol.value_grid[0, 0] == -3
    disc = value_iteration(m, gamma=0.9)
    assert disc.value_grid[1, 1] == pytest.approx(-1 / (1 - 0.9), abs=1e-6)  # stays forever at -1 a step


def test_policy_evaluation_of_the_random_policy_matches_a_linear_solve():
    m = model("puddles")
    P, R = m.dense
    uniform = np.full((m.n_states, 5), 0.2)
    sol = policy_evaluation(m, uniform, theta=1e-11)
    live = np.flatnonzero(~m.terminal)
    P_pi = P[live].mean(axis=1)[:, live]
    r_pi = R[live].mean(axis=1)
    exact = np.linalg.solve(np.eye(len(live)) - P_pi, r_pi)
    np.testing.assert_allclose(sol.values[live], exact, rtol=1e-7)
    # its greedy policy is one improvement step: never worse anywhere
    better = policy_evaluation(m, sol.policy, theta=1e-11)
    assert np.all(better.values >= sol.values - 1e-7)


def test_policy_evaluation_rejects_a_policy_that_never_reaches_the_exit_with_gamma_one():
    m = model("walls")
    with pytest.raises(ValueError, match="policy: with gamma=1"):
        policy_evaluation(m, np.zeros(m.n_states, dtype=np.int64))
    sol = policy_evaluation(m, np.zeros(m.n_states, dtype=np.int64), gamma=0.5, theta=1e-12)
    assert sol.values[0] == pytest.approx(-2.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"gamma": 0.0}, "gamma"),
        ({"gamma": 1.5}, "gamma"),
        ({"gamma": True}, "gamma"),
        ({"theta": 0}, "theta"),
        ({"theta": float("nan")}, "theta"),
        ({"max_iterations": 0}, "max_iterations"),
        ({"tie_tol": -1.0}, "tie_tol"),
    ],
)
def test_bad_parameters_are_value_errors_naming_them(kwargs, match):
    with pytest.raises(ValueError, match=match):
        value_iteration(model("default"), **kwargs)


def test_bad_policies_and_levels_are_clear_errors():
    m = model("default")
    with pytest.raises(ValueError, match="policy: actions must lie in 0..4"):
        policy_evaluation(m, np.full(9, 7))
    with pytest.raises(ValueError, match="policy: expected int"):
        policy_evaluation(m, np.zeros(4, dtype=np.int64))
    with pytest.raises(ValueError, match="sum to 1"):
        policy_evaluation(m, np.full((9, 5), 0.5))
    with pytest.raises(TypeError, match="level"):
        model(42)
    with pytest.raises(ValueError, match="rules"):
        model(BabyRobotEnv(), rules=Rules())
    with pytest.raises(RuntimeError, match="max_iterations=3"):
        value_iteration(model("walls"), max_iterations=3)


def test_model_of_an_env_uses_its_level_and_rules_and_matches_env_P():
    import gymnasium as gym

    env = gym.make("babyrobot_marl/BabyRobot-v0", level="glass", glass_pass_prob=0.8)
    m = model(env)
    assert m.rules.glass_pass_prob == 0.8 and m.level is env.unwrapped.level
    assert m.frozenlake_P == env.unwrapped.P
    level = Level.from_ascii(levels.get("glass").to_ascii())
    assert value_iteration(m).values[0] > value_iteration(model(level)).values[0]  # glass passes more easily


def test_text_views():
    sol = value_iteration(model("default"))
    assert value_text(sol, decimals=0).splitlines()[0].split() == ["-3", "-2", "-1"]
    assert policy_text(sol).splitlines() == ["→ → ↓", "→ → ↓", "→ → E"]
    sol = value_iteration(model("blocked"))
    assert "#" in policy_text(sol) and "#" in value_text(sol)


def test_compiled_table_is_the_one_the_model_reads():
    t = compile_level(levels.get("puddles"))
    env = BabyRobotEnv(level="puddles")
    np.testing.assert_array_equal(model(env).next, model(t.level).next)
