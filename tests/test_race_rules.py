"""The race's collision rules (DESIGN.md, "Collisions in a race"), checked on hand-built positions,
over long random races, and against an independent brute-force reading of the rules."""

from __future__ import annotations

from collections import defaultdict
from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import Action
from babyrobot_marl.core import race as race_core
from babyrobot_marl.core import rng
from babyrobot_marl.core.level import Level
from babyrobot_marl.core.outcomes import OUTCOME_NAMES
from babyrobot_marl.envs.race import RaceEnv
from tests.strategies import OPEN, resolve_all_robots

STAY, NORTH, EAST, SOUTH, WEST = (int(a) for a in (Action.STAY, Action.NORTH, Action.EAST, Action.SOUTH, Action.WEST))
MODES = ("block", "bounce", "pass", "soft")
EXCLUSIVE = ("block", "bounce", "soft")  # the modes under which robots never share a cell

# Levels without puddles or glass walls: every robot's own move is certain, so the only
# randomness left in a step is the "block" draw.
CORRIDOR = """
+-+-+-+-+-+-+-+
|0 1 2 3     E|
+-+-+-+-+-+-+-+
"""  # one row, x = 0..6, exit at x = 6
TWO_EXITS = """
+-+-+-+-+-+-+-+
|E 0 1 2     E|
+-+-+-+-+-+-+-+
"""  # one row, exits at both ends

AGENTS = [f"robot_{i}" for i in range(10)]


def race(level: str, n: int, mode: str, seed: int = 0, **kw) -> RaceEnv:
    env = RaceEnv(level=level, n_robots=n, collisions=mode, **kw)
    env.reset(seed=seed)
    return env


def step(env: RaceEnv, *actions: int):
    """One step with robot i taking actions[i] (robots no longer in agents are skipped)."""
    return env.step({a: act for a, act in zip(AGENTS, actions) if a in env.agents})


def blocked(infos) -> list[bool]:
    return [infos[a]["blocked"] for a in sorted(infos)]


# ------------------------------------------------------------------------ hand-built positions
def test_levels_used_here_have_no_randomness_of_their_own():
    for text in (CORRIDOR, TWO_EXITS, OPEN):
        level = Level.from_ascii(text)
        assert not (level.small_puddles or level.large_puddles or level.glass)


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_two_robots_swapping_cells_both_stay_and_are_blocked(mode):
    env = race(CORRIDOR, 2, mode)
    env.set_cells([(1, 0), (2, 0)])
    _, rewards, _, _, infos = step(env, EAST, WEST)
    assert env.robot_cells == [(1, 0), (2, 0)]
    assert blocked(infos) == [True, True]
    assert rewards == {"robot_0": -1.0, "robot_1": -1.0}  # each pays its own floor cell


def test_two_robots_swap_freely_under_pass():
    env = race(CORRIDOR, 2, "pass")
    env.set_cells([(1, 0), (2, 0)])
    _, _, _, _, infos = step(env, EAST, WEST)
    assert env.robot_cells == [(2, 0), (1, 0)]
    assert blocked(infos) == [False, False]


@pytest.mark.parametrize("mode", MODES)
def test_a_robot_follows_into_the_cell_its_occupant_leaves(mode):
    env = race(CORRIDOR, 3, mode)
    env.set_cells([(1, 0), (2, 0), (3, 0)])
    _, _, _, _, infos = step(env, EAST, EAST, EAST)
    assert env.robot_cells == [(2, 0), (3, 0), (4, 0)]
    assert blocked(infos) == [False, False, False]


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_a_robot_may_not_enter_the_cell_of_a_robot_that_stays(mode):
    env = race(CORRIDOR, 2, mode)
    env.set_cells([(1, 0), (2, 0)])
    _, _, _, _, infos = step(env, EAST, STAY)
    assert env.robot_cells == [(1, 0), (2, 0)]
    assert blocked(infos) == [True, False]  # robot 1 chose to stay: nobody stopped it


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_a_chain_behind_a_robot_stuck_at_a_wall_all_stays(mode):
    # C at the west border bumps into it; B wants C's cell, A wants B's: the whole chain stays.
    env = race(CORRIDOR, 3, mode)
    env.set_cells([(2, 0), (1, 0), (0, 0)])
    _, _, _, _, infos = step(env, WEST, WEST, WEST)
    assert env.robot_cells == [(2, 0), (1, 0), (0, 0)]
    assert blocked(infos) == [True, True, False]  # C was stopped by the wall, not by a robot
    assert OUTCOME_NAMES[infos["robot_2"]["outcome"]] == "bumped"


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_a_chain_behind_a_staying_robot_all_stays(mode):
    env = race(CORRIDOR, 4, mode)
    env.set_cells([(1, 0), (2, 0), (3, 0), (4, 0)])
    _, _, _, _, infos = step(env, EAST, EAST, EAST, STAY)
    assert env.robot_cells == [(1, 0), (2, 0), (3, 0), (4, 0)]
    assert blocked(infos) == [True, True, True, False]


