"""BabyRobot-v0, the single-robot Gymnasium env: API conformance, registration, arguments, rendering, seeding, copies."""

from __future__ import annotations

import copy
import os
import pickle
import subprocess
import sys
import warnings
from collections import Counter
from pathlib import Path

import cloudpickle
import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env

import babyrobot_marl
from babyrobot_marl import Action, BabyRobotEnv, Level, Rules, levels
from babyrobot_marl.core.outcomes import OUTCOME_NAMES
from babyrobot_marl.policies import RandomPolicy
from tests.strategies import exit_distances

ENV_ID = "babyrobot_marl/BabyRobot-v0"
ROOT = Path(babyrobot_marl.__file__).resolve().parents[1]
OPEN_TEXT = """
+-+-+-+
|S    |
+ + + +
|     |
+ + + +
|    E|
+-+-+-+
"""


def run_episode(env, seed, actions=None, policy_seed=0, start_options=None):
    """The episode (to its end, or to the end of ``actions``) as a list of plain tuples."""
    obs, info = env.reset(seed=seed, options=start_options)
    record = [(tuple(obs.tolist()), tuple(info["cell"].tolist()))]
    policy = RandomPolicy(policy_seed)
    plan = iter(actions) if actions is not None else iter(policy, None)
    for a in plan:
        obs, reward, terminated, truncated, info = env.step(a)
        record.append((tuple(obs.tolist()), reward, terminated, truncated, tuple(info["cell"].tolist()), info["outcome"]))
        if terminated or truncated:
            break
    return record


