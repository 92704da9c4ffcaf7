"""Collision rules in crowds: long queues, long rotations and dense crowds of tens to hundreds of
robots, in both numberings, against the brute-force reading of the rules (``reference_resolve``)
for the scalar rules (``core.race``) and the batch engine's (``core.batch``)."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import OUTCOME_NAMES
from babyrobot_marl.core import race as race_core
from babyrobot_marl.core import rng
from babyrobot_marl.core.batch import resolve_collisions_array
from babyrobot_marl.envs.race import RaceEnv
from tests.strategies import resolve_all_robots
from tests.test_race_rules import configurations, reference_resolve

EXCLUSIVE = ("block", "bounce", "soft")


def both_engines(mode, cells, desired, racing, key=12345, step=7):
    """The result, after checking that the scalar rules (numpy above ``_ARRAYS_FROM`` racing robots,
    dicts below), the dict-based path alone and the batch engine all equal the brute-force reference."""
    n = len(cells)

    def priority(i):
        return rng.uniform(key, (step * n + i) * rng.SLOTS + rng.SLOT_PRIORITY)

    expected = reference_resolve(mode, cells, desired, racing, priority)
    scalar = list(resolve_all_robots(mode, list(cells), list(desired), list(racing), key, step))
    with mock.patch.object(race_core, "_ARRAYS_FROM", 10**9):  # the dict-based path at any size
        dicts = list(resolve_all_robots(mode, list(cells), list(desired), list(racing), key, step))
    for label, path in on_arrays(mode, cells, desired, racing, key, step).items():
        assert path == expected, label
    array = resolve_collisions_array(
        mode,
        np.array([cells]),
        np.array([desired]),
        np.array([racing]),
        np.array([key], dtype=np.uint64),
        np.array([step]),
    )[0].tolist()
    assert scalar == expected
    assert dicts == expected
    assert array == expected
    return expected


def on_arrays(mode, cells, desired, racing, key, step) -> dict[str, list[int]]:
    """The result through the array paths of the scalar rules at any size: the movers that can be stopped
    found on arrays, then resolved one by one, or on arrays too."""
    got = {}
    for label, one_by_one in (("arrays, one by one", 10**9), ("arrays throughout", -1)):
        with mock.patch.object(race_core, "_ARRAYS_FROM", 0), mock.patch.object(race_core, "_ONE_BY_ONE_UP_TO", one_by_one):
            got[label] = list(resolve_all_robots(mode, list(cells), list(desired), list(racing), key, step))
    return got


@settings(max_examples=600, deadline=None)
@given(configurations(), st.sampled_from(EXCLUSIVE))
def test_the_array_paths_agree_with_the_reference_on_small_configurations(config, mode):
    """Swaps, contests, chains and cycles of a few robots, some finished, through both array paths."""
    cells, desired, racing, key, step = config
    n = len(cells)

    def priority(i):
        return rng.uniform(key, (step * n + i) * rng.SLOTS + rng.SLOT_PRIORITY)

    expected = reference_resolve(mode, cells, desired, racing, priority)
    for label, got in on_arrays(mode, cells, desired, racing, key, step).items():
        assert got == expected, label


def queue(n: int, head_highest: bool, head: str):
    """Robots on cells 0..n-1 of a row, each heading for the next cell; the head (on cell n-1)
    stays (``"stay"``), moves on to a free cell (``"free"``), or swaps with the robot behind (``"swap"``).
    ``head_highest``: robot k sits on cell k (the head is robot n-1), else on cell n-1-k."""
    cells = list(range(n)) if head_highest else list(range(n - 1, -1, -1))
    target = {"stay": n - 1, "free": n, "swap": n - 2}[head]
    desired = [c + 1 if c < n - 1 else target for c in cells]
    return cells, desired


@pytest.mark.parametrize("mode", EXCLUSIVE)
@pytest.mark.parametrize("head_highest", [True, False])
@pytest.mark.parametrize("head", ["stay", "free", "swap"])
def test_a_long_queue_resolves_as_the_reference_says_in_both_numberings(mode, head_highest, head):
    n = 300
    cells, desired = queue(n, head_highest, head)
    got = both_engines(mode, cells, desired, [True] * n)
    if head == "free":
        assert got == desired  # everyone follows the head
    else:
        assert got == cells  # the stop at the head runs down the whole queue


@pytest.mark.parametrize("mode", EXCLUSIVE)
@pytest.mark.parametrize("head_highest", [True, False])
def test_a_queue_with_a_contest_at_its_head_and_a_finished_robot_on_the_way(mode, head_highest):
    n = 200
    cells, desired = queue(n, head_highest, "free")
    racing = [True] * n
    # a rival from the side heads for the head's destination too, and a finished robot sits in the queue
    cells, desired, racing = cells + [10_000], desired + [n], racing + [True]
    cells, desired, racing = cells + [50], desired + [50], racing + [False]
    got = both_engines(mode, cells, desired, racing)
    head = cells.index(n - 1)
    if mode == "bounce":
        assert got[:n] == cells[:n]  # nobody gets the contested cell: the whole queue stays
    else:
        won = got[head] == n
        assert got[:n] == (desired[:n] if won else cells[:n])
        assert got[n] == (cells[n] if won else n)


@pytest.mark.parametrize("mode", EXCLUSIVE)
@pytest.mark.parametrize("n", [3, 4, 9, 257])
def test_a_long_rotation_turns_and_one_staying_robot_stops_all_of_it(mode, n):
    cells = list(range(n))
    desired = [(c + 1) % n for c in cells]
    assert both_engines(mode, cells, desired, [True] * n) == desired
    desired[n // 2] = cells[n // 2]
    assert both_engines(mode, cells, desired, [True] * n) == cells
    reverse = list(range(n - 1, -1, -1))  # the same, numbered the other way round
    assert both_engines(mode, reverse, [(c + 1) % n for c in reverse], [True] * n) == [(c + 1) % n for c in reverse]


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_a_queue_feeding_into_a_rotation_follows_it(mode):
    ring = list(range(8))
    ring_desired = [(c + 1) % 8 for c in ring]
    tail = list(range(100, 140))  # 100 -> 101 -> ... -> 139 -> ring cell 0's occupant's cell
    tail_desired = [c + 1 for c in tail[:-1]] + [0]
    # the tail's head contests ring cell 0 with robot 7 of the ring
    got = both_engines(mode, ring + tail, ring_desired + tail_desired, [True] * 48)
    assert len(set(got)) == len(got)


@st.composite
def crowds(draw):
    """A patch of a grid crowded with 9 to 60 robots (more than the array engine's pair-by-pair
    pre-check handles), each heading for a neighbour or staying; some finished."""
    width = draw(st.integers(4, 12))
    n = draw(st.integers(9, min(60, width * width)))
    cells = draw(st.lists(st.integers(0, width * width - 1), min_size=n, max_size=n, unique=True))
    racing = [draw(st.integers(0, 9)) > 0 for _ in range(n)]  # about one in ten finished
    desired = []
    for c, r in zip(cells, racing):
        x, y = c % width, c // width
        around = ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1))
        options = [c] + [nx + ny * width for nx, ny in around if 0 <= nx < width and 0 <= ny < width]
        desired.append(draw(st.sampled_from(options)) if r else c)
    return cells, desired, racing, draw(st.integers(0, 2**64 - 1)), draw(st.integers(0, 1000))


@settings(max_examples=300, deadline=None)
@given(crowds(), st.sampled_from(EXCLUSIVE))
def test_crowds_of_tens_of_robots_follow_the_reference_in_both_engines(crowd, mode):
    cells, desired, racing, key, step = crowd
    got = both_engines(mode, cells, desired, racing, key, step)
    final = [got[i] for i in range(len(cells)) if racing[i]]
    assert len(set(final)) == len(final)


def test_many_crowded_envs_at_once_equal_each_env_alone():
    """The array engine keys cells by env: robots of different envs never meet."""
    g = np.random.default_rng(3)
    n_envs, n, width = 40, 30, 7
    cells = np.stack([g.choice(width * width, size=n, replace=False) for _ in range(n_envs)])
    step_dirs = np.array([0, -width, 1, width, -1])
    desired = cells + step_dirs[g.integers(0, 5, size=cells.shape)]
    desired = np.where((desired >= 0) & (desired < width * width), desired, cells)
    racing = g.random(cells.shape) > 0.1
    desired = np.where(racing, desired, cells)
    keys = g.integers(0, 2**63, size=n_envs, dtype=np.uint64)
    steps = g.integers(0, 100, size=n_envs)
    for mode in EXCLUSIVE:
        got = resolve_collisions_array(mode, cells, desired, racing, keys, steps)
        for e in range(n_envs):
            row = (cells[e].tolist(), desired[e].tolist(), racing[e].tolist())
            alone = resolve_all_robots(mode, *row, int(keys[e]), int(steps[e]))
            assert got[e].tolist() == alone


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_a_queue_of_hundreds_in_a_race_env_stays_behind_its_head_whatever_the_numbering(mode):
    """The rules in a real race: a corridor full of robots all pressing west, the first against the wall."""
    n = 120
    text = "\n".join(["+" + "-+" * (n + 1), "|" + " " * (2 * n) + "E|", "+" + "-+" * (n + 1)])
    for xs in (list(range(n)), list(range(n - 1, -1, -1))):  # the head (x = 0) is robot 0, then robot n-1
        env = RaceEnv(level=text, n_robots=n, collisions=mode, start="random", max_cycles=5)
        env.reset(seed=0)
        env.set_cells([(x, 0) for x in xs])
        _, _, _, _, infos = env.step(dict.fromkeys(env.agents, 4))
        assert env.robot_cells == [(x, 0) for x in xs]
        head = xs.index(0)
        assert [infos[a]["blocked"] for a in env.agents] == [i != head for i in range(n)]
        assert OUTCOME_NAMES[infos[env.agents[head]]["outcome"]] == "bumped"  # into the wall
