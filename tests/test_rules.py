"""The rules of a step (DESIGN.md): walls, glass, blocked cells, borders, skids, rewards, exits, truncation.

Expected distributions are derived by hand from the rules on tiny levels; frequencies are checked
with a binomial 5-sigma bound per outcome (seeded, so never flaky; a wrong probability of even
0.05 is far outside the bound at these sample sizes).
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import pytest

from babyrobot_marl import Action, BabyRobotEnv, Level, Rules, levels
from babyrobot_marl.core.outcomes import OUTCOME_NAMES
from babyrobot_marl.core.rules import COLLISION_MODES

DELTA = {Action.STAY: (0, 0), Action.NORTH: (0, -1), Action.EAST: (1, 0), Action.SOUTH: (0, 1), Action.WEST: (-1, 0)}

# A puddle at (1,1): wall to its north, glass to its west, open to the east and south.
SKID_TEXT = """
+-+-+-+
|S    |
+ +-+ +
| *p  |
+ + + +
|    E|
+-+-+-+
"""

OPEN_TEXT = """
+-+-+-+
|S    |
+ + + +
|     |
+ + + +
|    E|
+-+-+-+
"""

# A puddle at (1,0) whose only non-glass neighbour is the start to its west; glass to the exit east.
DEAD_END_TEXT = """
+-+-+-+
|S p*E|
+-+-+-+
"""

CORRIDOR_TEXT = """
+-+-+-+-+-+
|S p P . E|
+-+-+-+-+-+
"""

NO_SKID = {"small_puddle_move_prob": 1.0, "large_puddle_move_prob": 1.0}


def edge(a, b):
    return (a, b) if a < b else (b, a)


def assert_binomial(count: int, n: int, p: float, what: str = "") -> None:
    if p <= 0.0:
        assert count == 0, what
    elif p >= 1.0:
        assert count == n, what
    else:
        sigma = math.sqrt(n * p * (1 - p))
        assert abs(count - n * p) <= 5 * sigma, f"{what}: {count} of {n}, expected {n * p:.1f} +- {5 * sigma:.1f}"


def assert_distribution(counts: Counter, n: int, expected: dict) -> None:
    assert sum(counts.values()) == n
    assert set(counts) <= {k for k, p in expected.items() if p > 0}, f"unexpected outcomes {set(counts) - set(expected)}"
    assert math.isclose(sum(expected.values()), 1.0)
    for k, p in expected.items():
        assert_binomial(counts.get(k, 0), n, p, str(k))


def one_step_counts(env: BabyRobotEnv, start, action, n: int, seed: int = 0):
    """Where one step from ``start`` ends, and with which outcome label, over ``n`` seeded episodes."""
    env.reset(seed=seed)
    cells, labels = Counter(), Counter()
    for _ in range(n):
        env.reset(options={"start": start})
        obs, _, _, _, info = env.step(action)
        assert tuple(info["cell"].tolist()) == tuple(obs.tolist())
        cells[tuple(info["cell"].tolist())] += 1
        labels[OUTCOME_NAMES[info["outcome"]]] += 1
    return cells, labels


# --------------------------------------------------------------------------------------- Rules values
def test_default_rules_are_the_ones_in_design_md():
    r = Rules()
    assert (r.floor_reward, r.small_puddle_reward, r.large_puddle_reward, r.exit_reward) == (-1.0, -2.0, -4.0, 0.0)
    assert (r.small_puddle_move_prob, r.large_puddle_move_prob, r.glass_pass_prob) == (0.6, 0.4, 0.5)
    assert r.collisions == "block"
    assert set(COLLISION_MODES) == {"block", "bounce", "pass", "soft"}


PROBABILITIES = ["small_puddle_move_prob", "large_puddle_move_prob", "glass_pass_prob"]
REWARDS = ["floor_reward", "small_puddle_reward", "large_puddle_reward", "exit_reward", "win_bonus"]


@pytest.mark.parametrize("field", PROBABILITIES)
@pytest.mark.parametrize("value", [-0.1, 1.0000001, 2, float("nan"), float("inf"), "0.5", None, True, [0.5]])
def test_probability_out_of_range_or_not_a_number_is_a_value_error_naming_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        Rules(**{field: value})
    with pytest.raises(ValueError, match=field):
        Rules().replace(**{field: value})


@pytest.mark.parametrize("field", REWARDS)
@pytest.mark.parametrize("value", [float("nan"), float("-inf"), "-1", None, False])
def test_reward_that_is_not_a_finite_number_is_a_value_error_naming_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        Rules(**{field: value})


@pytest.mark.parametrize("field", PROBABILITIES)
@pytest.mark.parametrize("value", [0, 1, 0.0, 1.0, 0.3])
def test_probability_bounds_are_allowed_and_stored_as_float(field, value):
    stored = getattr(Rules(**{field: value}), field)
    assert stored == value and type(stored) is float


@pytest.mark.parametrize("mode", ["crash", "", None, 1, "BLOCK"])
def test_bad_collisions_mode_is_a_value_error_naming_the_field(mode):
    with pytest.raises(ValueError, match="collisions"):
        Rules(collisions=mode)


def test_unknown_rule_name_is_an_error_naming_it():
    with pytest.raises(TypeError, match="glass_pass_probability"):
        Rules().replace(glass_pass_probability=0.3)
    with pytest.raises(TypeError, match="glass_pass_probability"):
        BabyRobotEnv(glass_pass_probability=0.3)
    with pytest.raises(TypeError, match="wind"):
        BabyRobotEnv(rules={"wind": 0.3})


def test_bad_rule_through_the_env_names_the_field():
    with pytest.raises(ValueError, match="glass_pass_prob"):
        BabyRobotEnv(glass_pass_prob=1.5)
    with pytest.raises(ValueError, match="small_puddle_move_prob"):
        BabyRobotEnv(rules={"small_puddle_move_prob": float("nan")})


def test_rules_are_immutable_and_replace_makes_a_copy():
    r = Rules()
    with pytest.raises(AttributeError):
        r.glass_pass_prob = 1.0
    r2 = r.replace(glass_pass_prob=0.9)
    assert (r.glass_pass_prob, r2.glass_pass_prob) == (0.5, 0.9)


# --------------------------------------------------------------------------------------- moves, walls, borders, blocked
def test_actions_are_the_contract_values():
    assert [(a.name, a.value) for a in Action] == [("STAY", 0), ("NORTH", 1), ("EAST", 2), ("SOUTH", 3), ("WEST", 4)]


@pytest.mark.parametrize("action", list(Action))
def test_each_action_moves_the_way_design_md_says(action):
    env = BabyRobotEnv(OPEN_TEXT)
    env.reset(seed=0, options={"start": (1, 1)})
    obs, reward, terminated, _, info = env.step(action)
    dx, dy = DELTA[action]
    assert tuple(obs.tolist()) == (1 + dx, 1 + dy)
    assert OUTCOME_NAMES[info["outcome"]] == ("stayed" if action == Action.STAY else "moved")
    assert info["intended"] is True
    assert reward == -1.0 and not terminated


@pytest.mark.parametrize("action", [Action.NORTH, Action.EAST, Action.SOUTH, Action.WEST])
def test_a_wall_stops_a_move_both_ways_and_the_robot_pays_its_own_cell(action):
    centre = (1, 1)
    dx, dy = DELTA[action]
    neighbour = (1 + dx, 1 + dy)
    walled = Level(width=3, height=3, starts=[centre], exits=[(0, 0)], walls=[edge(centre, neighbour)])
    unwalled = Level(width=3, height=3, starts=[centre], exits=[(0, 0)])
    back = {Action.NORTH: Action.SOUTH, Action.SOUTH: Action.NORTH, Action.EAST: Action.WEST, Action.WEST: Action.EAST}[action]
    for seed in range(10):
        env = BabyRobotEnv(walled)
        env.reset(seed=seed)
        obs, reward, terminated, truncated, info = env.step(action)
        assert tuple(obs.tolist()) == centre
        outcome = OUTCOME_NAMES[info["outcome"]]
        assert (reward, terminated, truncated, outcome, info["intended"]) == (-1.0, False, False, "bumped", False)
        env.reset(options={"start": neighbour})  # the same wall seen from the other side
        obs, *_ = env.step(back)
        assert tuple(obs.tolist()) == neighbour
        control = BabyRobotEnv(unwalled)
        control.reset(seed=seed)
        obs, *_ = control.step(action)
        assert tuple(obs.tolist()) == neighbour


def test_moves_off_the_grid_bump_at_every_border_cell():
    env = BabyRobotEnv(OPEN_TEXT)
    env.reset(seed=0)
    bumps = 0
    for x in range(3):
        for y in range(3):
            if (x, y) == (2, 2):
                continue  # the exit
            for action in (Action.NORTH, Action.EAST, Action.SOUTH, Action.WEST):
                dx, dy = DELTA[action]
                if 0 <= x + dx < 3 and 0 <= y + dy < 3:
                    continue
                env.reset(options={"start": (x, y)})
                obs, reward, _, _, info = env.step(action)
                assert tuple(obs.tolist()) == (x, y) and OUTCOME_NAMES[info["outcome"]] == "bumped" and reward == -1.0
                bumps += 1
    assert bumps == 4 * 3 - 2  # 12 border-facing moves, minus the two from the exit cell


def test_a_blocked_cell_cannot_be_entered_from_any_side():
    level = Level(width=3, height=3, starts=[(0, 0)], exits=[(2, 2)], blocked=[(1, 1)])
    env = BabyRobotEnv(level)
    env.reset(seed=0)
    for start, action in [((1, 0), Action.SOUTH), ((2, 1), Action.WEST), ((1, 2), Action.NORTH), ((0, 1), Action.EAST)]:
        env.reset(options={"start": start})
        obs, reward, _, _, info = env.step(action)
        assert tuple(obs.tolist()) == start and OUTCOME_NAMES[info["outcome"]] == "bumped" and reward == -1.0


@pytest.mark.parametrize("name", ["blocked", "mixed-8x8", "puddles", "glass"])
def test_every_step_of_a_random_walk_obeys_walls_glass_blocked_cells_and_skid_rules(name):
    level = levels.get(name)
    env = BabyRobotEnv(name, start="random", max_steps=10_000)
    obs, _ = env.reset(seed=7)
    rng = np.random.default_rng(7)
    seen = Counter()
    for _ in range(6000):
        action = Action(int(rng.integers(5)))
        prev = tuple(obs.tolist())
        obs, reward, terminated, truncated, info = env.step(action)
        cell = tuple(obs.tolist())
        seen[OUTCOME_NAMES[info["outcome"]]] += 1
        assert cell not in level.blocked
        dx, dy = DELTA[action]
        aimed = (prev[0] + dx, prev[1] + dy)
        if OUTCOME_NAMES[info["outcome"]] in ("stayed", "bumped", "glass"):
            assert cell == prev
        if OUTCOME_NAMES[info["outcome"]] == "stayed":
            assert action == Action.STAY
        if OUTCOME_NAMES[info["outcome"]] == "moved":
            assert cell == aimed
        if OUTCOME_NAMES[info["outcome"]] == "glass":
            assert edge(prev, aimed) in level.glass
        if OUTCOME_NAMES[info["outcome"]] == "skidded":
            assert prev in level.small_puddles | level.large_puddles and action != Action.STAY
            assert cell != aimed
        if cell != prev:
            assert abs(cell[0] - prev[0]) + abs(cell[1] - prev[1]) == 1
            assert edge(prev, cell) not in level.walls
            if edge(prev, cell) in level.glass:
                assert OUTCOME_NAMES[info["outcome"]] == "moved"  # skids never go through glass
        assert terminated == (cell in level.exits)
        if terminated or truncated:
            obs, _ = env.reset()
    expected = {"moved", "stayed", "bumped"} | ({"glass"} if level.glass else set())
    expected |= {"skidded"} if level.small_puddles | level.large_puddles else set()
    assert expected <= set(seen)  # the walk exercised every rule the level has


# --------------------------------------------------------------------------------------- skids
def skid_expectations(m: float, g: float):
    """Hand-derived from DESIGN.md for SKID_TEXT's puddle at (1,1), move probability m, glass g."""
    s = 1 - m
    return {
        Action.EAST: ({(2, 1): m, (1, 2): s}, {"moved": m, "skidded": s}),
        Action.SOUTH: ({(1, 2): m, (2, 1): s}, {"moved": m, "skidded": s}),
        Action.NORTH: ({(1, 1): m, (2, 1): s / 2, (1, 2): s / 2}, {"bumped": m, "skidded": s}),
        Action.WEST: (
            {(0, 1): m * g, (1, 1): m * (1 - g), (2, 1): s / 2, (1, 2): s / 2},
            {"moved": m * g, "glass": m * (1 - g), "skidded": s},
        ),
        Action.STAY: ({(1, 1): 1.0}, {"stayed": 1.0}),
    }