def test_under_pass_a_robot_enters_the_cell_of_a_staying_robot():
    env = race(CORRIDOR, 2, "pass")
    env.set_cells([(1, 0), (2, 0)])
    step(env, EAST, STAY)
    assert env.robot_cells == [(2, 0), (2, 0)]
    state = env.state().reshape(2, 3)
    assert state.tolist() == [[2, 0, 0], [2, 0, 0]]


def test_under_pass_robots_sharing_a_cell_move_independently():
    env = race(OPEN, 3, "pass")
    env.set_cells([(2, 2), (2, 2), (2, 2)])  # pass allows placing robots together
    _, _, _, _, infos = step(env, NORTH, EAST, STAY)
    assert env.robot_cells == [(2, 1), (3, 2), (2, 2)]
    assert blocked(infos) == [False, False, False]


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_set_cells_refuses_shared_cells_when_robots_interact(mode):
    env = race(OPEN, 2, mode)
    with pytest.raises(ValueError, match="share"):
        env.set_cells([(2, 2), (2, 2)])


@pytest.mark.parametrize("mode", MODES)
def test_four_robots_rotating_round_a_square_all_move(mode):
    # (1,1) -> (2,1) -> (2,2) -> (1,2) -> (1,1): no two robots swap, and each follows one that leaves.
    env = race(OPEN, 4, mode)
    env.set_cells([(1, 1), (2, 1), (2, 2), (1, 2)])
    _, _, _, _, infos = step(env, EAST, SOUTH, WEST, NORTH)
    assert env.robot_cells == [(2, 1), (2, 2), (1, 2), (1, 1)]
    assert blocked(infos) == [False] * 4


@pytest.mark.parametrize("mode", EXCLUSIVE)
def test_a_rotation_stops_entirely_when_one_robot_in_it_stays(mode):
    env = race(OPEN, 4, mode)
    env.set_cells([(1, 1), (2, 1), (2, 2), (1, 2)])
    _, _, _, _, infos = step(env, EAST, SOUTH, STAY, NORTH)
    # robot 2 stays, so robot 1 may not enter its cell, so robot 0 may not enter robot 1's, so robot 3 may not enter robot 0's
    assert env.robot_cells == [(1, 1), (2, 1), (2, 2), (1, 2)]
    assert blocked(infos) == [True, True, False, True]


def test_contest_for_a_cell_under_bounce_stops_every_contender():
    env = race(CORRIDOR, 2, "bounce")
    env.set_cells([(1, 0), (3, 0)])
    _, _, _, _, infos = step(env, EAST, WEST)
    assert env.robot_cells == [(1, 0), (3, 0)]
    assert blocked(infos) == [True, True]


def test_contest_for_a_cell_under_pass_lets_every_contender_in():
    env = race(OPEN, 3, "pass")
    env.set_cells([(1, 2), (3, 2), (2, 1)])
    step(env, EAST, WEST, SOUTH)
    assert env.robot_cells == [(2, 2)] * 3


def test_three_robot_contest_under_bounce_stops_all_three():
    env = race(OPEN, 3, "bounce")
    env.set_cells([(1, 2), (3, 2), (2, 1)])
    _, _, _, _, infos = step(env, EAST, WEST, SOUTH)
    assert env.robot_cells == [(1, 2), (3, 2), (2, 1)]
    assert blocked(infos) == [True, True, True]


