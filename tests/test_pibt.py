"""PIBT (``planning.pibt``): its moves never collide, each robot reaches its target on a map of loops, and
the same seed gives the same plan."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.actions import DELTAS
from babyrobot_marl.core.level import Level
from babyrobot_marl.planning.pibt import PIBT

MAZE = "\n".join([
    "...#.......",
    ".#.#.#####.",
    ".#...#.....",
    ".####.##.#.",
    "......#..#.",
    ".##.#.#.##.",
    "....#......",
])


def crowd(grid: str, n: int, seed: int) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    rng, cells = np.random.default_rng(seed), Level.from_grid(grid).free_cells()
    starts = [cells[i] for i in rng.permutation(len(cells))[:n]]
    while True:  # distinct goals, none on its own robot's start (the env refuses those)
        goals = [cells[i] for i in rng.permutation(len(cells))[:n]]
        if all(g != s for g, s in zip(goals, starts)):
            return starts, goals


CORRIDOR = "\n".join([".......", "###.###"])  # one side pocket halfway along


def walk(planner: PIBT, cells: list[tuple[int, int]], steps: int, goals: list[tuple[int, int]]) -> bool:
    """Steps the planner's moves; True if every robot stands on its target at once within ``steps``."""
    for _ in range(steps):
        cells = [(x + DELTAS[a][0], y + DELTAS[a][1]) for (x, y), a in zip(cells, planner.actions(cells))]
        if cells == goals:
            return True
    return False


@pytest.mark.parametrize(("n", "seed", "shielding"), [(4, 0, False), (12, 1, False), (24, 2, False), (40, 3, False),
                                                     (12, 4, True), (40, 5, True)])
def test_planned_moves_never_share_a_cell_nor_swap_and_the_env_carries_them_all_out(n, seed, shielding):
    # shielding: random preferences stand for a policy's, and the planner must still keep the moves apart
    starts, goals = crowd(MAZE, n, seed)
    wishes = np.random.default_rng(seed)
    env = race_v0.parallel_env(level=MAZE, n_robots=n, goals="own", collisions="block", observe="nearest", k=1,
                               start="random", max_cycles=60, finished="stay")
    env.reset(seed=seed, options={"starts": starts, "goals": goals})
    planner = PIBT(MAZE, goals, seed=seed)
    while env.agents:
        here = [tuple(c) for c in env.robot_cells]
        actions = planner.actions(here, wishes.random((n, 5)) if shielding else None)
        there = [(x + DELTAS[a][0], y + DELTAS[a][1]) for (x, y), a in zip(here, actions)]
        assert len(set(there)) == n  # no two robots in one cell
        assert not any(there[i] == here[j] and there[j] == here[i] for i in range(n) for j in range(i) if here[i] != there[i])
        env.step({a: actions[i] for i, a in enumerate(env.possible_agents) if a in env.agents})
        assert [tuple(c) for c in env.robot_cells] == there  # under the strictest rule every planned move happens


OPEN = "\n".join([".......", ".#.#.#.", ".......", ".#.#.#.", ".......", ".#.#.#.", "......."])  # every cell on a loop


@pytest.mark.parametrize("seed", range(4))
def test_every_robot_reaches_its_target_on_a_map_of_loops(seed):
    # PIBT's guarantee where every cell lies on a loop: each robot stands on its target at some step (without
    # the swap not always all at once: two robots can take turns on a cell one needs to pass)
    starts, goals = crowd(OPEN, 16, seed)
    planner, cells, reached = PIBT(OPEN, goals, seed=0, swap=False), list(starts), set()
    for _ in range(200):
        cells = [(x + DELTAS[a][0], y + DELTAS[a][1]) for (x, y), a in zip(cells, planner.actions(cells))]
        reached |= {i for i, (c, g) in enumerate(zip(cells, goals)) if c == g}
    assert reached == set(range(16))
    assert walk(PIBT(OPEN, goals, seed=0), list(starts), 200, goals)  # with the swap: all of them at once


def test_the_same_seed_gives_the_same_plan_and_another_may_differ():
    starts, goals = crowd(MAZE, 20, 7)

    def plan(seed: int) -> list[list[int]]:
        planner, cells, out = PIBT(MAZE, goals, seed=seed), list(starts), []
        for _ in range(30):
            out.append(planner.actions(cells))
            cells = [(x + DELTAS[a][0], y + DELTAS[a][1]) for (x, y), a in zip(cells, out[-1])]
        return out

    assert plan(3) == plan(3)
    assert any(plan(3) != plan(s) for s in range(4, 12))


def test_a_wrong_number_of_cells_is_one_line_naming_cells():
    planner = PIBT(MAZE, [(0, 0), (10, 6)])
    with pytest.raises(ValueError, match=r"^cells: one \(x, y\) per robot, 2 robots; got 1$"):
        planner.actions([(0, 0)])
    assert len(planner.actions([(0, 0), (10, 6)])) == 2  # still usable


@pytest.mark.parametrize("seed", range(3))
def test_robots_meeting_head_on_in_a_corridor_pass_at_its_pocket_only_with_the_swap(seed):
    # each wants the other's end: pushing alone parks one on the other's target for ever; the swap backs
    # one off into the pocket
    starts, goals = [(0, 0), (6, 0)], [(6, 0), (0, 0)]
    assert walk(PIBT(CORRIDOR, goals, seed=seed), list(starts), 40, goals)
    assert not walk(PIBT(CORRIDOR, goals, seed=seed, swap=False), list(starts), 40, goals)


def test_preferences_choose_each_robots_move_where_nothing_is_in_the_way():
    planner, free = PIBT(MAZE, [(10, 6), (0, 6)], seed=0), set(Level.from_grid(MAZE).free_cells())
    here = [(0, 0), (10, 0)]
    for action in (1, 2, 3, 4, 0):  # NORTH and the moves into the map's edge or a wall stay put
        wish = np.zeros((2, 5))
        wish[:, action] = 1.0
        moved = [(x + DELTAS[a][0], y + DELTAS[a][1]) for (x, y), a in zip(here, planner.actions(here, wish))]
        expected = [(x + DELTAS[action][0], y + DELTAS[action][1]) for x, y in here]
        assert moved == [e if e in free else h for e, h in zip(expected, here)]


def test_preferences_of_the_wrong_shape_are_one_line_naming_preferences():
    planner = PIBT(MAZE, [(0, 0), (10, 6)])
    with pytest.raises(ValueError, match=r"^preferences: one score per action \(5\) for each of the 2 robots, "
                                         r"shape \(2, 5\); got shape \(2, 4\)$"):
        planner.actions([(0, 0), (10, 6)], np.ones((2, 4)))
    assert len(planner.actions([(0, 0), (10, 6)], np.ones((2, 5)))) == 2  # still usable