@pytest.mark.parametrize(("puddle", "m"), [("p", 0.6), ("P", 0.4)])
@pytest.mark.parametrize("action", list(Action))
def test_skid_frequencies_match_the_rules_with_default_probabilities(puddle, m, action):
    env = BabyRobotEnv(SKID_TEXT.replace("p", puddle))
    cells, labels = one_step_counts(env, (1, 1), action, n=6000, seed=int(action) + 10 * (puddle == "P"))
    expected_cells, expected_labels = skid_expectations(m, 0.5)[action]
    assert_distribution(cells, 6000, expected_cells)
    assert_distribution(labels, 6000, expected_labels)


@pytest.mark.parametrize(("m", "g"), [(0.0, 0.5), (1.0, 0.5), (0.25, 0.8), (0.9, 0.1)])
@pytest.mark.parametrize("action", [Action.NORTH, Action.WEST, Action.EAST])
def test_skid_frequencies_follow_overridden_probabilities(m, g, action):
    env = BabyRobotEnv(SKID_TEXT, small_puddle_move_prob=m, glass_pass_prob=g)
    cells, labels = one_step_counts(env, (1, 1), action, n=4000, seed=99)
    expected_cells, expected_labels = skid_expectations(m, g)[action]
    assert_distribution(cells, 4000, expected_cells)
    assert_distribution(labels, 4000, expected_labels)