def _binomial_bounds(n: int, p: float, sigmas: float = 6.0) -> tuple[float, float]:
    """Wide bounds for a count of successes: the seeds below are fixed, so the test is
    deterministic; 6 standard deviations keep it honest against any seeding change."""
    sd = (n * p * (1 - p)) ** 0.5
    return n * p - sigmas * sd, n * p + sigmas * sd


def _contest_winners(level: str, starts, actions, target, trials_per_episode: int, episodes: int) -> np.ndarray:
    """Wins of each robot in repeated contests for ``target``: exactly one robot must get it."""
    n = len(starts)
    env = RaceEnv(level=level, n_robots=n, collisions="block")
    wins = np.zeros(n, dtype=int)
    for seed in range(episodes):
        env.reset(seed=seed)
        for _ in range(trials_per_episode):
            env.set_cells(list(starts))
            _, _, _, _, infos = step(env, *actions)
            cells = env.robot_cells
            movers = [i for i in range(n) if cells[i] != starts[i]]
            assert len(movers) == 1, f"block: exactly one contender gets the cell, got movers {movers}"
            (winner,) = movers
            assert cells[winner] == target
            assert blocked(infos) == [i != winner for i in range(n)]
            wins[winner] += 1
    return wins


def test_contest_of_two_under_block_gives_the_cell_to_each_robot_about_half_the_time():
    wins = _contest_winners(CORRIDOR, [(1, 0), (3, 0)], [EAST, WEST], (2, 0), trials_per_episode=10, episodes=200)
    lo, hi = _binomial_bounds(2000, 1 / 2)
    assert wins.sum() == 2000
    assert all(lo <= w <= hi for w in wins), wins


def test_contest_of_three_under_block_gives_the_cell_to_each_robot_about_a_third_of_the_time():
    wins = _contest_winners(OPEN, [(1, 2), (3, 2), (2, 1)], [EAST, WEST, SOUTH], (2, 2), trials_per_episode=10, episodes=300)
    lo, hi = _binomial_bounds(3000, 1 / 3)
    assert all(lo <= w <= hi for w in wins), wins


def test_contest_loser_blocks_a_robot_following_it():
    # robots 0 and 1 contest (2,0); robot 2 follows robot 1 into (3,0) only if robot 1 wins.
    env = RaceEnv(level=CORRIDOR, n_robots=3, collisions="block")
    outcomes = set()
    for seed in range(60):
        env.reset(seed=seed)
        env.set_cells([(1, 0), (3, 0), (4, 0)])
        _, _, _, _, infos = step(env, EAST, WEST, WEST)
        cells = env.robot_cells
        if cells[1] == (2, 0):  # robot 1 won: robot 2 follows it
            assert cells == [(1, 0), (2, 0), (3, 0)]
            assert blocked(infos) == [True, False, False]
        else:  # robot 0 won: robot 1 stays, so robot 2 may not enter its cell
            assert cells == [(2, 0), (3, 0), (4, 0)]
            assert blocked(infos) == [False, True, True]
        outcomes.add(cells[1])
    assert len(outcomes) == 2  # both branches were seen


# ------------------------------------------------------------------------ exits, ranks, bonus
def test_two_robots_entering_the_exit_together_under_block_one_finishes_first():
    env = RaceEnv(level=OPEN, n_robots=2, collisions="block")
    winners = set()
    for seed in range(40):
        env.reset(seed=seed)
        env.set_cells([(3, 4), (4, 3)])
        _, rewards, terms, _, infos = step(env, EAST, SOUTH)
        done = [a for a in ("robot_0", "robot_1") if terms[a]]
        assert len(done) == 1
        (winner,) = done
        loser = "robot_1" if winner == "robot_0" else "robot_0"
        assert rewards == {winner: 0.0 + 10.0, loser: -1.0}
        assert infos[winner]["rank"] == 1 and infos[loser]["blocked"] and infos[loser]["rank"] == 0
        assert env.agents == [loser]
        # the exit is a cell like any other, and the finished robot has left it: the loser enters next step
        _, rewards, terms, _, infos = env.step({loser: EAST if loser == "robot_0" else SOUTH})
        assert terms == {loser: True} and rewards == {loser: 0.0} and infos[loser]["rank"] == 2
        assert env.agents == []
        winners.add(winner)
    assert winners == {"robot_0", "robot_1"}


