"""Own goals (``goals="own"``): each robot its own target, drawn or given, observed and hinted as POGEMA does."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.goals import draw_goals, own_goal_table, target_channel
from babyrobot_marl.core.level import Level
from babyrobot_marl.core.table import compile_level
from babyrobot_marl.envs.vector import RaceVectorEnv
from babyrobot_marl.planning import optimal_actions

# a wall of blocked cells cuts the level in two: the right part is out of reach from the starts
SPLIT = """
+-+-+-+-+-+
|0 E #    |
+ + + + + +
|    #    |
+ + + + + +
|1   #    |
+-+-+-+-+-+
"""
# open floor, one exit in a corner: shortest paths are the optimal actions of the one-robot model
OPEN = """
+-+-+-+-+-+-+
|0         E|
+ + + + + + +
|    #      |
+ + + + + + +
|           |
+ + + + + + +
|  #     #  |
+ + + + + + +
|1          |
+-+-+-+-+-+-+
"""


def _moves(level: str | Level, a, b) -> int:
    """Moves between two cells of a level without puddles or glass, by a plain search over cells."""
    lv = race_v0.parallel_env(level=level, n_robots=1, start="fill").level
    seen, frontier, d = {tuple(a)}, [tuple(a)], 0
    while frontier:
        if tuple(b) in frontier:
            return d
        nxt = []
        for cell in frontier:
            for other, _ in lv.neighbours(cell):
                if other not in seen:
                    seen.add(other)
                    nxt.append(other)
        frontier, d = nxt, d + 1
    return -1


# ---------------------------------------------------------------------------- the default is the race
def test_the_default_goals_are_the_exits_and_report_no_own_goals():
    env = race_v0.parallel_env(level="race-4", n_robots=4)
    assert env.goals_mode == "exit" and env.goals is None
    env.reset(seed=0)
    assert env.goals is None


def test_a_bad_goals_argument_is_one_error_naming_goals():
    with pytest.raises(ValueError, match=r"^goals: must be one of 'exit', 'own', got 'mine'$"):
        race_v0.parallel_env(goals="mine")


def test_given_goals_on_the_exit_race_are_refused_by_name():
    env = race_v0.parallel_env(level="race-2", n_robots=2)
    with pytest.raises(ValueError, match=r"options\[\"goals\"\]: own goals need goals='own'"):
        env.reset(seed=0, options={"goals": [(0, 4), (4, 0)]})


# ---------------------------------------------------------------------------- drawn goals
@pytest.mark.parametrize(
    ("level", "n_robots", "start"), [("race-4", 4, "level"), ("mixed-8x8", 6, "random"), (SPLIT, 2, "level")]
)
def test_drawn_goals_are_free_distinct_reachable_and_not_the_start(level, n_robots, start):
    env = race_v0.parallel_env(level=level, n_robots=n_robots, start=start, goals="own")
    t = env.table
    for seed in range(30):
        env.reset(seed=seed)
        goals = [t.cell_id(env.goals[a]) for a in env.possible_agents]
        starts = [t.cell_id(c) for c in env.robot_cells]
        assert len(set(goals)) == n_robots
        for g, s in zip(goals, starts):
            assert g != s and not t.blocked[g] and t.move_prob[g] == 1.0  # free: no puddle
            assert _moves(level, t.cell_xy(s), t.cell_xy(g)) > 0


def test_same_seed_same_goals_and_other_seeds_other_goals():
    def goals(seed):
        env = race_v0.parallel_env(level="mixed-8x8", n_robots=5, start="random", goals="own")
        env.reset(seed=seed)
        return env.goals, env.robot_cells

    assert goals(3) == goals(3)
    assert len({str(goals(s)) for s in range(8)}) == 8


def test_goals_are_drawn_on_exits_too_which_are_floor():
    # the level's exit is a free cell for own goals: over many draws some robot gets it
    env = race_v0.parallel_env(level="race-2", n_robots=2, goals="own")
    exit_cell = next(iter(env.level.exits))
    hits = 0
    for seed in range(100):
        env.reset(seed=seed)
        hits += exit_cell in env.goals.values()
    assert hits > 0


def test_the_draw_trades_when_the_last_free_cell_is_a_robots_own_start():
    # three robots on a level of three free cells: every robot's goal is another robot's start
    three = "+-+-+-+\n|0 E  |\n+-+-+-+\n"
    table = own_goal_table(compile_level(race_v0.parallel_env(level=three, n_robots=1).level))
    for seed in range(40):
        goals = draw_goals(np.random.default_rng(seed), table, [0, 1, 2])
        assert sorted(goals) == [0, 1, 2] and all(g != s for g, s in zip(goals, [0, 1, 2]))


def test_a_robot_with_nothing_left_to_reach_is_an_error_naming_goals():
    boxed = "+-+-+-+\n|0 E #|\n+ + + +\n|  #  |\n+-+-+-+\n"  # (2, 1) is walled in by blocked cells
    table = own_goal_table(compile_level(race_v0.parallel_env(level=boxed, n_robots=1).level))
    assert table.cell_id((2, 1)) not in table.free_cells
    with pytest.raises(ValueError, match=r"^goals: no free cell is left for the robot starting at \(2, 1\)"):
        draw_goals(np.random.default_rng(0), table, [table.cell_id((2, 1))])


# ---------------------------------------------------------------------------- given goals
def test_given_goals_are_used_as_given():
    env = race_v0.parallel_env(level="race-4", n_robots=4, goals="own")
    env.reset(seed=0, options={"goals": [(3, 3), (1, 0), (0, 1), (6, 5)]})
    assert env.goals == {"robot_0": (3, 3), "robot_1": (1, 0), "robot_2": (0, 1), "robot_3": (6, 5)}


@pytest.mark.parametrize(
    ("goals", "message"),
    [
        ([(1, 1)], r"expected 2 distinct cells \(x, y\), one goal per robot, not blocked; got 1 cells"),
        ([(1, 1), (1, 1)], r"two robots share a goal"),
        ([(1, 1), (9, 0)], r"\(9, 0\) is outside the 5x3 grid"),
        ([(1, 1), (2, 1)], r"\(2, 1\) is blocked"),
        ([(3, 0), (1, 1)], r"robot_0's goal \(3, 0\) cannot be reached from its start \(0, 0\)"),
        ([(0, 0), (1, 1)], r"robot_0's goal \(0, 0\) is its start"),
        ("ab", r"expected a list of"),
    ],
)
def test_bad_given_goals_are_one_error_naming_goals_and_the_env_stays_usable(goals, message):
    env = race_v0.parallel_env(level=SPLIT, n_robots=2, goals="own")
    env.reset(seed=0)
    before = (env.goals, env.robot_cells)
    with pytest.raises(ValueError, match=r'^options\["goals"\]: ' + message):
        env.reset(seed=1, options={"goals": goals})
    assert (env.goals, env.robot_cells) == before
    env.step({a: 0 for a in env.agents})  # still usable


def test_given_goals_with_random_starts_never_start_a_robot_on_its_goal():
    env = race_v0.parallel_env(level="race-2", n_robots=2, start="random", goals="own")
    for seed in range(40):
        env.reset(seed=seed, options={"goals": [(0, 0), (4, 4)]})
        assert env.robot_cells[0] != (0, 0) and env.robot_cells[1] != (4, 4)


# ---------------------------------------------------------------------------- finishing and rewards
def test_a_robot_finishes_on_its_own_goal_with_the_exit_reward_and_no_bonus():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own")
    env.reset(seed=0, options={"goals": [(1, 0), (0, 3)]})  # one step east; one step north
    _, rewards, terms, _, infos = env.step({"robot_0": 2, "robot_1": 1})
    assert rewards == {"robot_0": 0.0, "robot_1": 0.0}  # Rules().exit_reward, no win_bonus
    assert terms == {"robot_0": True, "robot_1": True} and env.ranks == [1, 1]


def test_an_exit_and_another_robots_goal_are_floor():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own")
    # robot 0 walks along the top row onto robot 1's goal (2, 0) and on to the exit (5, 0); its own is (5, 2)
    env.reset(seed=0, options={"starts": [(0, 0), (0, 4)], "goals": [(5, 2), (2, 0)]})
    for _ in range(5):
        _, rewards, terms, _, _ = env.step({"robot_0": 2, "robot_1": 0})
        assert rewards["robot_0"] == -1.0 and not terms["robot_0"]
    assert env.robot_cells[0] == (5, 0) and env.agents == ["robot_0", "robot_1"]
    for _ in range(2):
        _, rewards, terms, _, _ = env.step({"robot_0": 3, "robot_1": 0})
    assert rewards["robot_0"] == 0.0 and terms["robot_0"]


def test_freeze_keeps_a_finished_robot_on_its_goal_and_out_of_others_way():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own", finished="freeze")
    env.reset(seed=0, options={"starts": [(0, 0), (2, 0)], "goals": [(1, 0), (0, 0)]})
    env.step({"robot_0": 2, "robot_1": 0})  # robot 0 finishes on (1, 0)
    _, rewards, terms, _, infos = env.step({"robot_0": 0, "robot_1": 4})  # robot 1 passes through it
    assert infos["robot_0"]["finished"] and env.robot_cells == [(1, 0), (1, 0)] and rewards["robot_0"] == 0.0
    _, rewards, terms, _, _ = env.step({"robot_0": 0, "robot_1": 4})
    assert rewards["robot_1"] == 0.0 and terms == {"robot_0": True, "robot_1": True}


# ---------------------------------------------------------------------------- observations
def test_global_and_nearest_rows_end_with_the_goals_xy():
    for kw, size in ((dict(), 2 + 3 * 2), (dict(observe="nearest", k=1), 2 + 2)):
        env = race_v0.parallel_env(level="race-4", n_robots=3, goals="own", **kw)
        exit_env = race_v0.parallel_env(level="race-4", n_robots=3, **kw)
        nvec = env.observation_space("robot_0").nvec
        assert nvec.tolist() == exit_env.observation_space("robot_0").nvec.tolist() + [7, 7]
        obs, _ = env.reset(seed=2)
        for a, row in obs.items():
            assert row.shape == (size + 2,) and tuple(row[-2:]) == env.goals[a]


def test_the_local_target_channel_marks_the_goal_or_its_projection_on_the_border():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own", observe="local", view_radius=1)
    exit_env = race_v0.parallel_env(level=OPEN, n_robots=2, observe="local", view_radius=1)
    assert env.observation_space("robot_0").nvec.tolist() == exit_env.observation_space("robot_0").nvec.tolist() + [2] * 9
    obs, _ = env.reset(seed=0, options={"starts": [(2, 2), (0, 4)], "goals": [(3, 1), (5, 0)]})
    # robot 0: the goal one east, one north: inside the window, row 0 (north), column 2 (east)
    assert obs["robot_0"][-9:].reshape(3, 3).tolist() == [[0, 0, 1], [0, 0, 0], [0, 0, 0]]
    # robot 1 at (0, 4), goal (5, 0): dx 5, dy -4 clamp to the north-east corner
    assert obs["robot_1"][-9:].reshape(3, 3).tolist() == [[0, 0, 1], [0, 0, 0], [0, 0, 0]]
    obs, _ = env.reset(seed=0, options={"starts": [(2, 2), (0, 4)], "goals": [(2, 4), (0, 0)]})
    assert obs["robot_0"][-9:].reshape(3, 3).tolist() == [[0, 0, 0], [0, 0, 0], [0, 1, 0]]  # straight south
    assert obs["robot_1"][-9:].reshape(3, 3).tolist() == [[0, 1, 0], [0, 0, 0], [0, 0, 0]]  # straight north


def test_target_channel_equals_pogemas_clamped_offsets_everywhere():
    rng = np.random.default_rng(0)
    table = compile_level(race_v0.parallel_env(level="maze-16x16", n_robots=1).level)
    w, h, r = table.width, table.height, 2
    ids = np.arange(w * h)
    xy = np.stack([ids % w, ids // w], axis=1)
    cells, goals = rng.integers(0, w * h, 400), rng.integers(0, w * h, 400)
    got = target_channel(table, cells, goals, r).reshape(400, 2 * r + 1, 2 * r + 1)
    # written into wider rows, at a column: the same, and nothing else touched
    wide = np.full((2, 200, 3 + (2 * r + 1) ** 2 + 4), 7, dtype=np.int64)
    target_channel(table, cells.reshape(2, 200), goals.reshape(2, 200), r, wide, 3)
    assert (wide[..., :3] == 7).all() and (wide[..., -4:] == 7).all()
    assert wide[..., 3:-4].reshape(400, 2 * r + 1, 2 * r + 1).tolist() == got.tolist()
    for k in range(400):
        dx, dy = xy[goals[k]] - xy[cells[k]]
        expected = np.zeros((2 * r + 1, 2 * r + 1), dtype=int)
        expected[min(max(dy, -r), r) + r, min(max(dx, -r), r) + r] = 1  # POGEMA's get_square_target, x/y as here
        assert got[k].tolist() == expected.tolist()


def test_an_exit_in_a_local_window_reads_as_floor_with_own_goals():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own", observe="local", view_radius=1)
    obs, _ = env.reset(seed=0, options={"starts": [(4, 0), (0, 4)], "goals": [(0, 0), (5, 4)]})
    window = obs["robot_0"][2 : 2 + 6 * 9].reshape(9, 6)
    assert window[5, 0] == 0  # the exit (5, 0), east of the robot: terrain floor
    exit_env = race_v0.parallel_env(level=OPEN, n_robots=2, observe="local", view_radius=1)
    obs, _ = exit_env.reset(seed=0, options={"starts": [(4, 0), (0, 4)]})
    assert obs["robot_0"][2 : 2 + 6 * 9].reshape(9, 6)[5, 0] == 4  # in the race: the exit code


# ---------------------------------------------------------------------------- the goal hint
def test_the_hint_is_the_optimal_one_robot_action_towards_the_own_goal():
    # the goal on the level's exit: the one-robot model's optimal actions (value iteration) are the hint
    env = race_v0.parallel_env(level=OPEN, n_robots=1, goals="own", observe="local", view_radius=1, hint=True)
    best = optimal_actions(env.level)
    seen = set()
    for x in range(6):
        for y in range(5):
            if (x, y) in env.level.blocked or (x, y) == (5, 0):
                continue
            obs, _ = env.reset(seed=0, options={"starts": [(x, y)], "goals": [(5, 0)]})
            assert obs["robot_0"][-5:].tolist() == best[y, x].tolist(), (x, y)
            seen.add(tuple(best[y, x].tolist()))
    assert len(seen) >= 3  # cells with one, and with two, optimal actions


def test_the_hint_follows_each_robots_own_goal_and_is_empty_on_it():
    env = race_v0.parallel_env(level=OPEN, n_robots=2, goals="own", observe="local", view_radius=1, hint=True, finished="freeze")
    obs, _ = env.reset(seed=0, options={"starts": [(2, 2), (3, 2)], "goals": [(0, 2), (5, 2)]})
    assert obs["robot_0"][-5:].tolist() == [0, 0, 0, 0, 1]  # west only
    assert obs["robot_1"][-5:].tolist() == [0, 0, 1, 0, 0]  # east only
    obs, *_ = env.step({"robot_0": 4, "robot_1": 2})
    obs, *_ = env.step({"robot_0": 4, "robot_1": 2})
    assert obs["robot_0"][-5:].tolist() == [0] * 5 and env.ranks[0] == 1


# ---------------------------------------------------------------------------- the other env forms
def test_the_aec_env_and_the_gymnasium_race_take_own_goals():
    aec = race_v0.env(level="race-4", n_robots=4, goals="own")
    aec.reset(seed=0)
    assert aec.unwrapped.goals_mode == "own"
    g = gym.make("babyrobot_marl/BabyRobotRace-v0", level=OPEN, opponents=["shortest"], goals="own")
    obs, _ = g.reset(seed=0, options={"starts": [(0, 0), (0, 4)], "goals": [(2, 0), (0, 1)]})
    assert tuple(obs[-2:]) == (2, 0)
    rewards = []
    for _ in range(3):  # the shortest opponent walks north to (0, 1); robot 0 east to (2, 0)
        obs, r, term, trunc, info = g.step(2)
        rewards.append(r)
        if term:
            break
    assert term and rewards == [-1.0, 0.0] and g.unwrapped.race.robot_cells[1] == (0, 2)


def test_the_vector_race_takes_own_goals_and_given_goals():
    v = RaceVectorEnv(2, level="race-4", n_robots=4, goals="own", observe="local", view_radius=1)
    single = race_v0.parallel_env(level="race-4", n_robots=4, goals="own", observe="local", view_radius=1)
    assert v.single_observation_space == single.observation_space("robot_0")
    goals = [(3, 3), (1, 0), (0, 1), (6, 5)]
    obs, _ = v.reset(seed=0, options={"goals": goals})
    s_obs, _ = single.reset(seed=0, options={"goals": goals})
    assert all(np.array_equal(obs[k], s_obs[f"robot_{k}"]) for k in range(4))
    assert v._batch.goals[1].tolist() == [single.table.cell_id(c) for c in goals]
    with pytest.raises(ValueError, match=r'^options\["goals"\]: two robots share a goal'):
        v.reset(options={"goals": [(3, 3)] * 4})
    random_starts = RaceVectorEnv(2, level="race-4", n_robots=4, goals="own", start="random")
    with pytest.raises(ValueError, match=r'^options\["goals"\]: a vector race takes given goals with known starts'):
        random_starts.reset(options={"goals": goals})


def test_goal_actions_are_the_hint_of_every_cell_and_the_optimal_actions_towards_an_exit_goal():
    from babyrobot_marl.planning import goal_actions

    best, hints = optimal_actions(OPEN), goal_actions(OPEN, (5, 0))
    assert hints.shape == best.shape and hints.dtype == np.uint8
    assert hints.tolist() == best.tolist()  # no puddles, no glass: shortest paths are optimal
    env = race_v0.parallel_env(level=OPEN, n_robots=1, goals="own", observe="local", view_radius=1, hint=True)
    other = goal_actions(OPEN, (0, 4))
    for x, y in [(0, 0), (3, 2), (5, 4), (2, 3)]:
        obs, _ = env.reset(seed=0, options={"starts": [(x, y)], "goals": [(0, 4)]})
        assert obs["robot_0"][-5:].tolist() == other[y, x].tolist()
    assert other[4, 0].tolist() == [0] * 5 and other[1, 2].tolist() == [0] * 5  # on the goal; a blocked cell


def test_the_trainers_reset_draws_valid_own_goals_for_every_env():
    from babyrobot_marl.core.goals import reach

    env = race_v0.parallel_env(level="mixed-8x8", n_robots=5, start="random", goals="own", finished="freeze")
    batch = env.batch(64)
    batch.reset_drawn(np.arange(64), np.random.default_rng(0))
    part, t = reach(env.table).component, env.table
    for cells, goals in zip(batch.cells.tolist(), batch.goals.tolist()):
        assert len(set(goals)) == 5 and all(g not in t.blocked.nonzero()[0] for g in goals)
        assert all(g != c and part[g] == part[c] and t.move_prob[g] == 1.0 for c, g in zip(cells, goals))
    assert len({tuple(g) for g in batch.goals.tolist()}) > 50  # drawn per env, not copied


def test_goal_distances_grow_their_store_by_doubling_and_keep_every_row():
    """Goals met one at a time (lifelong races) cost linear time: the rows' store is reallocated a
    logarithmic number of times, not once per new goal, and every row stays the search's."""
    from babyrobot_marl.core.goals import GoalDistances
    from babyrobot_marl.core.table import compile_level
    from babyrobot_marl.levels import get

    table = compile_level(get("maze-16x16"))
    dist, fresh = GoalDistances(table), GoalDistances(table)
    store, grown = dist._store, 0
    for cell in range(100):
        dist.rows_for(np.array([cell]))
        grown += dist._store is not store
        store = dist._store
    assert grown <= 5  # 8, 16, 32, 64, 128 rows
    all_at_once = fresh.rows_for(np.arange(100))
    assert np.array_equal(dist.rows[dist.row_of[np.arange(100)]], fresh.rows[all_at_once])
