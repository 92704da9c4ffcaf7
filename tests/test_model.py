"""The transition model p(s', r | s, a): exact by hand on tiny levels, well formed everywhere, and what the simulator does."""

from __future__ import annotations

import math

import numpy as np
import pytest

from babyrobot_marl import Action, BabyRobotEnv, Level, Rules, levels
from babyrobot_marl.core import compile_level, frozenlake_P, move_array, outcomes, transition_arrays
from babyrobot_marl.core.rng import SLOTS

# A small puddle at (1,1): wall to its north, glass to its west, open east and south.
SKID_TEXT = """
+-+-+-+
|S    |
+ +-+ +
| *p  |
+ + + +
|    E|
+-+-+-+
"""

RULE_SETS = [
    Rules(),
    Rules(small_puddle_move_prob=0.3, large_puddle_move_prob=0.9, glass_pass_prob=0.2),
    Rules(small_puddle_move_prob=0.0, large_puddle_move_prob=1.0, glass_pass_prob=1.0),
]


def cid(x, y, width=3):
    return y * width + x


@pytest.mark.parametrize(("m", "g"), [(0.6, 0.5), (0.25, 0.8), (0.0, 0.0), (1.0, 1.0)])
def test_outcomes_of_the_skid_puddle_are_the_hand_derived_distribution(m, g):
    t = compile_level(Level.from_ascii(SKID_TEXT), Rules(small_puddle_move_prob=m, glass_pass_prob=g))
    s = 1 - m
    puddle, east, south, west = cid(1, 1), cid(2, 1), cid(1, 2), cid(0, 1)
    expected = {
        Action.STAY: {puddle: 1.0},
        Action.EAST: {east: m, south: s},
        Action.SOUTH: {south: m, east: s},
        Action.NORTH: {puddle: m, east: s / 2, south: s / 2},
        Action.WEST: {west: m * g, puddle: m * (1 - g), east: s / 2, south: s / 2},
    }
    for a, want in expected.items():
        got = outcomes(t, puddle, a)
        want = {k: v for k, v in want.items() if v > 0}
        assert got.keys() == want.keys(), a
        for k in want:
            assert got[k] == pytest.approx(want[k], abs=1e-12)


def test_outcomes_off_puddles_are_deterministic_except_glass():
    t = compile_level(Level.from_ascii(SKID_TEXT), Rules(glass_pass_prob=0.3))
    assert outcomes(t, cid(0, 0), Action.EAST) == {cid(1, 0): 1.0}
    assert outcomes(t, cid(0, 0), Action.NORTH) == {cid(0, 0): 1.0}  # border
    assert outcomes(t, cid(1, 0), Action.SOUTH) == {cid(1, 0): 1.0}  # wall
    got = outcomes(t, cid(0, 1), Action.EAST)  # through the glass into the puddle
    assert got == pytest.approx({cid(1, 1): 0.3, cid(0, 1): 0.7})


@pytest.mark.parametrize("rules", RULE_SETS, ids=["default", "odd", "extreme"])
@pytest.mark.parametrize("name", levels.names())
def test_transition_arrays_are_distributions_and_frozenlake_P_agrees(name, rules):
    t = compile_level(levels.get(name), rules)
    n = t.n_cells
    P, R = transition_arrays(t)
    assert P.shape == (n, 5, n) and R.shape == (n, 5)
    assert np.all(P >= 0)
    np.testing.assert_allclose(P.sum(axis=2), 1.0, atol=1e-12)
    # expected reward of a step is the reward of the cell it ends in; exits and blocked cells absorb with 0
    terminal = t.is_exit | t.blocked
    np.testing.assert_allclose(R[~terminal], (P @ t.reward)[~terminal], atol=1e-12)
    assert np.all(R[terminal] == 0)
    for c in np.flatnonzero(terminal):
        assert np.all(P[c, :, c] == 1.0)
    # nothing ever enters a blocked cell
    assert np.all(P[:, :, t.blocked][~t.blocked] == 0)

    fl = frozenlake_P(t)
    assert sorted(fl) == list(range(n))
    for s in range(n):
        assert sorted(fl[s]) == list(range(5))
        for a in range(5):
            row = np.zeros(n)
            expected_reward = 0.0
            for p, nxt, r, done in fl[s][a]:
                assert type(done) is bool and type(r) is float and 0 < p <= 1
                row[nxt] += p
                expected_reward += p * r
                if not terminal[s]:
                    assert r == t.reward[nxt] and done == bool(t.is_exit[nxt])
                else:
                    assert (nxt, r, done) == (s, 0.0, bool(t.is_exit[s]))
            np.testing.assert_allclose(row, P[s, a], atol=1e-12)
            assert expected_reward == pytest.approx(R[s, a], abs=1e-12)