def test_two_robots_entering_the_exit_together_under_bounce_neither_finishes():
    env = race(OPEN, 2, "bounce")
    env.set_cells([(3, 4), (4, 3)])
    _, rewards, terms, _, infos = step(env, EAST, SOUTH)
    assert terms == {"robot_0": False, "robot_1": False}
    assert rewards == {"robot_0": -1.0, "robot_1": -1.0}
    assert blocked(infos) == [True, True]
    assert env.ranks == [0, 0]


def test_two_robots_entering_the_exit_together_under_pass_both_win():
    env = race(OPEN, 2, "pass")
    env.set_cells([(3, 4), (4, 3)])
    _, rewards, terms, _, infos = step(env, EAST, SOUTH)
    assert terms == {"robot_0": True, "robot_1": True}
    assert rewards == {"robot_0": 10.0, "robot_1": 10.0}
    assert infos["robot_0"]["rank"] == infos["robot_1"]["rank"] == 1
    assert env.ranks == [1, 1] and env.agents == []


@pytest.mark.parametrize("mode", MODES)
def test_ranks_are_shared_by_a_finishing_step_and_count_everyone_before(mode):
    # A and B finish in step 1 at the two exits (no contest); C finishes three steps later
    # through the exit A took: the finished A blocks nobody.
    env = race(TWO_EXITS, 3, mode)
    env.set_cells([(1, 0), (5, 0), (3, 0)])
    _, rewards, terms, _, infos = step(env, WEST, EAST, STAY)
    assert terms == {"robot_0": True, "robot_1": True, "robot_2": False}
    assert rewards == {"robot_0": 10.0, "robot_1": 10.0, "robot_2": -1.0}
    assert env.ranks == [1, 1, 0]
    for _ in range(2):
        _, rewards, terms, _, _ = step(env, None, None, WEST)
        assert terms == {"robot_2": False} and rewards == {"robot_2": -1.0}
    _, rewards, terms, _, infos = step(env, None, None, WEST)
    assert terms == {"robot_2": True}
    assert rewards == {"robot_2": 0.0}  # exit reward, no bonus: it was not among the first
    assert infos["robot_2"]["rank"] == 3  # 1 + the two robots that finished before
    assert env.ranks == [1, 1, 3]


@pytest.mark.parametrize("mode", MODES)
def test_later_finishers_together_share_the_next_rank(mode):
    env = race(TWO_EXITS, 3, mode)
    env.set_cells([(1, 0), (4, 0), (2, 0)])
    # step 1: A finishes alone; C follows into the cell A left; B moves on
    _, _, terms, _, infos = step(env, WEST, EAST, WEST)
    assert terms == {"robot_0": True, "robot_1": False, "robot_2": False}
    assert env.robot_cells[2] == (1, 0) and not infos["robot_2"]["blocked"]
    # step 2: B and C finish at different exits in the same step: both second
    _, rewards, terms, _, infos = step(env, None, EAST, WEST)
    assert terms == {"robot_1": True, "robot_2": True}
    assert infos["robot_1"]["rank"] == infos["robot_2"]["rank"] == 2
    assert rewards == {"robot_1": 0.0, "robot_2": 0.0}
    assert env.ranks == [1, 2, 2]


@pytest.mark.parametrize("bonus", [0.0, 3.5])
def test_win_bonus_is_configurable_and_goes_only_to_the_first_finishers(bonus):
    env = race(TWO_EXITS, 2, "block", win_bonus=bonus, exit_reward=1.0)
    env.set_cells([(1, 0), (4, 0)])
    _, rewards, _, _, _ = step(env, WEST, EAST)
    assert rewards == {"robot_0": 1.0 + bonus, "robot_1": -1.0}
    _, rewards, _, _, _ = step(env, None, EAST)
    assert rewards == {"robot_1": 1.0}
    assert env.returns == [1.0 + bonus, -1.0 + 1.0]


