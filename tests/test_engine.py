"""The step engine and its random numbers: the scalar and array forms agree exactly, draws are well formed."""

from __future__ import annotations

import math
import warnings
import zlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import levels
from babyrobot_marl.core import DELTAS, OUTCOMES, Rules, compile_level, move, move_array, rng
from babyrobot_marl.core.level import Level
from babyrobot_marl.core.outcomes import BUMPED, GLASS, MOVED, SKIDDED, STAYED

RULE_SETS = {
    "default": Rules(),
    "odd-probabilities": Rules(small_puddle_move_prob=0.3, large_puddle_move_prob=0.85, glass_pass_prob=0.7),
    "always-skid-never-pass": Rules(small_puddle_move_prob=0.0, large_puddle_move_prob=0.0, glass_pass_prob=0.0),
    "never-skid-always-pass": Rules(small_puddle_move_prob=1.0, large_puddle_move_prob=1.0, glass_pass_prob=1.0),
}

U64 = st.integers(0, 2**64 - 1)


# --------------------------------------------------------------------------------------- rng
@settings(max_examples=300, deadline=None)
@given(U64, st.integers(0, 2**62))
def test_uniform_and_uniform_array_are_bit_identical(key, count):
    scalar = rng.uniform(key, count)
    assert 0.0 <= scalar < 1.0
    array = rng.uniform_array(np.array([key], dtype=np.uint64), np.array([count], dtype=np.uint64))
    assert array.dtype == np.float64 and array[0] == scalar
    assert rng.uniform_array(key, count) == scalar  # 0-d inputs


def test_uniform_array_matches_uniform_on_a_large_random_batch_and_broadcasts():
    g = np.random.default_rng(0)
    keys = g.integers(0, 2**64, size=(50, 40), dtype=np.uint64)
    counts = g.integers(0, 2**40, size=(50, 40), dtype=np.int64)
    got = rng.uniform_array(keys, counts)
    want = np.array(
        [[rng.uniform(int(k), int(c)) for k, c in zip(kr, cr, strict=True)] for kr, cr in zip(keys, counts, strict=True)]
    )
    assert got.shape == (50, 40)
    assert np.array_equal(got, want)
    # one key broadcast over many counters
    row = rng.uniform_array(int(keys[0, 0]), np.arange(100))
    assert np.array_equal(row, [rng.uniform(int(keys[0, 0]), c) for c in range(100)])


def test_uniform_array_on_scalars_emits_no_overflow_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rng.uniform_array(2**64 - 1, 2**63)
        rng.uniform_array(np.uint64(12345), np.uint64(7))


def test_uniform_draws_are_uniform_on_the_unit_interval():
    n, bins = 200_000, 20
    u = rng.uniform_array(np.uint64(0xDEADBEEF), np.arange(n))
    assert u.min() >= 0.0 and u.max() < 1.0
    counts = np.bincount((u * bins).astype(int), minlength=bins)
    p = 1 / bins
    assert np.all(np.abs(counts - n * p) <= 5 * math.sqrt(n * p * (1 - p)))
    # successive numbers are not correlated
    assert abs(np.corrcoef(u[:-1], u[1:])[0, 1]) <= 5 / math.sqrt(n)


def test_counter_gives_every_decision_its_own_address():
    n_robots = 3
    addresses = [
        rng.counter(step, robot, n_robots, slot) for step in range(20) for robot in range(n_robots) for slot in range(rng.SLOTS)
    ]
    assert len(set(addresses)) == len(addresses)
    assert sorted(addresses) == list(range(len(addresses)))  # dense: no gaps, no overlaps


def test_new_key_comes_from_the_generator():
    a = rng.new_key(np.random.default_rng(5))
    b = rng.new_key(np.random.default_rng(5))
    c = rng.new_key(np.random.default_rng(6))
    assert a == b != c
    assert isinstance(a, int) and 0 <= a < 2**64


# --------------------------------------------------------------------------------------- move vs move_array
def random_inputs(table, n, seed):
    g = np.random.default_rng(seed)
    cells = g.integers(0, table.n_cells, size=n)
    actions = g.integers(0, 5, size=n)
    keys = g.integers(0, 2**64, size=n, dtype=np.uint64)
    counts = g.integers(0, 2**40, size=n) * rng.SLOTS
    return cells, actions, keys, counts


@pytest.mark.parametrize("rules", list(RULE_SETS))
@pytest.mark.parametrize("name", levels.names())
def test_move_and_move_array_agree_exactly_on_every_built_in_level(name, rules):
    table = compile_level(levels.get(name), RULE_SETS[rules])
    lists = table.lists
    cells, actions, keys, counts = random_inputs(table, 3000, seed=zlib.crc32(f"{name}|{rules}".encode()))
    dest, outcome = move_array(table, cells, actions, keys, counts)
    assert dest.shape == outcome.shape == cells.shape
    for i in range(len(cells)):
        assert move(lists, int(cells[i]), int(actions[i]), int(keys[i]), int(counts[i])) == (dest[i], outcome[i]), i