# --------------------------------------------------------------------------------------- API conformance
@pytest.mark.parametrize("render_mode", [None, "ansi", "human"])
@pytest.mark.parametrize("name", levels.names())
def test_gymnasium_env_checker_passes_without_warnings(name, render_mode, capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env = gymnasium.make(ENV_ID, level=name, render_mode=render_mode)
        gym_check_env(env.unwrapped)  # made with gymnasium.make: has a spec, so every render mode is checked too
    capsys.readouterr()


@pytest.mark.parametrize("render_mode", [None, "ansi", "human"])
@pytest.mark.parametrize("name", levels.names())
def test_sb3_env_checker_passes_without_warnings(name, render_mode, capsys):
    checker = pytest.importorskip("stable_baselines3.common.env_checker", reason="needs the train extra (Stable-Baselines3)")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        checker.check_env(BabyRobotEnv(level=name, render_mode=render_mode), warn=True)
    capsys.readouterr()


@pytest.mark.parametrize("name", levels.names())
def test_step_returns_python_types_and_a_fresh_observation_inside_the_space(name):
    env = BabyRobotEnv(name)
    obs, info = env.reset(seed=1)
    assert obs.dtype == np.int64 and env.observation_space.dtype == np.int64
    assert env.observation_space.contains(obs)
    assert tuple(info["cell"].tolist()) == tuple(obs.tolist()) == env.level.starts[0]
    policy = RandomPolicy(1)
    for _ in range(50):
        previous = obs
        obs, reward, terminated, truncated, info = env.step(policy())
        assert type(reward) is float and type(terminated) is bool and type(truncated) is bool
        assert obs.dtype == np.int64 and obs.shape == (2,) and env.observation_space.contains(obs)
        assert obs is not previous
        assert set(info) >= {"cell", "outcome", "intended"}
        assert tuple(info["cell"].tolist()) == tuple(obs.tolist()) == env.robot_cell
        assert OUTCOME_NAMES[info["outcome"]] in ("moved", "stayed", "bumped", "skidded", "glass")
        assert info["intended"] == (OUTCOME_NAMES[info["outcome"]] in ("moved", "stayed"))
        previous[:] = -7  # mutating an old observation changes nothing the env keeps
        assert env.robot_cell == tuple(obs.tolist()) and obs.min() >= 0
        if terminated or truncated:
            obs, _ = env.reset()


def test_mutating_a_returned_observation_does_not_change_the_next_one():
    env = BabyRobotEnv(OPEN_TEXT)
    obs, _ = env.reset(seed=0)
    obs[:] = [2, 2]
    obs2, *_ = env.step(Action.STAY)
    assert obs2.tolist() == [0, 0]
    obs2[0] = 1
    obs3, *_ = env.step(Action.STAY)
    assert obs3.tolist() == [0, 0]
    obs4, _ = env.reset(seed=0)
    assert obs4.tolist() == [0, 0]


def test_spaces_are_five_actions_and_the_grid_size():
    env = BabyRobotEnv("walls")
    assert env.action_space == gymnasium.spaces.Discrete(5)
    assert env.observation_space == gymnasium.spaces.MultiDiscrete([5, 5])
    wide = BabyRobotEnv("race-corridor")
    assert list(wide.observation_space.nvec) == [7, 3]  # [x range, y range]


# --------------------------------------------------------------------------------------- registration
def test_make_by_id_after_import():
    env = gymnasium.make(ENV_ID, level="maze-8x8")
    assert isinstance(env.unwrapped, BabyRobotEnv)
    assert env.unwrapped.level == levels.get("maze-8x8")
    obs, _ = env.reset(seed=0)
    assert obs.tolist() == [0, 0]
    assert gymnasium.make(ENV_ID).unwrapped.level == levels.get("default")


def test_make_with_module_prefix_in_a_fresh_interpreter():
    code = (
        "import sys, gymnasium\n"
        "assert 'babyrobot_marl' not in sys.modules\n"
        "env = gymnasium.make('babyrobot_marl:babyrobot_marl/BabyRobot-v0', level='walls')\n"
        "obs, info = env.reset(seed=0)\n"
        "obs, r, term, trunc, info = env.step(2)\n"
        "print(type(env.unwrapped).__name__, obs.tolist(), r)\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=Path(__file__).parent, env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["BabyRobotEnv", "[1,", "0]", "-1.0"]


def test_rule_overrides_pass_through_make():
    env = gymnasium.make(ENV_ID, level="glass", glass_pass_prob=1.0, max_steps=7)
    assert env.unwrapped.rules.glass_pass_prob == 1.0
    assert env.unwrapped.max_steps == 7


# --------------------------------------------------------------------------------------- arguments
def test_level_may_be_a_name_a_level_or_a_text():
    by_name = BabyRobotEnv("puddles")
    by_level = BabyRobotEnv(levels.get("puddles"))
    by_text = BabyRobotEnv(levels.get("puddles").to_ascii())
    assert by_name.level == by_level.level == by_text.level
    assert run_episode(by_name, 3) == run_episode(by_level, 3) == run_episode(by_text, 3)


def test_keyword_rule_overrides_take_effect():
    glass_text = "+-+-+\n|S*E|\n+-+-+"
    always = BabyRobotEnv(glass_text, glass_pass_prob=1.0)
    never = BabyRobotEnv(glass_text, rules=Rules(glass_pass_prob=0.0))
    as_dict = BabyRobotEnv(glass_text, rules={"glass_pass_prob": 0.0}, glass_pass_prob=1.0)  # the keyword wins
    for seed in range(30):
        always.reset(seed=seed)
        never.reset(seed=seed)
        as_dict.reset(seed=seed)
        assert always.step(Action.EAST)[2] is True
        assert never.step(Action.EAST)[2] is False
        assert as_dict.step(Action.EAST)[2] is True


@pytest.mark.parametrize("level", ["no-such-level", "maze-0x4"])
def test_unknown_level_name_is_a_value_error(level):
    with pytest.raises(ValueError, match="level|width|height"):
        BabyRobotEnv(level)


def test_unknown_level_name_lists_the_known_names():
    with pytest.raises(ValueError) as info:
        BabyRobotEnv("defualt")
    assert all(name in str(info.value) for name in levels.names())


@pytest.mark.parametrize("level", [None, 5, ["default"]])
def test_level_of_the_wrong_type_is_a_type_error(level):
    with pytest.raises(TypeError, match="level"):
        BabyRobotEnv(level)


def test_malformed_level_text_is_a_value_error_with_a_position():
    with pytest.raises(ValueError, match=r"line 2, column 4"):
        BabyRobotEnv("+-+-+-+\n|S x E|\n+-+-+-+")


@pytest.mark.parametrize("max_steps", [0, -3, 2.5, "10", True, [5]])
def test_bad_max_steps_is_a_value_error_naming_it(max_steps):
    with pytest.raises(ValueError, match="max_steps"):
        BabyRobotEnv(max_steps=max_steps)


def test_max_steps_accepts_numpy_integers():
    assert BabyRobotEnv(max_steps=np.int64(12)).max_steps == 12


@pytest.mark.parametrize("start", ["middle", "Random", 0, (0, 0)])
def test_bad_start_is_a_value_error_naming_it(start):
    with pytest.raises(ValueError, match="start"):
        BabyRobotEnv(start=start)


@pytest.mark.parametrize("render_mode", ["rgb", "video", "Human", 1])
def test_bad_render_mode_is_a_value_error_naming_it(render_mode):
    with pytest.raises(ValueError, match="render_mode"):
        BabyRobotEnv(render_mode=render_mode)


@pytest.mark.parametrize(
    "start",
    [(3, 0), (0, -1), (2, 2), (1.5, 0), (True, 0), "ab", (1,), (0, 0, 0), 7, [[0], [0]]],
    ids=["off-grid-x", "off-grid-y", "exit", "float", "bool", "string", "one-number", "three-numbers", "int", "nested"],
)
def test_bad_options_start_is_a_value_error_and_changes_nothing(start):
    env = BabyRobotEnv(OPEN_TEXT)
    env.reset(seed=0)
    env.step(Action.EAST)
    with pytest.raises(ValueError, match=r"options\['start'\]"):
        env.reset(options={"start": start})
    assert env.robot_cell == (1, 0) and env.elapsed_steps == 1
    env.step(Action.EAST)
    assert env.robot_cell == (2, 0)


def test_an_unknown_reset_option_warns_once_naming_start_and_is_ignored():
    """Gymnasium's and PettingZoo's own tests reset with arbitrary options (DESIGN.md)."""
    env, plain = BabyRobotEnv("glass", start="random"), BabyRobotEnv("glass", start="random")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        obs, _ = env.reset(seed=5, options={"options": 1})
    assert [str(w.message) for w in caught] == ["options: unknown option 'options' ignored; known options are 'start'"]
    assert caught[0].category is UserWarning and caught[0].filename == __file__  # points at the reset() call
    assert obs.tolist() == plain.reset(seed=5)[0].tolist()
    with pytest.warns(UserWarning, match="unknown option 'x' ignored"):
        episode = run_episode(env, 7, start_options={"start": (1, 1), "x": 0})
    assert episode == run_episode(plain, 7, start_options={"start": (1, 1)})


def test_a_bad_start_beside_an_unknown_option_is_still_a_value_error():
    env = BabyRobotEnv(OPEN_TEXT)
    with pytest.warns(UserWarning, match="'options' ignored"), pytest.raises(ValueError, match=r"options\['start'\]"):
        env.reset(options={"start": (9, 9), "options": 1})


def test_options_start_on_a_blocked_cell_is_a_value_error():
    env = BabyRobotEnv("blocked")
    (x, y) = sorted(levels.get("blocked").blocked)[0]
    with pytest.raises(ValueError, match="blocked"):
        env.reset(options={"start": (x, y)})


# --------------------------------------------------------------------------------------- bad actions and call order
BAD_ACTIONS = [5, -1, 1.0, 2.5, "1", "NORTH", True, False, np.bool_(True), [1], (1,), np.array([1]), None, np.float64(1.0)]


@pytest.mark.parametrize("action", BAD_ACTIONS, ids=[repr(a) for a in BAD_ACTIONS])
def test_bad_action_is_a_value_error_naming_action_and_the_env_stays_usable(action):
    env = BabyRobotEnv(OPEN_TEXT)
    env.reset(seed=0)
    env.step(Action.EAST)
    with pytest.raises(ValueError, match="action"):
        env.step(action)
    assert env.robot_cell == (1, 0) and env.elapsed_steps == 1
    obs, reward, *_ = env.step(Action.SOUTH)
    assert obs.tolist() == [1, 1] and reward == -1.0


@pytest.mark.parametrize("action", [np.int64(2), np.int32(2), np.array(2), Action.EAST, 2])
def test_integer_like_actions_are_accepted(action):
    env = BabyRobotEnv(OPEN_TEXT)
    env.reset(seed=0)
    assert env.step(action)[0].tolist() == [1, 0]


def test_step_before_reset_is_a_runtime_error():
    env = BabyRobotEnv()
    assert env.robot_cell is None
    with pytest.raises(RuntimeError, match="reset"):
        env.step(Action.STAY)
    env.reset(seed=0)
    env.step(Action.STAY)


def test_step_after_the_episode_ended_is_a_runtime_error_until_reset():
    env = BabyRobotEnv(OPEN_TEXT, max_steps=2)
    env.reset(seed=0)
    env.step(Action.STAY)
    assert env.step(Action.STAY)[3] is True
    with pytest.raises(RuntimeError, match="reset"):
        env.step(Action.STAY)
    env.reset()  # a new episode may step again
    assert env.step(Action.EAST)[3] is False
    env2 = BabyRobotEnv(OPEN_TEXT)
    env2.reset(seed=0)
    for a in (Action.EAST, Action.EAST, Action.SOUTH):
        env2.step(a)
    assert env2.step(Action.SOUTH)[2] is True
    with pytest.raises(RuntimeError, match="reset"):
        env2.step(Action.STAY)


# --------------------------------------------------------------------------------------- starts
def test_reset_options_start_places_the_robot():
    env = BabyRobotEnv("puddles")
    for cell in [(3, 0), (0, 4), (2, 2)]:  # (2, 2) is a small puddle: allowed
        obs, info = env.reset(seed=0, options={"start": cell})
        assert tuple(obs.tolist()) == cell == tuple(info["cell"].tolist()) == env.robot_cell
    obs, _ = env.reset(options={"start": np.array([4, 1])})
    assert obs.tolist() == [4, 1]
    obs, _ = env.reset()  # the option lasts one episode
    assert tuple(obs.tolist()) == levels.get("puddles").starts[0]


def free_cells_by_the_rules(level):
    """Floor cells (no puddle, no exit, not blocked) from which an exit is reachable: computed independently."""
    return set(exit_distances(level)) - level.exits - level.small_puddles - level.large_puddles


@pytest.mark.parametrize("name", ["blocked", "puddles", "mixed-8x8"])
def test_random_start_covers_the_free_cells_uniformly(name):
    env = BabyRobotEnv(name, start="random")
    free = free_cells_by_the_rules(levels.get(name))
    n = 300 * len(free)
    env.reset(seed=123)
    starts = Counter(tuple(env.reset()[0].tolist()) for _ in range(n))
    assert set(starts) == free
    p = 1 / len(free)
    assert all(abs(k - n * p) <= 5 * np.sqrt(n * p * (1 - p)) for k in starts.values())


def test_a_level_without_starts_starts_at_random():
    level = Level(width=3, height=2, exits=[(2, 1)], large_puddles=[(1, 1)])
    env = BabyRobotEnv(level)
    env.reset(seed=0)
    starts = {tuple(env.reset()[0].tolist()) for _ in range(200)}
    assert starts == {(0, 0), (1, 0), (2, 0), (0, 1)}


# --------------------------------------------------------------------------------------- seeding
@pytest.mark.parametrize("name", ["puddles", "glass", "mixed-8x8"])
def test_same_seed_same_episode_whatever_came_before(name):
    a = BabyRobotEnv(name, start="random")
    b = BabyRobotEnv(name, start="random")
    run_episode(b, seed=99)  # b has a different history
    for seed in (0, 1, 2**31):
        assert run_episode(a, seed) == run_episode(b, seed)
    # unseeded resets continue the seeded stream identically
    a.reset(seed=5)
    b.reset(seed=5)
    assert [run_episode(a, None, policy_seed=i) for i in range(3)] == [run_episode(b, None, policy_seed=i) for i in range(3)]


def test_different_seeds_give_different_episodes():
    env = BabyRobotEnv("puddles", max_steps=30)
    actions = [Action.EAST, Action.SOUTH] * 15  # a fixed plan through the puddles: only the env's draws differ
    episodes = [tuple(run_episode(env, seed, actions=actions)) for seed in range(12)]
    assert len(set(episodes)) >= 6
    random_start = BabyRobotEnv("mixed-8x8", start="random")
    assert len({run_episode(random_start, seed, actions=[0])[0] for seed in range(12)}) >= 6


# --------------------------------------------------------------------------------------- copies
@pytest.mark.parametrize("how", ["pickle", "cloudpickle", "deepcopy"])
def test_a_copy_taken_mid_episode_continues_identically(how):
    env = BabyRobotEnv("mixed-8x8", start="random", max_steps=400)
    env.reset(seed=21)
    policy = RandomPolicy(4)
    for _ in range(5):
        env.step(policy())
    clone = {
        "pickle": lambda e: pickle.loads(pickle.dumps(e)),
        "cloudpickle": lambda e: cloudpickle.loads(cloudpickle.dumps(e)),
        "deepcopy": copy.deepcopy,
    }[how](env)
    assert clone is not env and clone.robot_cell == env.robot_cell and clone.elapsed_steps == env.elapsed_steps
    actions = [RandomPolicy(8)() for _ in range(1000)]
    for episode in range(3):
        ours, theirs = [], []
        for a in actions:
            r1, r2 = env.step(a), clone.step(a)
            ours.append((r1[0].tolist(), *r1[1:4], r1[4]["cell"].tolist(), r1[4]["outcome"]))
            theirs.append((r2[0].tolist(), *r2[1:4], r2[4]["cell"].tolist(), r2[4]["outcome"]))
            if r1[2] or r1[3]:
                break
        assert ours == theirs, episode
        assert env.reset()[0].tolist() == clone.reset()[0].tolist()  # the generator state came along too


# --------------------------------------------------------------------------------------- rendering
def robot_positions(frame: str, level: Level):
    grid = frame.split("\n")[: 2 * level.height + 1]
    return [(x // 2, y // 2) for y, line in enumerate(grid) for x, ch in enumerate(line) if ch == "R"]


def test_ansi_render_draws_the_robot_where_it_is():
    env = BabyRobotEnv(OPEN_TEXT, render_mode="ansi")
    env.reset(seed=0)
    frame = env.render()
    assert isinstance(frame, str)
    assert robot_positions(frame, env.level) == [(0, 0)]
    for action, cell in [(Action.EAST, (1, 0)), (Action.SOUTH, (1, 1)), (Action.EAST, (2, 1))]:
        env.step(action)
        frame = env.render()
        assert robot_positions(frame, env.level) == [cell]
        # everything but the robot is the level text
        lines = frame.split("\n")[:7]
        expected = env.level.to_ascii().split("\n")
        expected[2 * cell[1] + 1] = (
            expected[2 * cell[1] + 1][: 2 * cell[0] + 1] + "R" + expected[2 * cell[1] + 1][2 * cell[0] + 2 :]
        )
        assert lines == expected


def test_human_render_prints_the_frame_without_a_display(capsys, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    env = BabyRobotEnv(OPEN_TEXT, render_mode="human")
    env.reset(seed=0)
    out = capsys.readouterr().out
    assert robot_positions(out, env.level) == [(0, 0)]
    env.step(Action.SOUTH)
    out = capsys.readouterr().out
    assert robot_positions(out, env.level) == [(0, 1)]
    assert env.render() is None
    assert robot_positions(capsys.readouterr().out, env.level) == [(0, 1)]


def test_render_without_a_render_mode_warns_and_returns_none():
    env = BabyRobotEnv()
    env.reset(seed=0)
    with pytest.warns(UserWarning, match="render_mode"):
        assert env.render() is None


def test_render_modes_are_declared():
    assert {"ansi", "human"} <= set(BabyRobotEnv.metadata["render_modes"])