def test_skids_go_uniformly_to_all_three_other_open_neighbours():
    env = BabyRobotEnv(OPEN_TEXT.replace("|     |", "|  P  |"))
    cells, _ = one_step_counts(env, (1, 1), Action.EAST, n=8000, seed=3)
    s = 1 - 0.4
    assert_distribution(cells, 8000, {(2, 1): 0.4, (1, 0): s / 3, (1, 2): s / 3, (0, 1): s / 3})


def test_a_skid_with_no_other_open_neighbour_stays():
    env = BabyRobotEnv(DEAD_END_TEXT)
    # WEST: the only other neighbour is behind glass, so a skid stays put
    cells, labels = one_step_counts(env, (1, 0), Action.WEST, n=4000, seed=5)
    assert_distribution(cells, 4000, {(0, 0): 0.6, (1, 0): 0.4})
    assert_distribution(labels, 4000, {"moved": 0.6, "skidded": 0.4})
    # EAST through the glass: pass 0.6 * 0.5, fail 0.6 * 0.5, skid west 0.4
    cells, labels = one_step_counts(env, (1, 0), Action.EAST, n=4000, seed=6)
    assert_distribution(cells, 4000, {(2, 0): 0.3, (1, 0): 0.3, (0, 0): 0.4})
    assert_distribution(labels, 4000, {"moved": 0.3, "glass": 0.3, "skidded": 0.4})


