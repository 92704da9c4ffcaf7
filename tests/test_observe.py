"""Observation modes (core/observe.py) against direct readings of the level and the robots."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl.core import nearest, observe
from babyrobot_marl.core.goals import cell_keys, channel_marks, channel_where, goal_offsets, row_starts, target_channel
from babyrobot_marl.core.table import compile_level
from tests.strategies import edge, grid_levels, inside

TERRAIN, EDGE = observe.TERRAIN, observe.EDGE


def reference_local(level, cells_xy, racing, i, r):
    """Robot i's local row read cell by cell from the Level (no precomputation)."""
    x0, y0 = cells_xy[i]
    row = [x0, y0]
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            c = (x0 + dx, y0 + dy)
            if not inside(level, c):
                row += [TERRAIN["blocked"], 0] + [EDGE["wall"]] * 4
                continue
            if c in level.blocked:
                terrain = TERRAIN["blocked"]
            elif c in level.exits:
                terrain = TERRAIN["exit"]
            elif c in level.small_puddles:
                terrain = TERRAIN["small puddle"]
            elif c in level.large_puddles:
                terrain = TERRAIN["large puddle"]
            else:
                terrain = TERRAIN["floor"]
            robot = int(any(racing[j] and tuple(cells_xy[j]) == c for j in range(len(cells_xy)) if j != i))
            sides = []
            for ddx, ddy in ((0, -1), (1, 0), (0, 1), (-1, 0)):  # north, east, south, west
                n = (c[0] + ddx, c[1] + ddy)
                e = edge(c, n)
                if not inside(level, n) or e in level.walls:
                    sides.append(EDGE["wall"])
                elif e in level.glass:
                    sides.append(EDGE["glass"])
                else:
                    sides.append(EDGE["open"])
            row += [terrain, robot, *sides]
    return row


def reference_nearest(cells_xy, racing, i, k, w, h):
    x0, y0 = cells_xy[i]
    others = sorted(
        (abs(x - x0) + abs(y - y0), j) for j, (x, y) in enumerate(cells_xy) if j != i and racing[j]
    )[:k]
    row = [x0, y0]
    for _, j in others:
        row += [cells_xy[j][0] - x0 + w - 1, cells_xy[j][1] - y0 + h - 1]
    row += [2 * w - 1, 2 * h - 1] * (k - len(others))
    return row


@st.composite
def crowds_on_levels(draw, max_robots=12):
    level = draw(grid_levels(max_side=10))
    n = draw(st.integers(1, max_robots))
    shared = draw(st.booleans())  # "pass": robots may share cells
    cells = [
        (draw(st.integers(0, level.width - 1)), draw(st.integers(0, level.height - 1)))
        for _ in range(n)
    ]
    if not shared:
        cells = list(dict.fromkeys(cells))
    racing = [draw(st.integers(0, 5)) > 0 for _ in cells]
    return level, cells, racing


@settings(max_examples=150, deadline=None)
@given(crowds_on_levels(), st.integers(0, 3))
def test_local_rows_read_the_level_and_the_robots_cell_by_cell(crowd, r):
    level, cells_xy, racing = crowd
    table = compile_level(level)
    view = observe.local_view(table, r)
    cells = np.array([y * level.width + x for x, y in cells_xy])
    for table_bytes in (observe._LEVEL_ROWS_BYTES, 0):  # rows from the table of level rows, and window by window
        with mock.patch.object(observe, "_LEVEL_ROWS_BYTES", table_bytes):
            observe.level_rows.cache_clear()
            assert (observe.level_rows(view) is None) == (table_bytes == 0)
            got = observe.local_observations(view, cells, np.array(racing))
        assert got.shape == (len(cells), view.size)
        for i in range(len(cells)):
            assert got[i].tolist() == reference_local(level, cells_xy, racing, i, r)
        assert (got < view.nvec).all() and (got >= 0).all()
    observe.level_rows.cache_clear()


@pytest.mark.parametrize("table_bytes", [observe._LEVEL_ROWS_BYTES, 0])
def test_local_rows_given_goals_carry_the_target_channel_first_in_their_extra_columns(table_bytes):
    table = compile_level(__import__("babyrobot_marl").levels.get("mixed-8x8"))
    view = observe.local_view(table, 2)
    g = np.random.default_rng(1)
    cells = np.stack([g.choice(table.n_cells, 5, replace=False) for _ in range(3)])
    goals, racing = g.integers(0, table.n_cells, cells.shape), g.random(cells.shape) > 0.3
    with mock.patch.object(observe, "_LEVEL_ROWS_BYTES", table_bytes):
        observe.level_rows.cache_clear()
        plain = observe.local_observations(view, cells, racing, extra=view.window.size + 3)
        got = observe.local_observations(view, cells, racing, extra=view.window.size + 3, goals=goals)
    observe.level_rows.cache_clear()
    channel = got[..., view.size : view.size + view.window.size]
    assert (got[..., : view.size] == plain[..., : view.size]).all()
    assert (channel == target_channel(table, cells, goals, 2)).all() and (channel.sum(axis=-1) == 1).all()
    assert (got[..., view.size + view.window.size :] == 0).all() and (plain[..., view.size :] == 0).all()


