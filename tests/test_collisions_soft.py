"""``collisions="soft"``: POGEMA's soft rule, against a line-by-line reading of POGEMA 1.4's own
algorithm (``pogema_soft``: its ``used_cells`` / ``used_edges`` bookkeeping and recursive reverts),
for the scalar rules (``core.race``, dicts and numpy), the batch engine and a race env.

The package computes soft as block's closure with the contest going to the lowest robot number;
POGEMA reverts one robot at a time. The reference below follows POGEMA's steps, so these tests
check that the two formulations agree (tests_integrations/test_pogema_soft.py checks POGEMA itself).
"""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import race_v0
from babyrobot_marl.core import race as race_core
from babyrobot_marl.core.batch import resolve_collisions_array
from babyrobot_marl.core.level import Level
from tests.strategies import resolve_all_robots


def pogema_soft(cells, aims, racing, blocked=frozenset()):
    """Where each robot ends under POGEMA's soft rule: ``aims`` is the cell each robot's action
    points at (its own cell to stay), ``blocked`` the obstacle cells, robots not racing are off
    the board. POGEMA's ``Pogema.move_agents`` for ``collision_system="soft"``, with cells for
    (x, y) and "aim == cell" for the stay action."""
    n = len(cells)
    aims = list(aims)
    used_cells: dict[int, list[int]] = {}
    used_edges: dict[tuple[int, int], list[int]] = {}
    for i in range(n):
        if racing[i]:
            used_cells.setdefault(aims[i], []).append(i)
            used_edges[cells[i], aims[i]] = [i]
            if aims[i] != cells[i]:
                used_edges.setdefault((aims[i], cells[i]), []).append(i)
    for i in range(n):
        if racing[i] and len(used_edges[cells[i], aims[i]]) > 1:  # a swap
            used_cells[aims[i]].remove(i)
            used_cells.setdefault(cells[i], []).append(i)
            aims[i] = cells[i]

    def revert(i, cell):
        aims[i] = cells[i]
        used_cells[cell].remove(i)
        back = cells[i]
        if used_cells.get(back):
            used_cells[back].append(i)
            revert(used_cells[back][0], back)
        else:
            used_cells.setdefault(back, []).append(i)

    for i in reversed(range(n)):
        if racing[i] and (len(used_cells[aims[i]]) > 1 or aims[i] in blocked):
            revert(i, aims[i])
    return [aims[i] if racing[i] else cells[i] for i in range(n)]


def engines(cells, aims, racing, blocked=frozenset(), key=99, step=3):
    """Every engine's soft result for robots aiming at ``aims`` (a blocked aim: the robot stays, as
    the package's move tables say), after checking they all agree."""
    desired = [c if a in blocked or not r else a for c, a, r in zip(cells, aims, racing)]
    scalar = list(resolve_all_robots("soft", list(cells), desired, list(racing), key, step))
    with mock.patch.object(race_core, "_ARRAYS_FROM", 10**9):  # the dict-based path at any size
        dicts = list(resolve_all_robots("soft", list(cells), desired, list(racing), key, step))
    array = resolve_collisions_array(
        "soft", np.array([cells]), np.array([desired]), np.array([racing]),
        np.array([key], dtype=np.uint64), np.array([step]),
    )[0].tolist()
    assert scalar == dicts == array
    return scalar


# ------------------------------------------------------------------------ the reference on hand-built cases
def test_the_reference_reads_pogemas_rule_on_hand_built_cases():
    # a contest for a free cell: the lowest robot number gets it (POGEMA reverts the highest first)
    assert pogema_soft([0, 2, 4], [1, 1, 1], [True] * 3) == [1, 2, 4]
    assert pogema_soft([4, 2, 0], [1, 1, 1], [True] * 3) == [1, 2, 0]
    # a swap: both stay; following a robot that leaves: both move; a rotation: all move
    assert pogema_soft([0, 1], [1, 0], [True, True]) == [0, 1]
    assert pogema_soft([0, 1], [1, 2], [True, True]) == [1, 2]
    assert pogema_soft([0, 1, 2], [1, 2, 0], [True] * 3) == [1, 2, 0]
    # behind a robot that stays, or one that bumps into an obstacle, a queue stays
    assert pogema_soft([0, 1, 2], [1, 2, 2], [True] * 3) == [0, 1, 2]
    assert pogema_soft([0, 1, 2], [1, 2, 3], [True] * 3, blocked={3}) == [0, 1, 2]
    # a robot off the board blocks nobody
    assert pogema_soft([0, 1], [1, 1], [True, False]) == [1, 1]