@pytest.mark.parametrize("m", [0.0, 0.6])
def test_stay_never_skids_even_when_every_move_would(m):
    env = BabyRobotEnv(SKID_TEXT, small_puddle_move_prob=m)
    cells, labels = one_step_counts(env, (1, 1), Action.STAY, n=2000, seed=1)
    assert cells == Counter({(1, 1): 2000}) and labels == Counter({"stayed": 2000})
    env.reset(options={"start": (1, 1)})
    for _ in range(50):
        obs, reward, *_ = env.step(Action.STAY)
        assert tuple(obs.tolist()) == (1, 1) and reward == -2.0


# --------------------------------------------------------------------------------------- glass
GLASS_TEXT = """
+-+-+-+
|S*  E|
+-+-+-+
"""


@pytest.mark.parametrize("g", [0.0, 0.25, 0.5, 0.9, 1.0])
def test_glass_pass_frequency_is_the_glass_probability_in_both_directions(g):
    env = BabyRobotEnv(GLASS_TEXT, glass_pass_prob=g)
    for start, action, other_side in [((0, 0), Action.EAST, (1, 0)), ((1, 0), Action.WEST, (0, 0))]:
        cells, labels = one_step_counts(env, start, action, n=4000, seed=int(g * 100))
        assert_distribution(cells, 4000, {other_side: g, start: 1 - g})
        assert_distribution(labels, 4000, {"moved": g, "glass": 1 - g})


def test_a_failed_glass_pass_pays_the_own_cell_and_is_not_intended():
    env = BabyRobotEnv(GLASS_TEXT, glass_pass_prob=0.0)
    env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(Action.EAST)
    assert (tuple(obs.tolist()), reward, terminated, truncated) == ((0, 0), -1.0, False, False)
    assert (OUTCOME_NAMES[info["outcome"]], info["intended"]) == ("glass", False)