# ------------------------------------------------------------------------ random races: invariants
RACE_SETUPS = [
    ("race-2", 2, "level"),
    ("race-4", 4, "level"),
    ("race-corridor", 4, "level"),
    ("maze-8x8", 6, "random"),
]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("level", "n", "start"), RACE_SETUPS)
def test_random_races_keep_the_rules_of_a_step(level, n, start, mode):
    """Thousands of random steps: no two racing robots share a cell (block, bounce), each robot
    moves at most to an open neighbour, a blocked robot stays, finished robots never come back."""
    env = RaceEnv(level=level, n_robots=n, collisions=mode, start=start)
    lvl = env.level
    actions_rng = np.random.default_rng(12345)
    steps = n_blocked = n_finished = 0
    seed = 0
    while steps < 2500:
        env.reset(seed=seed)
        seed += 1
        gone: set[str] = set()
        prev = env.robot_cells
        while env.agents:
            live = list(env.agents)
            actions = {a: int(actions_rng.integers(5)) for a in live}
            _, _, terms, truncs, infos = env.step(actions)
            steps += 1
            cells = env.robot_cells
            state = env.state().reshape(n, 3)
            assert set(terms) == set(live) and not (gone & set(env.agents))
            for i in range(n):
                agent = f"robot_{i}"
                if agent in gone:
                    assert cells[i] == prev[i] and state[i, 2] == 1  # parked where it finished
                    continue
                allowed = {prev[i]} | {c for c, _ in lvl.neighbours(prev[i])}
                assert cells[i] in allowed, f"{agent} jumped from {prev[i]} to {cells[i]}"
                outcome, was_blocked = OUTCOME_NAMES[infos[agent]["outcome"]], infos[agent]["blocked"]
                if was_blocked:  # stopped by another robot: it stays, and it had meant to move
                    assert mode != "pass" and cells[i] == prev[i] and outcome in ("moved", "skidded")
                    n_blocked += 1
                elif outcome == "moved":
                    assert cells[i] != prev[i]
                elif outcome in ("stayed", "bumped", "glass"):
                    assert cells[i] == prev[i]
                assert terms[agent] == (cells[i] in lvl.exits) == bool(state[i, 2])
                if terms[agent]:
                    gone.add(agent)
                    n_finished += 1
                else:
                    assert truncs[agent] == (env.elapsed_steps >= env.max_cycles)
            racing = [cells[i] for i in range(n) if f"robot_{i}" not in gone]
            if mode != "pass":
                assert len(set(racing)) == len(racing), f"robots share a cell: {cells}"
            assert set(env.agents) == {f"robot_{i}" for i in range(n)} - gone or env.agents == []
            prev = cells
    assert n_finished > 0
    if mode != "pass":
        assert n_blocked > 0  # the rules were actually exercised


# ------------------------------------------------------------------------ resolve_collisions itself
def reference_resolve(mode, cells, desired, racing, priority):
    """DESIGN.md's rules by brute force: start with every racing robot that wants to move, and
    take back moves until nothing changes. A move is taken back when the cell's occupant stays,
    when two robots would swap, or (block: all but the highest ``priority``; soft: all but the
    lowest robot number; bounce: all) when several robots head for one cell. Robots not racing
    are off the board."""
    n = len(cells)
    if mode == "pass":
        return list(desired)
    live = [i for i in range(n) if racing[i]]
    occupant = {cells[i]: i for i in live}
    moving = {i for i in live if desired[i] != cells[i]}
    while True:
        stop = set()
        heading = defaultdict(list)
        for i in moving:
            heading[desired[i]].append(i)
            j = occupant.get(desired[i])
            if j is not None and (j not in moving or desired[j] == cells[i]):
                stop.add(i)
        for group in heading.values():
            if len(group) > 1:
                keep = set() if mode == "bounce" else {min(group)} if mode == "soft" else {max(group, key=priority)}
                stop.update(set(group) - keep)
        if not stop:
            break
        moving -= stop
    return [desired[i] if i in moving else cells[i] for i in range(n)]