@pytest.mark.parametrize("lowest_first", [True, False])
def test_a_contest_goes_to_the_lowest_robot_number_in_every_engine(lowest_first):
    cells = [0, 2, 4] if lowest_first else [4, 2, 0]
    for key in range(40):  # no draw: whatever the episode's key and step (block would draw a winner)
        assert engines(cells, [1, 1, 1], [True] * 3, key=key, step=key) == pogema_soft(cells, [1, 1, 1], [True] * 3)


def test_a_contest_lost_at_a_queues_head_stops_the_queue_behind_the_loser():
    # robots 1..5 queue east towards cell 10, robot 0 comes from the side for the same cell
    cells = [20, 5, 6, 7, 8, 9]
    aims = [10, 6, 7, 8, 9, 10]
    got = engines(cells, aims, [True] * 6)
    assert got == pogema_soft(cells, aims, [True] * 6) == [10, 5, 6, 7, 8, 9]


# ------------------------------------------------------------------------ random configurations
@st.composite
def boards(draw, side_lo=2, side_hi=9, robots_hi=60):
    """Robots on distinct cells of a small square board with obstacles, each aiming at itself or a
    neighbour (obstacles and the border included, as POGEMA's padded grid has them), some off the board."""
    side = draw(st.integers(side_lo, side_hi))
    n_cells = side * side
    blocked = set(draw(st.lists(st.integers(0, n_cells - 1), max_size=n_cells // 3)))
    free = [c for c in range(n_cells) if c not in blocked]
    n = draw(st.integers(1, max(1, min(robots_hi, len(free)))))
    if not free:
        return [], [], [], blocked
    cells = draw(st.permutations(free))[:n]
    racing = draw(st.lists(st.sampled_from([True, True, True, False]), min_size=n, max_size=n))
    aims = []
    for c in cells:
        x, y = c % side, c // side
        around = [(x, y), (x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)]
        # off the board counts as an obstacle (POGEMA's border); here a cell id past the board
        options = [nx + ny * side if 0 <= nx < side and 0 <= ny < side else n_cells + 1 for nx, ny in around]
        aims.append(draw(st.sampled_from(options)))
    return cells, aims, racing, blocked | {n_cells + 1}


@settings(max_examples=500, deadline=None)
@given(boards())
def test_every_engine_equals_pogemas_algorithm_on_random_boards(board):
    cells, aims, racing, blocked = board
    if not cells:
        return
    got = engines(cells, aims, racing, blocked)
    assert got == pogema_soft(cells, aims, racing, blocked)
    final = [got[i] for i in range(len(cells)) if racing[i]]
    assert len(set(final)) == len(final)  # no two robots on the board share a cell


@settings(max_examples=60, deadline=None)
@given(boards(side_lo=16, side_hi=24, robots_hi=300))
def test_crowds_of_hundreds_equal_pogemas_algorithm(board):
    cells, aims, racing, blocked = board
    if not cells:
        return
    assert engines(cells, aims, racing, blocked) == pogema_soft(cells, aims, racing, blocked)


# ------------------------------------------------------------------------ a race under soft
GRID = "\n".join([
    "........",
    ".##..#..",
    "........",
    "..#..##.",
    "........",
])


def test_a_race_under_soft_steps_as_pogemas_algorithm_says():
    """A race on a grid map (with an exit added): every step's cells are POGEMA's soft rule applied
    to the cells before it and the cells the actions aim at."""
    grid = Level.from_grid(GRID)
    level = Level(width=grid.width, height=grid.height, blocked=grid.blocked, exits={(7, 4)})
    env = race_v0.parallel_env(level=level, n_robots=12, collisions="soft", start="random", max_cycles=400)
    w, deltas = level.width, ((0, 0), (0, -1), (1, 0), (0, 1), (-1, 0))
    blocked = {x + y * w for x, y in level.blocked}
    g = np.random.default_rng(5)
    steps = contests = 0
    for seed in range(6):
        env.reset(seed=seed)
        while env.agents:
            before = {a: env.robot_cells[env.possible_agents.index(a)] for a in env.agents}
            acts = {a: int(g.integers(5)) for a in env.agents}
            cells, aims = [], []
            for a in env.agents:
                (x, y), (dx, dy) = before[a], deltas[acts[a]]
                nx, ny = x + dx, y + dy
                cells.append(x + y * w)
                aims.append(nx + ny * w if 0 <= nx < w and 0 <= ny < level.height else -1)
            contests += len(aims) - len(set(aims))
            expected = pogema_soft(cells, aims, [True] * len(cells), blocked | {-1})
            agents = list(env.agents)
            env.step(acts)
            after = [env.robot_cells[env.possible_agents.index(a)] for a in agents]
            assert [x + y * w for x, y in after] == expected
            steps += 1
    assert steps > 500 and contests > 50  # the rule was exercised, not just free moves