@pytest.mark.parametrize("rules", ["default", "odd-probabilities"])
def test_differential_sample_exercises_every_outcome(rules):
    table = compile_level(levels.get("mixed-8x8"), RULE_SETS[rules])
    cells, actions, keys, counts = random_inputs(table, 3000, seed=1)
    _, outcome = move_array(table, cells, actions, keys, counts)
    assert set(outcome.tolist()) == {MOVED, STAYED, BUMPED, SKIDDED, GLASS}


def test_move_array_works_on_batches_of_any_shape_with_one_key_per_env():
    table = compile_level(levels.get("puddles"))
    g = np.random.default_rng(3)
    n_envs, n_robots = 64, 3
    cells = g.choice([table.cell_id(c) for c in levels.get("puddles").small_puddles], size=(n_envs, n_robots))
    actions = g.integers(0, 5, size=(n_envs, n_robots))
    keys = g.integers(0, 2**64, size=(n_envs, 1), dtype=np.uint64)
    step = 17
    counts = np.array([[rng.counter(step, r, n_robots, 0) for r in range(n_robots)]] * n_envs)
    dest, outcome = move_array(table, cells, actions, keys, counts)
    assert dest.shape == (n_envs, n_robots)
    for e in range(n_envs):
        for r in range(n_robots):
            want = move(table.lists, int(cells[e, r]), int(actions[e, r]), int(keys[e, 0]), int(counts[e, r]))
            assert (dest[e, r], outcome[e, r]) == want


# --------------------------------------------------------------------------------------- move semantics
def test_stay_stays_for_every_cell_and_key():
    table = compile_level(levels.get("mixed-8x8"), RULE_SETS["always-skid-never-pass"])
    for c in range(table.n_cells):
        for key in (0, 1, 2**63, 2**64 - 1):
            assert move(table.lists, c, 0, key, 4 * c) == (c, STAYED)


def test_without_puddles_or_glass_a_move_is_deterministic():
    level = levels.get("walls")
    table = compile_level(level)
    for c in range(table.n_cells):
        x, y = table.cell_xy(c)
        for a in range(1, 5):
            dx, dy = DELTAS[a]
            n = (x + dx, y + dy)
            inside = 0 <= n[0] < level.width and 0 <= n[1] < level.height
            wall = ((x, y), n) in level.walls or (n, (x, y)) in level.walls
            want = (table.cell_id(n), MOVED) if inside and not wall else (c, BUMPED)
            for key in range(5):
                assert move(table.lists, c, a, key, 0) == want


def test_outcome_names_are_documented():
    assert OUTCOMES == ("moved", "stayed", "bumped", "skidded", "glass")
    assert (OUTCOMES[MOVED], OUTCOMES[STAYED], OUTCOMES[BUMPED], OUTCOMES[SKIDDED], OUTCOMES[GLASS]) == OUTCOMES


# --------------------------------------------------------------------------------------- compiled tables
def test_table_matches_the_level_cell_by_cell():
    text = """
    +-+-+-+
    |S   #|
    + +-+ +
    | *p  |
    + + + +
    |P   E|
    +-+-+-+
    """
    level = Level.from_ascii(text)
    rules = Rules(small_puddle_move_prob=0.7, large_puddle_move_prob=0.2, floor_reward=-1.5, exit_reward=3.0)
    t = compile_level(level, rules)

    def cid(x, y):
        return y * 3 + x

    assert t.cell_id((2, 1)) == 5 and t.cell_xy(5) == (2, 1)
    # intended targets from the puddle (1,1): north is walled, west behind glass
    assert t.target[cid(1, 1)].tolist() == [cid(1, 1), cid(1, 1), cid(2, 1), cid(1, 2), cid(0, 1)]
    assert t.glass[cid(1, 1)].tolist() == [False, False, False, False, True]
    # skid choices: the other open, non-glass neighbours
    skids = {a: sorted(t.skid[cid(1, 1), a, : t.n_skid[cid(1, 1), a]].tolist()) for a in range(1, 5)}
    assert skids == {1: [cid(2, 1), cid(1, 2)], 2: [cid(1, 2)], 3: [cid(2, 1)], 4: [cid(2, 1), cid(1, 2)]}
    # (1,0) cannot move east into the blocked (2,0)
    assert t.target[cid(1, 0), 2] == cid(1, 0)
    assert t.blocked.tolist() == [c == cid(2, 0) for c in range(9)]
    assert t.is_exit.tolist() == [c == cid(2, 2) for c in range(9)]
    assert t.move_prob[cid(1, 1)] == 0.7 and t.move_prob[cid(0, 2)] == 0.2 and t.move_prob[cid(0, 0)] == 1.0
    assert t.reward[cid(0, 0)] == -1.5 and t.reward[cid(1, 1)] == -2.0 and t.reward[cid(0, 2)] == -4.0
    assert t.reward[cid(2, 2)] == 3.0


def test_table_arrays_are_read_only():
    t = compile_level(levels.get("default"))
    for arr in (t.target, t.glass, t.move_prob, t.skid, t.n_skid, t.reward, t.is_exit, t.blocked):
        with pytest.raises(ValueError):
            arr[0] = arr[0]
