"""Grid mazes (``gridmaze:A..B``): blocked cells with loops, seeded, drawn by the env, for own goals."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.levels.gridmazes import grid_maze
from babyrobot_marl.levels.sources import grid_maze_family, parse_level_family


def free_graph(level):
    """The free cells, the number of edges between neighbouring free cells, and the connected parts."""
    free = {(x, y) for x in range(level.width) for y in range(level.height)} - set(level.blocked)
    edges = sum((x + 1, y) in free for x, y in free) + sum((x, y + 1) in free for x, y in free)
    seen, parts = set(), 0
    for cell in free:
        if cell in seen:
            continue
        parts, stack = parts + 1, [cell]
        seen.add(cell)
        while stack:
            x, y = stack.pop()
            for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                if n in free and n not in seen:
                    seen.add(n)
                    stack.append(n)
    return free, edges, parts


@pytest.mark.parametrize("side", [5, 8, 17, 20, 21])
def test_a_grid_maze_is_its_side_and_seed(side):
    level = grid_maze(side, 3)
    assert (level.width, level.height) == (side, side)
    assert level.exits == frozenset() and level.walls == frozenset()
    assert grid_maze.__wrapped__(side, 3) == level  # the same seed draws the same maze, cache or not
    assert len({grid_maze(side, s).blocked for s in range(8)}) > 1


def test_grid_mazes_have_loops_and_varied_density():
    shares, looped = [], 0
    for seed in range(60):
        level = grid_maze(19, seed)
        free, edges, parts = free_graph(level)
        looped += edges - len(free) + parts > 0  # a graph with more edges than a forest holds a cycle
        shares.append(len(level.blocked) / 19**2)
    assert looped >= 55  # a perfect maze (mazes.maze) has none
    assert min(shares) < 0.15 and max(shares) > 0.35


def test_a_family_draws_its_sides_and_seeds_from_the_generator():
    family = parse_level_family("gridmaze:9..11", seeds=range(5))
    drawn = [family(np.random.default_rng(s)) for s in range(40)]
    assert {lv.width for lv in drawn} == {9, 10, 11}
    allowed = {grid_maze(side, seed) for side in (9, 10, 11) for seed in range(5)}
    assert all(lv in allowed for lv in drawn)
    assert family.family == "gridmaze:9..11" and family.largest == (11, 11)
    assert [family(np.random.default_rng(7)) for _ in range(2)] == [family(np.random.default_rng(7))] * 2


def test_the_env_races_own_goals_on_grid_mazes_and_refuses_the_exit_race():
    env = race_v0.parallel_env(level="gridmaze:11..13", n_robots=6, start="random", observe="local",
                               goals="own", collisions="soft")
    first = env.reset(seed=4)
    level, goals = env.level, dict(env.goals)
    assert level.name.startswith("gridmaze-") and all(g not in level.blocked for g in goals.values())
    again = env.reset(seed=4)
    assert env.level == level and env.goals == goals
    assert all(np.array_equal(first[0][a], again[0][a]) for a in env.agents)
    with pytest.raises(ValueError, match=r"^level: has no exit; use goals='own'$"):
        race_v0.parallel_env(level="gridmaze:11..13", n_robots=2)


@pytest.mark.parametrize("spec", ["gridmaze:1..4", "gridmaze:9..8", "gridmaze:8", "gridmaze:a..b"])
def test_a_bad_grid_maze_spec_is_one_line_naming_level(spec):
    with pytest.raises(ValueError, match=r"^level: a level family is .*'gridmaze:A\.\.B'") as err:
        grid_maze_family(1, 4) if spec == "gridmaze:1..4" else parse_level_family(spec)
    assert "\n" not in str(err.value)