@pytest.mark.parametrize("table_bytes", [observe._LEVEL_ROWS_BYTES, 0])
@pytest.mark.parametrize("races", [1, 3])
def test_local_rows_from_the_goals_marks_equal_those_from_the_goals(table_bytes, races):
    """An own-goal step hands the observer where the target channel's 1s go (``channel_marks``, from the
    goals' offsets it checked finishing with): the same rows as from the goals."""
    table = compile_level(__import__("babyrobot_marl").levels.get("mixed-8x8"))
    w, h = table.width, table.height
    view = observe.local_view(table, 2)
    g = np.random.default_rng(2)
    cells = np.stack([g.choice(table.n_cells, 6, replace=False) for _ in range(races)])
    goals, racing = g.integers(0, table.n_cells, cells.shape), g.random(cells.shape) > 0.3
    goals[:, 0] = cells[:, 0]  # a robot on its goal: offset 0, its window's centre marked
    offsets = goal_offsets(cell_keys(w, h), cells, cell_keys(w, h).take(goals))
    assert ((offsets == 0) == (cells == goals)).all()
    starts = row_starts(cells.size, view.size + view.window.size, view.size).reshape(cells.shape)
    marks = channel_marks(offsets, channel_where(w, h, 2), starts)
    if races == 1:
        cells, goals, racing, marks = cells[0], goals[0], racing[0], marks[0]
    with mock.patch.object(observe, "_LEVEL_ROWS_BYTES", table_bytes):
        observe.level_rows.cache_clear()
        want = observe.local_observations(view, cells, racing, extra=view.window.size, goals=goals)
        got = observe.local_observations(view, cells, racing, extra=view.window.size, marks=marks)
    observe.level_rows.cache_clear()
    assert (got == want).all() and (got[..., view.size :] == target_channel(table, cells, goals, 2)).all()


def test_local_rows_of_many_races_at_once_equal_each_race_alone():
    table = compile_level(__import__("babyrobot_marl").levels.get("mixed-8x8"))
    view = observe.local_view(table, 2)
    g = np.random.default_rng(0)
    cells = np.stack([g.choice(table.n_cells, 5, replace=False) for _ in range(7)])
    racing = g.random(cells.shape) > 0.3
    together = observe.local_observations(view, cells, racing)
    with mock.patch.object(observe, "_SCRATCH", 1):  # one race per scratch grid
        assert (observe.local_observations(view, cells, racing) == together).all()
    for e in range(7):
        assert (together[e] == observe.local_observations(view, cells[e], racing[e])).all()
    assert together[:, :, 2 + observe._ROBOT :: 6].any()  # robots were seen


@settings(max_examples=200, deadline=None)
@given(crowds_on_levels(max_robots=30), st.integers(0, 6), st.booleans())
def test_nearest_rows_list_the_k_nearest_racing_robots_ties_to_the_lower_number(crowd, k, rings):
    level, cells_xy, racing = crowd
    w, h = level.width, level.height
    xy = np.array(cells_xy, dtype=np.int64)
    # rings: the search used for many robots, forced here on a few
    with mock.patch.object(nearest, "_BRUTE_UP_TO", 0 if rings else nearest._BRUTE_UP_TO):
        got = observe.nearest_observations(xy, np.array(racing), k, w, h)
    for i in range(len(cells_xy)):
        assert got[i].tolist() == reference_nearest(cells_xy, racing, i, k, w, h)
    assert (got < observe.nearest_nvec(w, h, k)).all() and (got >= 0).all()


@pytest.mark.parametrize("n", [200, 1000])
def test_nearest_rows_of_hundreds_of_robots_equal_the_reference(n):
    g = np.random.default_rng(n)
    w = h = 64
    flat = g.choice(w * h, size=n, replace=False)
    xy = np.stack([flat % w, flat // w], axis=1)
    xy[:3] = [[0, 0], [63, 63], [0, 63]]  # corners: far from the crowd, some found by brute force
    racing = g.random(n) > 0.2
    got = observe.nearest_observations(xy, racing, 5, w, h)
    cells_xy = xy.tolist()
    for i in list(range(10)) + list(range(n - 10, n)):
        assert got[i].tolist() == reference_nearest(cells_xy, racing.tolist(), i, 5, w, h)


def test_local_view_is_computed_once_per_table_and_radius():
    table = compile_level(__import__("babyrobot_marl").levels.get("maze-8x8"))
    assert observe.local_view(table, 2) is observe.local_view(table, 2)
    assert observe.local_view(table, 1) is not observe.local_view(table, 2)
