"""LaCAM (``planning.lacam``): its plans are valid and end on the goals, the env carries every planned move out,
it solves what PIBT alone does not, the same seed gives the same plan, a spent budget gives None (and PIBT's
steps), and bad arguments are one line naming them."""

from __future__ import annotations

import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level
from babyrobot_marl.planning import LaCAM
from babyrobot_marl.planning.pibt import PIBT
from tests.test_pibt import MAZE, OPEN, crowd, walk

Cell = tuple[int, int]


def assert_valid(grid: str, plan: list[list[Cell]], starts: list[Cell], goals: list[Cell]) -> None:
    """Every step: each robot stays or moves to a free cell next to it, no two share a cell or trade places;
    the plan runs from the starts to the goals."""
    free = set(Level.from_grid(grid).free_cells())
    assert plan[0] == starts and plan[-1] == goals
    for here, there in zip(plan, plan[1:]):
        assert all(b in free and abs(a[0] - b[0]) + abs(a[1] - b[1]) <= 1 for a, b in zip(here, there))
        assert len(set(there)) == len(there)
        moved = {(a, b) for a, b in zip(here, there) if a != b}
        assert not any((b, a) in moved for a, b in moved)


@pytest.mark.parametrize(("grid", "n", "seed"), [(MAZE, 4, 0), (MAZE, 12, 1), (MAZE, 20, 2), (MAZE, 28, 4),
                                                 (OPEN, 30, 4), (OPEN, 36, 5)])
def test_every_plan_is_valid_and_ends_with_every_robot_on_its_goal(grid, n, seed):
    starts, goals = crowd(grid, n, seed)
    plan = LaCAM(grid, goals, seed=seed).solve(starts)
    assert plan is not None
    assert_valid(grid, plan, starts, goals)


@pytest.mark.parametrize(("n", "seed"), [(8, 0), (20, 2), (28, 4)])
def test_the_env_carries_out_every_planned_move_under_the_strictest_rule(n, seed):
    starts, goals = crowd(MAZE, n, seed)
    plan = LaCAM(MAZE, goals, seed=seed).solve(starts)
    assert plan is not None
    env = race_v0.parallel_env(level=MAZE, n_robots=n, goals="own", collisions="block", observe="nearest", k=1,
                               start="random", max_cycles=len(plan) + 5, finished="stay")
    env.reset(seed=seed, options={"starts": starts, "goals": goals})
    planner = LaCAM(MAZE, goals, seed=seed)
    for there in [*plan[1:], goals, goals]:  # then STAY on the goals
        actions = planner.actions([tuple(c) for c in env.robot_cells])
        env.step({a: actions[i] for i, a in enumerate(env.possible_agents) if a in env.agents})
        assert [tuple(c) for c in env.robot_cells] == there
    assert not planner.fell_back


# five robots on ten cells of a street with two dead ends off it: PIBT, with the swap, still circles
STREET = "\n".join([
    "....",
    ".#.#",
    "....",
])


def test_lacam_solves_an_instance_pibt_alone_does_not():
    starts, goals = crowd(STREET, 5, 0)
    assert not walk(PIBT(STREET, goals, seed=0), list(starts), 200, goals)
    plan = LaCAM(STREET, goals, seed=0).solve(starts)
    assert plan is not None and len(plan) - 1 <= 200
    assert_valid(STREET, plan, starts, goals)
    assert walk(LaCAM(STREET, goals, seed=0), list(starts), len(plan) - 1, goals)  # its actions() replay it


def test_a_plan_that_cannot_exist_ends_the_search_before_its_budget():
    # two robots trading ends of a corridor with no pocket: every configuration is tried, none ends on the goals
    planner = LaCAM(".....", [(4, 0), (0, 0)], seed=0, max_nodes=10_000)
    assert planner.solve([(0, 0), (4, 0)]) is None
    assert 0 < planner.nodes < 10_000


def test_the_same_seed_gives_the_same_plan_and_another_may_differ():
    starts, goals = crowd(MAZE, 30, 7)

    def plan(seed: int) -> list[list[Cell]] | None:
        return LaCAM(MAZE, goals, seed=seed).solve(starts)

    assert plan(3) == plan(3)
    assert any(plan(3) != plan(s) for s in range(4, 12))


def test_a_spent_budget_gives_none_and_actions_fall_back_on_pibts_steps():
    starts, goals = crowd(STREET, 7, 0)  # seven robots on ten cells: thousands of PIBT steps to a plan
    planner = LaCAM(STREET, goals, seed=0, max_nodes=50)
    assert planner.solve(starts) is None and planner.nodes == 50
    actions = planner.actions(starts)
    assert planner.fell_back
    assert actions == PIBT(STREET, goals, seed=0).actions(starts)  # PIBT's first step, as from the same seed


def test_horizon_searches_on_for_a_plan_that_short_and_stops_there():
    starts, goals = crowd(MAZE, 28, 4)
    planner = LaCAM(MAZE, goals, seed=0)
    first = planner.solve(starts)
    assert first is not None and len(first) - 1 > 150
    searched = planner.nodes
    planner = LaCAM(MAZE, goals, seed=0, horizon=150)
    shorter = planner.solve(starts)
    assert shorter is not None and len(shorter) - 1 <= 150
    assert searched < planner.nodes < planner.max_nodes
    assert_valid(MAZE, shorter, starts, goals)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"max_nodes": 0}, r"^max_nodes: a whole number of PIBT steps, at least 1; got 0$"),
    ({"max_nodes": 2.5}, r"^max_nodes: a whole number of PIBT steps, at least 1; got 2\.5$"),
    ({"horizon": -1}, r"^horizon: None or a whole number of steps, at least 0; got -1$"),
    ({"goals": [(0, 0), (0, 0)]}, r"^goals: one \(x, y\) per robot, no two the same$"),
])
def test_bad_arguments_are_one_line_naming_them(kwargs, message):
    args = {"goals": [(0, 0), (10, 6)], **kwargs}
    with pytest.raises(ValueError, match=message):
        LaCAM(MAZE, args.pop("goals"), **args)


def test_bad_cells_are_one_line_naming_the_argument_and_the_planner_stays_usable():
    planner = LaCAM(MAZE, [(0, 0), (10, 6)], seed=0)
    with pytest.raises(ValueError, match=r"^cells: one \(x, y\) per robot, 2 robots; got 1$"):
        planner.actions([(0, 0)])
    with pytest.raises(ValueError, match=r"^starts: one \(x, y\) per robot, 2 robots; got 3$"):
        planner.solve([(0, 0), (10, 6), (2, 2)])
    with pytest.raises(ValueError, match=r"^starts: one \(x, y\) per robot, no two the same$"):
        planner.solve([(2, 2), (2, 2)])
    assert planner.solve([(10, 6), (0, 0)]) is not None
    assert len(planner.actions([(10, 6), (0, 0)])) == 2