@pytest.mark.parametrize("name", ["mixed-8x8", "puddles", "glass", "race-4"])
def test_simulated_step_frequencies_match_the_model(name):
    """Every (cell, action): 3000 seeded draws of the simulator's step against ``outcomes``, 5 sigma per next cell."""
    t = compile_level(levels.get(name), Rules(glass_pass_prob=0.35))
    n = 3000
    g = np.random.default_rng(11)
    for c in range(t.n_cells):
        if t.blocked[c] or t.is_exit[c]:
            continue
        for a in range(5):
            keys = g.integers(0, 2**64, size=n, dtype=np.uint64)
            counts = g.integers(0, 2**30, size=n) * SLOTS
            dest, _ = move_array(t, np.full(n, c), np.full(n, a), keys, counts)
            freq = np.bincount(dest, minlength=t.n_cells)
            dist = outcomes(t, c, a)
            assert set(np.flatnonzero(freq)) <= set(dist), (c, a)
            for nxt, p in dist.items():
                sigma = math.sqrt(n * p * (1 - p))
                assert abs(freq[nxt] - n * p) <= 5 * sigma + 1e-9, (c, a, nxt, freq[nxt], n * p)


def value_iteration(P, R, terminal, sweeps):
    V = np.zeros(P.shape[0])
    for _ in range(sweeps):
        V = np.where(terminal, 0.0, (R + P @ V).max(axis=1))
    return V


@pytest.mark.parametrize(("name", "moves"), [("default", 4), ("walls", None)])
def test_value_iteration_on_deterministic_levels_gives_minus_the_path_length_plus_one(name, moves):
    """With no puddles or glass, the best return is -1 per step except the last (the exit pays 0)."""
    level = levels.get(name)
    t = compile_level(level)
    P, R = transition_arrays(t)
    V = value_iteration(P, R, t.is_exit | t.blocked, sweeps=4 * t.n_cells)
    if moves is None:  # shortest path by breadth-first search over the level's own sets
        frontier, dist = list(level.exits), {e: 0 for e in level.exits}
        while frontier:
            nxt = []
            for x, y in frontier:
                for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                    e = ((x, y), n) if (x, y) < n else (n, (x, y))
                    if 0 <= n[0] < level.width and 0 <= n[1] < level.height and e not in level.walls and n not in dist:
                        dist[n] = dist[(x, y)] + 1
                        nxt.append(n)
            frontier = nxt
        moves = dist[level.starts[0]]
    assert V[t.cell_id(level.starts[0])] == pytest.approx(-(moves - 1))


def test_env_P_is_the_frozenlake_model_of_its_own_table_and_matches_its_steps():
    env = BabyRobotEnv(SKID_TEXT, glass_pass_prob=0.5)
    model = env.P
    assert model == frozenlake_P(env.table)
    assert env.P is model  # computed once
    env.reset(seed=0)
    for s, by_action in model.items():
        x, y = s % 3, s // 3
        if (x, y) in env.level.exits:
            continue
        for a, transitions in by_action.items():
            support = {nxt: (r, done) for _, nxt, r, done in transitions}
            for _ in range(60):
                env.reset(options={"start": (x, y)})
                obs, reward, terminated, _, _ = env.step(a)
                nxt = int(obs[1]) * 3 + int(obs[0])
                assert nxt in support, (s, a, nxt)
                assert (reward, terminated) == support[nxt]


def test_env_P_follows_rule_overrides():
    never = BabyRobotEnv(SKID_TEXT, glass_pass_prob=0.0).P
    always = BabyRobotEnv(SKID_TEXT, glass_pass_prob=1.0).P
    across_glass = cid(0, 1), Action.EAST
    assert [(p, nxt) for p, nxt, _, _ in never[across_glass[0]][across_glass[1]]] == [(1.0, cid(0, 1))]
    assert [(p, nxt) for p, nxt, _, _ in always[across_glass[0]][across_glass[1]]] == [(1.0, cid(1, 1))]