@st.composite
def configurations(draw):
    """Abstract cells 0..7: racing robots on distinct cells, finished robots anywhere (they may
    sit on a racing robot's cell), desired cells anywhere (neighbours or not)."""
    n = draw(st.integers(1, 6))
    racing = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    distinct = draw(st.permutations(range(8)))
    cells = [distinct[i] if racing[i] else draw(st.integers(0, 7)) for i in range(n)]
    desired = [draw(st.integers(0, 7)) if racing[i] else cells[i] for i in range(n)]
    key = draw(st.integers(0, 2**64 - 1))
    step_no = draw(st.integers(0, 10_000))
    return cells, desired, racing, key, step_no


@settings(max_examples=600, deadline=None)
@given(configurations(), st.sampled_from(MODES))
def test_resolve_collisions_agrees_with_a_brute_force_reading_of_the_rules(config, mode):
    cells, desired, racing, key, step_no = config
    n = len(cells)

    def priority(i):  # DESIGN: uniform draw; the package ranks contenders by this number
        return rng.uniform(key, (step_no * n + i) * 4 + 3)

    got = resolve_all_robots(mode, list(cells), list(desired), list(racing), key, step_no)
    assert list(got) == reference_resolve(mode, cells, desired, racing, priority)
    if mode != "pass":
        final = [got[i] for i in range(n) if racing[i]]
        assert len(set(final)) == len(final)


@settings(max_examples=300, deadline=None)
@given(configurations(), st.sampled_from(("block", "bounce")), st.data())
def test_resolve_collisions_does_not_depend_on_the_order_of_the_robots(config, mode, data):
    """Relabelling the robots (each keeping its priority) relabels the result (not under soft, whose
    contests go to the lowest robot number)."""
    cells, desired, racing, key, step_no = config
    n = len(cells)
    prio = data.draw(st.permutations(range(n)), label="priorities")  # distinct, like 53-bit uniforms
    perm = data.draw(st.permutations(range(n)), label="relabelling")  # robot i becomes robot perm[i]
    inv = [0] * n
    for i, p in enumerate(perm):
        inv[p] = i

    def permuted(xs):
        return [xs[inv[j]] for j in range(n)]

    with mock.patch.object(race_core, "_priority", lambda key, step, n, robot: prio[robot]):
        got = list(resolve_all_robots(mode, list(cells), list(desired), list(racing), key, step_no))
    permuted_prio = permuted(prio)
    with mock.patch.object(race_core, "_priority", lambda key, step, n, robot: permuted_prio[robot]):
        got_permuted = list(
            resolve_all_robots(mode, permuted(cells), permuted(desired), permuted(racing), key, step_no)
        )
    # the patched priorities did rank the contenders (else this test would check nothing)
    assert got == reference_resolve(mode, cells, desired, racing, prio.__getitem__)
    assert got_permuted == permuted(got)


def test_resolve_collisions_reference_sees_the_hand_built_cases():
    """The reference itself, on the cases of DESIGN.md (so the differential test compares with
    something that reads the rules right)."""
    first = [1.0, 0.0, 0.5].__getitem__
    # a swap: both stay
    assert reference_resolve("block", [0, 1], [1, 0], [True, True], first) == [0, 1]
    # following: both move
    assert reference_resolve("block", [0, 1], [1, 2], [True, True], first) == [1, 2]
    # behind a staying robot: stays
    assert reference_resolve("bounce", [0, 1], [1, 1], [True, True], first) == [0, 1]
    # a contest: block gives it to the highest priority, bounce to nobody
    assert reference_resolve("block", [0, 2, 4], [1, 1, 1], [True] * 3, first) == [1, 2, 4]
    assert reference_resolve("bounce", [0, 2, 4], [1, 1, 1], [True] * 3, first) == [0, 2, 4]
    # a three-cycle moves (no swap, each follows)
    assert reference_resolve("block", [0, 1, 2], [1, 2, 0], [True] * 3, first) == [1, 2, 0]
    # a finished robot on the cell blocks nobody
    assert reference_resolve("block", [0, 1], [1, 1], [True, False], first) == [1, 1]