# --------------------------------------------------------------------------------------- rewards, exits, truncation
def walk_corridor(level_or_text, **kwargs):
    env = BabyRobotEnv(level_or_text, **{**NO_SKID, **kwargs})
    env.reset(seed=0)
    steps = [env.step(Action.EAST) for _ in range(4)]
    return [s[1] for s in steps], [s[2] for s in steps], [s[3] for s in steps]


def test_rewards_floor_small_puddle_large_puddle_and_exit():
    rewards, terminated, truncated = walk_corridor(CORRIDOR_TEXT)
    assert rewards == [-2.0, -4.0, -1.0, 0.0]
    assert all(type(r) is float for r in rewards)
    assert terminated == [False, False, False, True]
    assert truncated == [False] * 4


def test_staying_or_bumping_pays_the_reward_of_the_own_cell():
    env = BabyRobotEnv(CORRIDOR_TEXT)
    env.reset(seed=0)
    assert env.step(Action.STAY)[1] == -1.0
    assert env.step(Action.WEST)[1] == -1.0  # into the border
    env.reset(options={"start": (1, 0)})
    assert env.step(Action.STAY)[1] == -2.0
    env.reset(options={"start": (2, 0)})
    assert env.step(Action.STAY)[1] == -4.0


def test_reward_rules_can_be_overridden():
    rewards, _, _ = walk_corridor(
        CORRIDOR_TEXT, floor_reward=-0.5, small_puddle_reward=-3, large_puddle_reward=-7, exit_reward=10
    )
    assert rewards == [-3.0, -7.0, -0.5, 10.0]


def test_custom_cell_rewards_replace_the_rules_reward():
    level = Level.from_ascii(CORRIDOR_TEXT)
    assert walk_corridor(level.with_rewards({(3, 0): 2.5}))[0] == [-2.0, -4.0, 2.5, 0.0]
    assert walk_corridor(level.with_area_reward((3, 0), (1, 0), -10))[0] == [-10.0, -10.0, -10.0, 0.0]
    rewards, terminated, _ = walk_corridor(level.with_rewards({(4, 0): 50}))
    assert rewards == [-2.0, -4.0, -1.0, 50.0] and terminated[-1]
    env = BabyRobotEnv(level.with_rewards({(0, 0): 0.25}))
    env.reset(seed=0)
    assert env.step(Action.STAY)[1] == 0.25


def test_reaching_an_exit_terminates_and_ends_the_episode():
    env = BabyRobotEnv(GLASS_TEXT, glass_pass_prob=1.0)
    env.reset(seed=0)
    assert env.step(Action.EAST)[2] is False  # through the glass onto (1, 0)
    obs, reward, terminated, truncated, info = env.step(Action.EAST)
    assert (tuple(obs.tolist()), reward, terminated, truncated) == ((2, 0), 0.0, True, False)
    assert env.robot_cell == (2, 0)
    with pytest.raises(RuntimeError):
        env.step(Action.STAY)


def test_truncation_at_max_steps():
    env = BabyRobotEnv(OPEN_TEXT, max_steps=3)
    env.reset(seed=0)
    results = [env.step(Action.STAY) for _ in range(3)]
    assert [r[3] for r in results] == [False, False, True]
    assert [r[2] for r in results] == [False, False, False]
    assert all(type(r[2]) is bool and type(r[3]) is bool for r in results)
    with pytest.raises(RuntimeError):
        env.step(Action.STAY)


def test_a_step_that_terminates_on_the_last_allowed_step_is_not_truncated():
    env = BabyRobotEnv(OPEN_TEXT, max_steps=4)  # the exit is exactly 4 moves away
    env.reset(seed=0)
    results = [env.step(a) for a in (Action.EAST, Action.EAST, Action.SOUTH, Action.SOUTH)]
    assert [(r[2], r[3]) for r in results] == [(False, False)] * 3 + [(True, False)]


def test_default_max_steps_is_documented_four_per_cell_at_least_100():
    assert BabyRobotEnv("default").max_steps == 100
    assert BabyRobotEnv("maze-16x16").max_steps == 4 * 256
    env = BabyRobotEnv("default")
    env.reset(seed=0)
    truncated = [env.step(Action.STAY)[3] for _ in range(100)]
    assert truncated == [False] * 99 + [True]
