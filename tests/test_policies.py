"""Scripted robots: the shortest-path robot walks the BFS distance; the random robot is repeatable."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from babyrobot_marl import Action, BabyRobotEnv, Level, Rules, compile_level, levels
from babyrobot_marl.core.outcomes import OUTCOME_NAMES
from babyrobot_marl.policies import POLICY_NAMES, RandomPolicy, ShortestPathPolicy, distances, make, shortest_path_actions
from tests.strategies import exit_distances

# No skids, glass always passes: every move goes where it aims, so the shortest path is a BFS path.
SURE = {"small_puddle_move_prob": 1.0, "large_puddle_move_prob": 1.0, "glass_pass_prob": 1.0}


@pytest.mark.parametrize("name", levels.names())
def test_distances_are_the_bfs_distances_when_glass_always_passes(name):
    level = levels.get(name)
    t = compile_level(level, Rules(**SURE))
    got = distances(t)
    want = exit_distances(level)
    for c in range(t.n_cells):
        cell = t.cell_xy(c)
        assert got[c] == want.get(cell, np.inf), cell


@pytest.mark.parametrize("name", levels.names())
def test_shortest_path_robot_reaches_the_exit_in_exactly_the_bfs_distance_from_every_cell(name):
    level = levels.get(name)
    env = BabyRobotEnv(level, **SURE)
    policy = ShortestPathPolicy(env.table)
    dist = exit_distances(level)
    starts = [c for c in dist if c not in level.exits]
    assert set(level.starts) <= set(starts)
    env.reset(seed=0)
    for start in starts:
        obs, _ = env.reset(options={"start": start})
        steps = 0
        while True:
            before = tuple(obs.tolist())
            obs, _, terminated, truncated, info = env.step(policy(obs))
            steps += 1
            assert OUTCOME_NAMES[info["outcome"]] == "moved"
            assert dist[tuple(obs.tolist())] == dist[before] - 1  # every step gets one move closer
            assert not truncated
            if terminated:
                break
        assert steps == dist[start]


def test_the_robot_reaches_the_exit_from_the_level_start_with_the_documented_return():
    env = BabyRobotEnv("default", **SURE)
    obs, _ = env.reset(seed=0)
    policy = ShortestPathPolicy(env.table)
    total, terminated = 0.0, False
    while not terminated:
        obs, reward, terminated, _, _ = env.step(policy(obs))
        total += reward
    assert total == -3.0  # four moves on the 3x3 grid: -1, -1, -1, then 0 at the exit


# A 2x2 level: the exit is one glass wall east of the start, or three moves round through the bottom row.
CHOICE_TEXT = """
+-+-+
|S*E|
+ + +
|   |
+-+-+
"""


@pytest.mark.parametrize(
    ("p", "distance", "action"),
    [(1.0, 1.0, Action.EAST), (0.5, 2.0, Action.EAST), (0.25, 3.0, Action.SOUTH), (0.0, 3.0, Action.SOUTH)],
)
def test_glass_costs_the_expected_number_of_tries(p, distance, action):
    """Crossing glass costs 1/p steps on average: worth it while 1/p < 3, the length of the way round."""
    t = compile_level(Level.from_ascii(CHOICE_TEXT), Rules(glass_pass_prob=p))
    assert distances(t)[0] == pytest.approx(distance)
    assert shortest_path_actions(t)[0] == action


def test_a_cell_that_cannot_reach_an_exit_stays_and_exits_stay():
    t = compile_level(Level.from_ascii("+-+-+\n|S*E|\n+-+-+"), Rules(glass_pass_prob=0.0))
    assert distances(t).tolist() == [np.inf, 0.0]
    assert shortest_path_actions(t).tolist() == [Action.STAY, Action.STAY]


def test_shortest_path_policy_reads_only_the_first_two_entries_of_an_observation():
    t = compile_level(levels.get("default"))
    policy = ShortestPathPolicy(t)
    assert policy(np.array([0, 2, 9, 9, 1])) == policy(np.array([0, 2])) == Action.EAST
    assert policy([2, 0]) == Action.SOUTH


def test_random_policy_is_repeatable_covers_every_action_and_depends_on_the_seed():
    first, second = RandomPolicy(7), RandomPolicy(7)
    a = [first() for _ in range(2000)]
    b = [second.act(None) for _ in range(2000)]
    assert a == b
    assert all(type(x) is int for x in a)
    counts = Counter(a)
    assert set(counts) == {0, 1, 2, 3, 4}
    assert all(abs(k - 400) <= 5 * np.sqrt(2000 * 0.2 * 0.8) for k in counts.values())
    other = RandomPolicy(8)
    assert a != [other() for _ in range(2000)]


def test_random_policy_can_draw_from_a_given_generator():
    g = np.random.default_rng(5)
    policy = RandomPolicy(g)
    assert policy.rng is g
    same = RandomPolicy(np.random.default_rng(5))
    assert [policy() for _ in range(20)] == [same() for _ in range(20)]


def test_make_builds_policies_by_name():
    t = compile_level(levels.get("walls"))
    assert set(POLICY_NAMES) == {"random", "shortest"}
    assert isinstance(make("shortest", t), ShortestPathPolicy)
    r1, r2 = make("random", t, seed=3), make("random", t, seed=3)
    assert [r1() for _ in range(50)] == [r2() for _ in range(50)]
    with pytest.raises(ValueError, match="random") as info:
        make("greedy", t)
    assert "shortest" in str(info.value) and "greedy" in str(info.value)
