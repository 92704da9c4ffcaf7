"""Bad input, in one table: every public entry point given a bad value raises a clear error
(``ValueError`` or ``TypeError``) whose message names the bad argument; a bad call on an existing
env leaves it usable and unchanged (compared with a twin env driven identically); a bad command
line exits non-zero with one line on stderr and no traceback.

Entry points: ``gymnasium.make`` of BabyRobot-v0 and BabyRobotRace-v0, the env classes,
``race_v0.parallel_env`` / ``env``, ``Level`` / ``Level.from_ascii`` / ``with_rewards``,
``Rules``, ``levels.get`` / ``levels.maze``, ``policies.make``, ``step`` / ``reset`` /
``observation_space`` / ``set_cells`` on the envs, and ``babyrobot_marl.cli.main``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import gymnasium
import numpy as np
import pytest

import babyrobot_marl  # noqa: F401  (registers the Gymnasium ids)
from babyrobot_marl import BabyRobotEnv, Level, Rules, cli, compile_level, levels, race_v0
from babyrobot_marl.envs.race_gym import BabyRobotRaceEnv
from babyrobot_marl.policies import make as make_policy

SINGLE_ID = "babyrobot_marl/BabyRobot-v0"
RACE_ID = "babyrobot_marl/BabyRobotRace-v0"
EAST = 2

# robot_0 reaches the exit with one certain move EAST; the others start on and beside puddles
FINISH_LEVEL = """
+-+-+-+-+-+
|0 E P 1 2|
+ + + + + +
|p p  *  p|
+-+-+-+-+-+
"""
BAD_TEXT = "+-+-+-+\n|S x E|\n+-+-+-+"


# --------------------------------------------------------------------------------------- envs and twins
def plain(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return ("array", x.tolist())
    if isinstance(x, dict):
        return {k: plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [plain(v) for v in x]
    if isinstance(x, np.generic):
        return x.item()
    return x


def race_fingerprint(race) -> Any:
    return plain(
        (
            race.agents,
            race.robot_cells,
            race.ranks,
            race.returns,
            race.collisions_count,
            race.elapsed_steps,
            race.state(),
            race.np_random.bit_generator.state,
        )
    )


def fingerprint(env, kind: str) -> Any:
    """Everything public about the env's state, its generator included."""
    inner = env.unwrapped
    if kind == "aec":
        aec_view = (env.agent_selection, env.agents, env.rewards, env.terminations, env.truncations, env.infos)
        return plain(aec_view) + [race_fingerprint(inner)]
    if kind == "parallel":
        return race_fingerprint(env)
    if isinstance(inner, BabyRobotRaceEnv):
        return [race_fingerprint(inner.race), plain(inner.np_random.bit_generator.state)]
    return plain((inner.robot_cell, inner.elapsed_steps, inner.np_random.bit_generator.state))


def drive(env, kind: str, n: int, actions: np.random.Generator) -> list:
    """``n`` steps of random actions, resetting (unseeded) whenever an episode ends."""
    out = []
    for _ in range(n):
        if kind == "gym":
            result = env.step(int(actions.integers(5)))
            done = result[2] or result[3]
        elif kind == "parallel":
            result = env.step({a: int(actions.integers(5)) for a in env.agents})
            done = not env.agents
        else:
            obs, reward, term, trunc, info = env.last()
            action = None if term or trunc else int(actions.integers(5))
            env.step(action)
            result, done = (env.agent_selection, obs, reward, term, trunc, info, action), not env.agents
        out.append(plain(result))
        if done:
            out.append(plain(env.reset()))
    return out


def one_aec_cycle(env) -> None:
    """Every agent acts once: robot_0 is to act next, at the start of a cycle."""
    drive(env, "aec", 4, np.random.default_rng(0))
    assert env.agent_selection == "robot_0"


def finish_robot_0(env) -> None:
    env.step({"robot_0": EAST, "robot_1": 0, "robot_2": 0})
    assert env.ranks[0] == 1


@dataclass(frozen=True)
class EnvSpec:
    factory: Callable[[], Any]
    kind: str  # "gym", "parallel" or "aec"
    prepare: Callable[[Any], None] | None = None  # after reset(seed); default: 3 random steps


ENVS: dict[str, EnvSpec] = {
    "single": EnvSpec(lambda: BabyRobotEnv("mixed-8x8", start="random", max_steps=12), "gym"),
    "single-make": EnvSpec(lambda: gymnasium.make(SINGLE_ID, level="puddles", start="random", max_steps=12), "gym"),
    "race": EnvSpec(lambda: race_v0.parallel_env(level="race-4", n_robots=4, max_cycles=300), "parallel"),
    "race-removed": EnvSpec(
        lambda: race_v0.parallel_env(level=FINISH_LEVEL, n_robots=3, finished="remove", max_cycles=300),
        "parallel",
        finish_robot_0,
    ),
    "race-parked": EnvSpec(
        lambda: race_v0.parallel_env(level=FINISH_LEVEL, n_robots=3, finished="freeze", max_cycles=300),
        "parallel",
        finish_robot_0,
    ),
    "aec": EnvSpec(lambda: race_v0.env(level="race-4", n_robots=4, max_cycles=300), "aec", one_aec_cycle),
    "race-gym": EnvSpec(lambda: BabyRobotRaceEnv(level="race-4", opponents=["shortest"] * 3, max_cycles=300), "gym"),
    "race-gym-random": EnvSpec(lambda: BabyRobotRaceEnv(level="race-4", opponents=["random", "shortest", "random"]), "gym"),
    "race-gym-make": EnvSpec(lambda: gymnasium.make(RACE_ID, level="race-2", opponents=["shortest"], start="random"), "gym"),
}


def ready(name: str):
    spec = ENVS[name]
    env = spec.factory()
    env.reset(seed=3)
    if spec.prepare is not None:
        spec.prepare(env)
    else:
        drive(env, spec.kind, 3, np.random.default_rng(0))
    return env


# --------------------------------------------------------------------------------------- the table
@dataclass(frozen=True)
class Bad:
    """One bad input: ``call()`` (a constructor or function), ``call(env)`` on ``env``, or CLI ``argv``."""

    names: str  # the message must contain this (the bad argument, or its value)
    call: Callable[..., Any] | None = None
    env: str | None = None
    argv: tuple[str, ...] | None = None
    errors: tuple[type[BaseException], ...] = (ValueError, TypeError)


def make_single(**kw):
    return lambda: gymnasium.make(SINGLE_ID, **kw)


def make_race_gym(**kw):
    return lambda: gymnasium.make(RACE_ID, **kw)


def race(**kw):
    return lambda: race_v0.parallel_env(**kw)


RACE_ACTIONS = {"robot_0": 0, "robot_1": 0, "robot_2": 0, "robot_3": 0}


def race_step(**changes):
    return lambda env: env.step({**RACE_ACTIONS, **changes})


CASES = [
    # ---- gymnasium.make("babyrobot_marl/BabyRobot-v0", ...)
    ("make-single level None", Bad("level", make_single(level=None))),
    ("make-single level int", Bad("level", make_single(level=5))),
    ("make-single level unknown name", Bad("nope", make_single(level="nope"))),
    ("make-single level bad text", Bad("line 2, column 4", make_single(level=BAD_TEXT))),
    ("make-single level text 1x1 only an exit", Bad("level", make_single(level="+-+\n|E|\n+-+"))),
    ("make-single level maze of width 0", Bad("level", make_single(level="maze-0x3"))),
    ("make-single rules str", Bad("rules", make_single(rules="fast"))),
    ("make-single rules unknown name", Bad("foo", make_single(rules={"foo": 1}))),
    ("make-single rules non-str key", Bad("rules", make_single(rules={1: 2.0}))),
    ("make-single rules nan reward", Bad("floor_reward", make_single(rules={"floor_reward": float("nan")}))),
    ("make-single unknown kwarg", Bad("foo", make_single(foo=1))),
    ("make-single opponents", Bad("opponents", make_single(opponents=["shortest"]))),
    ("make-single max_steps 0", Bad("max_steps", make_single(max_steps=0))),
    ("make-single max_steps float", Bad("max_steps", make_single(max_steps=1.5))),
    ("make-single max_steps str", Bad("max_steps", make_single(max_steps="10"))),
    ("make-single max_steps bool", Bad("max_steps", make_single(max_steps=True))),
    ("make-single start fill", Bad("start", make_single(start="fill"))),
    ("make-single start tuple", Bad("start", make_single(start=(0, 0)))),
    ("make-single render_mode", Bad("render_mode", make_single(render_mode="video"))),
    ("make-single cell_size", Bad("cell_size", make_single(cell_size=0))),
    ("make-single theme", Bad("theme", make_single(theme="neon"))),
    ("make-single glass_pass_prob", Bad("glass_pass_prob", make_single(glass_pass_prob=1.5))),
    ("make-single collisions", Bad("collisions", make_single(collisions="crash"))),
    # ---- gymnasium.make("babyrobot_marl/BabyRobotRace-v0", ...)
    ("make-race level None", Bad("level", make_race_gym(level=None))),
    ("make-race level unknown", Bad("nope", make_race_gym(level="nope"))),
    ("make-race too few starts", Bad("level", make_race_gym(level="default"))),
    ("make-race rules", Bad("rules", make_race_gym(rules=3))),
    ("make-race unknown kwarg", Bad("foo", make_race_gym(foo=1))),
    ("make-race max_steps", Bad("max_steps", make_race_gym(max_steps=10))),
    ("make-race max_cycles 0", Bad("max_cycles", make_race_gym(max_cycles=0))),
    ("make-race start", Bad("start", make_race_gym(start="anywhere"))),
    ("make-race render_mode", Bad("render_mode", make_race_gym(render_mode="video"))),
    ("make-race collisions", Bad("collisions", make_race_gym(collisions="crash"))),
    ("make-race opponents str", Bad("opponents", make_race_gym(opponents="shortest"))),
    ("make-race opponents unknown", Bad("opponents", make_race_gym(opponents=["greedy"]))),
    ("make-race opponents None", Bad("opponents", make_race_gym(opponents=None))),
    ("make-race opponents int", Bad("opponents", make_race_gym(opponents=3))),
    ("make-race n_robots", Bad("n_robots", make_race_gym(n_robots=3))),
    ("make-race finished", Bad("finished", make_race_gym(finished="remove"))),
    # ---- the race: race_v0.parallel_env / race_v0.env
    ("race n_robots 0", Bad("n_robots", race(n_robots=0))),
    ("race n_robots negative", Bad("n_robots", race(n_robots=-2))),
    ("race n_robots float", Bad("n_robots", race(n_robots=2.5))),
    ("race n_robots str", Bad("n_robots", race(n_robots="2"))),
    ("race n_robots bool", Bad("n_robots", race(n_robots=True))),
    ("race n_robots None", Bad("n_robots", race(n_robots=None))),
    ("race n_robots over level starts", Bad("n_robots", race(level="race-2", n_robots=3))),
    ("race n_robots over free cells", Bad("n_robots", race(level="default", n_robots=9, start="random"))),
    ("race n_robots over free cells, fill", Bad("n_robots", race(level="default", n_robots=9, start="fill"))),
    ("race collisions", Bad("collisions", race(collisions="crash"))),
    ("race collisions int", Bad("collisions", race(collisions=1))),
    ("race finished", Bad("finished", race(finished="vanish"))),
    ("race finished None", Bad("finished", race(finished=None))),
    ("race start", Bad("start", race(start="anywhere"))),
    ("race start None", Bad("start", race(start=None))),
    ("race max_cycles 0", Bad("max_cycles", race(max_cycles=0))),
    ("race max_cycles float", Bad("max_cycles", race(max_cycles=2.5))),
    ("race max_cycles str", Bad("max_cycles", race(max_cycles="10"))),
    ("race render_mode", Bad("render_mode", race(render_mode="video"))),
    ("race level", Bad("level", race(level=3))),
    ("race rules", Bad("rules", race(rules=[1]))),
    ("race unknown kwarg", Bad("foo", race(foo=1))),
    ("race cell_size", Bad("cell_size", race(cell_size=7))),
    ("race theme", Bad("theme", race(theme=1))),
    ("aec n_robots", Bad("n_robots", lambda: race_v0.env(n_robots=0))),
    ("aec render_mode", Bad("render_mode", lambda: race_v0.env(render_mode="video"))),
    ("env class single render_mode", Bad("render_mode", lambda: BabyRobotEnv(render_mode=1))),
    ("env class race-gym render_mode", Bad("render_mode", lambda: BabyRobotRaceEnv(render_mode="video"))),
    # ---- level texts and Level fields
    ("text empty", Bad("empty", lambda: Level.from_ascii(""))),
    ("text None", Bad("text", lambda: Level.from_ascii(None))),
    ("text bytes", Bad("text", lambda: Level.from_ascii(b"+-+\n|E|\n+-+"))),
    ("text bad character", Bad("line 2, column 4", lambda: Level.from_ascii(BAD_TEXT))),
    ("text open border", Bad("line 2, column 1", lambda: Level.from_ascii("+-+-+\n S E|\n+-+-+"))),
    ("text missing exit", Bad("exit", lambda: Level.from_ascii("+-+-+\n|S  |\n+-+-+"))),
    ("level width 0", Bad("width", lambda: Level(width=0, height=1, exits=[(0, 0)]))),
    ("level height str", Bad("height", lambda: Level(width=1, height="1", exits=[(0, 0)]))),
    ("level exits empty in a race", Bad("has no exit", lambda: race_v0.parallel_env(level=Level(width=2, height=1), n_robots=1))),
    ("grid map ragged", Bad("line 2, column 3", lambda: race_v0.parallel_env(level="..\n....", n_robots=1))),
    ("level start outside", Bad("starts", lambda: Level(width=2, height=1, exits=[(1, 0)], starts=[(5, 0)]))),
    ("level glass not an edge", Bad("glass", lambda: Level(width=2, height=1, exits=[(1, 0)], glass=[(0, 0)]))),
    ("level reward nan", Bad("rewards", lambda: Level(width=2, height=1, exits=[(1, 0)], rewards={(0, 0): float("nan")}))),
    ("level walls None", Bad("walls", lambda: Level(width=2, height=1, exits=[(1, 0)], walls=None))),
    ("level exits int", Bad("exits", lambda: Level(width=2, height=1, exits=5))),
    ("with_rewards bad value", Bad("rewards", lambda: levels.get("default").with_rewards({(0, 0): "x"}))),
    ("with_area_reward outside", Bad("rewards", lambda: levels.get("default").with_area_reward((0, 0), (5, 5), 1.0))),
    ("with_rewards pairs not pairs", Bad("rewards", lambda: levels.get("default").with_rewards([1, 2]))),
    # ---- levels.get / levels.maze / policies.make
    ("levels.get unknown", Bad("nope", lambda: levels.get("nope"))),
    ("levels.get None", Bad("level", lambda: levels.get(None))),
    ("levels.get list", Bad("level", lambda: levels.get(["default"]))),
    ("maze width 0", Bad("width", lambda: levels.maze(0, 3))),
    ("maze height 300", Bad("height", lambda: levels.maze(3, 300))),
    ("maze width float", Bad("width", lambda: levels.maze(2.5, 3))),
    ("maze 1x1", Bad("width, height", lambda: levels.maze(1, 1))),
    ("maze seed negative", Bad("seed", lambda: levels.maze(3, 3, seed=-1))),
    ("policies.make unknown", Bad("greedy", lambda: make_policy("greedy", compile_level(levels.get("default"))))),
    pytest.param(
        Bad("seed", lambda: make_policy("random", compile_level(levels.get("default")), seed=-1)),
        id="policies.make seed negative",
    ),
    pytest.param(
        Bad("table", lambda: make_policy("shortest", levels.get("default"))),
        id="policies.make table is a Level",
    ),
    # ---- Rules
    ("rules reward str", Bad("floor_reward", lambda: Rules(floor_reward="x"))),
    ("rules reward inf", Bad("exit_reward", lambda: Rules(exit_reward=float("inf")))),
    ("rules reward bool", Bad("win_bonus", lambda: Rules(win_bonus=True))),
    ("rules probability negative", Bad("glass_pass_prob", lambda: Rules(glass_pass_prob=-0.1))),
    ("rules probability above 1", Bad("small_puddle_move_prob", lambda: Rules(small_puddle_move_prob=1.5))),
    ("rules probability nan", Bad("large_puddle_move_prob", lambda: Rules(large_puddle_move_prob=float("nan")))),
    ("rules collisions", Bad("collisions", lambda: Rules(collisions="crash"))),
    ("rules collisions None", Bad("collisions", lambda: Rules(collisions=None))),
    ("rules replace unknown", Bad("foo", lambda: Rules().replace(foo=1))),
    ("rules replace bad value", Bad("floor_reward", lambda: Rules().replace(floor_reward=None))),
    # ---- single env: step and reset
    *[
        (f"{name} step {label}", Bad("action", lambda env, a=a: env.step(a), env=name))
        for name in ("single", "single-make")
        for label, a in [
            ("5", 5),
            ("-1", -1),
            ("1.5", 1.5),
            ("np.float64(1.0)", np.float64(1.0)),
            ("str", "1"),
            ("None", None),
            ("True", True),
            ("np.bool_", np.bool_(True)),
            ("array of 2", np.array([1, 2])),
            ("np.uint8(255)", np.uint8(255)),
        ]
    ],
    ("single reset start outside", Bad("start", lambda env: env.reset(options={"start": (9, 9)}), env="single")),
    ("single reset start float", Bad("start", lambda env: env.reset(options={"start": (0.5, 0)}), env="single")),
    ("single reset start str", Bad("start", lambda env: env.reset(options={"start": "a"}), env="single")),
    ("single reset start exit", Bad("start", lambda env: env.reset(options={"start": (7, 7)}), env="single")),
    ("single reset start blocked", Bad("start", lambda env: env.reset(options={"start": (6, 2)}), env="single")),
    ("single reset start with seed", Bad("start", lambda env: env.reset(seed=1, options={"start": (1,)}), env="single")),
    ("single-make reset start", Bad("start", lambda env: env.reset(options={"start": (-1, 0)}), env="single-make")),
    ("single reset options str", Bad("options", lambda env: env.reset(options="start"), env="single")),
    ("single reset options list", Bad("options", lambda env: env.reset(options=[(0, 0)]), env="single")),
    # ---- race (parallel): step, spaces, set_cells
    ("race step not a dict", Bad("actions", lambda env: env.step([0, 0, 0, 0]), env="race")),
    ("race step empty dict", Bad("robot_0", lambda env: env.step({}), env="race")),
    ("race step missing agent", Bad("robot_3", lambda env: env.step({"robot_0": 0, "robot_1": 0, "robot_2": 0}), env="race")),
    ("race step unknown agent", Bad("robot_9", race_step(robot_9=0), env="race")),
    ("race step non-str agent", Bad("0", lambda env: env.step({0: 1, **RACE_ACTIONS}), env="race")),
    ("race step action 7", Bad("robot_2", race_step(robot_2=7), env="race")),
    ("race step action -1", Bad("robot_1", race_step(robot_1=-1), env="race")),
    ("race step action float", Bad("robot_0", race_step(robot_0=1.5), env="race")),
    ("race step action None", Bad("robot_3", race_step(robot_3=None), env="race")),
    ("race step action bool", Bad("robot_0", race_step(robot_0=True), env="race")),
    ("race step action str", Bad("robot_0", race_step(robot_0="1"), env="race")),
    (
        "race step removed agent bad action",
        Bad("robot_0", lambda env: env.step({"robot_0": 9, "robot_1": 0, "robot_2": 0}), env="race-removed"),
    ),
    (
        "race step parked agent bad action",
        Bad("robot_0", lambda env: env.step({"robot_0": 9, "robot_1": 0, "robot_2": 0}), env="race-parked"),
    ),
    ("race observation_space unknown", Bad("robot_9", lambda env: env.observation_space("robot_9"), env="race")),
    ("race action_space unknown", Bad("agent", lambda env: env.action_space(0), env="race")),
    ("race set_cells too few", Bad("cells", lambda env: env.set_cells([(0, 0)]), env="race")),
    ("race set_cells shared", Bad("cells", lambda env: env.set_cells([(0, 0), (0, 0), (6, 0), (6, 6)]), env="race")),
    ("race set_cells exit", Bad("cells", lambda env: env.set_cells([(3, 3), (0, 0), (6, 0), (6, 6)]), env="race")),
    ("race set_cells outside", Bad("cells", lambda env: env.set_cells([(9, 9), (0, 0), (6, 0), (6, 6)]), env="race")),
    ("race set_cells None", Bad("cells", lambda env: env.set_cells(None), env="race")),
    # ---- race (AEC): PettingZoo's AssertOutOfBoundsWrapper rejects out-of-space actions with an AssertionError
    ("aec step 7", Bad("action", lambda env: env.step(7), env="aec", errors=(ValueError, TypeError, AssertionError))),
    ("aec step float", Bad("action", lambda env: env.step(1.5), env="aec", errors=(ValueError, TypeError, AssertionError))),
    ("aec step str", Bad("action", lambda env: env.step("1"), env="aec", errors=(ValueError, TypeError, AssertionError))),
    ("aec step True", Bad("robot_0", lambda env: env.step(True), env="aec")),
    # ---- BabyRobotRace-v0: step
    *[
        (f"{name} step {label}", Bad("action", lambda env, a=a: env.step(a), env=name))
        for name in ("race-gym", "race-gym-make")
        for label, a in [("7", 7), ("-1", -1), ("1.5", 1.5), ("None", None), ("True", True), ("str", "2")]
    ],
    ("race-gym random opponents step 7", Bad("action", lambda env: env.step(7), env="race-gym-random")),
    # ---- the command line: babyrobot_marl.cli.main
    ("cli unknown command", Bad("invalid choice", argv=("fly",))),
    ("cli unknown option", Bad("--bogus", argv=("play", "--bogus"))),
    ("cli play unknown level", Bad("nope", argv=("play", "--level", "nope"))),
    ("cli play unknown policy", Bad("greedy", argv=("play", "--policy", "greedy"))),
    ("cli play negative seed", Bad("--seed", argv=("play", "--seed", "-1"))),
    ("cli play seed not an integer", Bad("--seed", argv=("play", "--seed", "x"))),
    ("cli play max-steps 0", Bad("--max-steps", argv=("play", "--max-steps", "0"))),
    ("cli play delay nan", Bad("--delay", argv=("play", "--delay", "nan"))),
    ("cli play level missing value", Bad("--level", argv=("play", "--level"))),
    ("cli play maze 1x1", Bad("maze-1x1", argv=("play", "--level", "maze-1x1"))),
    ("cli play maze too wide", Bad("maze-300x3", argv=("play", "--level", "maze-300x3"))),
    ("cli play missing file", Bad("no such level file", argv=("play", "--level", "{tmp}/missing.txt"))),
    ("cli play broken file", Bad("line 2, column 3", argv=("play", "--level", "{tmp}/broken.txt"))),
    ("cli play empty file", Bad("empty", argv=("play", "--level", "{tmp}/empty.txt"))),
    ("cli play binary file", Bad("cannot read", argv=("play", "--level", "{tmp}/binary.txt"))),
    ("cli play no free cell", Bad("level", argv=("play", "--level", "{tmp}/only-exit.txt"))),
    ("cli levels unknown", Bad("nope", argv=("levels", "nope"))),
    ("cli levels two names", Bad("one level", argv=("levels", "walls", "--show", "glass"))),
    ("cli levels show missing value", Bad("--show", argv=("levels", "--show"))),
    ("cli race zero robots", Bad("--robots", argv=("race", "--robots", "0"))),
    ("cli race robots over free cells", Bad("robots", argv=("race", "--level", "default", "--robots", "9"))),
    ("cli race too few starts", Bad("robots", argv=("race", "--level", "race-2", "--robots", "3", "--start", "level"))),
    ("cli race policies count", Bad("policies", argv=("race", "--robots", "3", "--policies", "random,shortest"))),
    ("cli race policies empty", Bad("policy", argv=("race", "--policies", ","))),
    ("cli race collisions", Bad("crash", argv=("race", "--collisions", "crash"))),
    ("cli race start", Bad("bogus", argv=("race", "--start", "bogus"))),
    ("cli race max-cycles", Bad("--max-cycles", argv=("race", "--max-cycles", "-5"))),
    ("cli race level file no free cell", Bad("robots", argv=("race", "--level", "{tmp}/only-exit.txt"))),
]
TABLE = [pytest.param(c[1], id=c[0]) if type(c) is tuple else c for c in CASES]


def write_level_files(tmp) -> None:
    (tmp / "broken.txt").write_text("+-+-+\n|S?E|\n+-+-+\n")
    (tmp / "empty.txt").write_text("")
    (tmp / "binary.txt").write_bytes(b"\xff\xfe\x00+-+")
    (tmp / "only-exit.txt").write_text("+-+\n|E|\n+-+\n")


def own_message(err: BaseException) -> str:
    """The error's message, without the kwargs gymnasium.make appends to a TypeError (they name every argument)."""
    return str(err).split(" was raised from the environment creator for ")[0]


def run_cli(argv: list[str]) -> int:
    try:
        return cli.main(argv)
    except SystemExit as exit_:  # argparse errors
        return exit_.code if isinstance(exit_.code, int) else 1


@pytest.mark.filterwarnings("ignore:.*render_mode.*:UserWarning")
@pytest.mark.parametrize("case", TABLE)
def test_bad_input_is_a_clear_error_naming_it_and_changes_nothing(case: Bad, tmp_path, capsys):
    if case.argv is not None:
        write_level_files(tmp_path)
        code = run_cli([a.replace("{tmp}", str(tmp_path)) for a in case.argv])
        captured = capsys.readouterr()
        assert code != 0
        assert "Traceback" not in captured.err
        assert captured.err.count("\n") == 1 and captured.err.endswith("\n"), f"not one line on stderr:\n{captured.err}"
        assert ": error: " in captured.err and case.names in captured.err, captured.err
        assert captured.out == ""
        return
    if case.env is None:
        with pytest.raises(case.errors) as info:
            case.call()
        assert case.names in own_message(info.value), f"{own_message(info.value)!r} should name {case.names!r}"
        return
    spec = ENVS[case.env]
    env, twin = ready(case.env), ready(case.env)
    assert fingerprint(env, spec.kind) == fingerprint(twin, spec.kind)
    with pytest.raises(case.errors) as info:
        case.call(env)
    assert case.names in own_message(info.value), f"{own_message(info.value)!r} should name {case.names!r}"
    assert fingerprint(env, spec.kind) == fingerprint(twin, spec.kind), "the rejected call changed the env"
    later = drive(env, spec.kind, 40, np.random.default_rng(1))  # still usable, and on the same course as its twin
    assert later == drive(twin, spec.kind, 40, np.random.default_rng(1))


def test_every_env_of_the_table_is_driven_by_its_random_numbers():
    """The twin comparison would miss a changed generator on an env whose course ignores it."""
    for name, spec in ENVS.items():
        courses = set()
        for seed in range(4):
            env = spec.factory()
            env.reset(seed=seed)
            courses.add(repr(drive(env, spec.kind, 40, np.random.default_rng(1))))
        assert len(courses) > 1, name


# --------------------------------------------------------------------------------------- good values near the bad ones
@pytest.mark.parametrize("value", [np.float32(0.5), np.int64(1)], ids=["float32", "int64"])
def test_numpy_numbers_are_accepted_as_rule_values_and_rewards(value):
    assert Rules(glass_pass_prob=value).glass_pass_prob == float(value)
    assert Rules(win_bonus=value).win_bonus == float(value)
    level = levels.get("default").with_rewards({(1, 1): value})
    assert level.reward_map() == {(1, 1): float(value)}
    assert levels.get("default").with_rewards([((1, 1), value)]) == level


@pytest.mark.parametrize(
    "action", [np.int64(2), np.array(2), babyrobot_marl.Action.EAST], ids=["np.int64", "0-d array", "Action"]
)
def test_integer_like_actions_are_accepted_by_every_env(action):
    for name in ("single", "race-gym"):
        env, twin = ready(name), ready(name)
        assert plain(env.step(action)) == plain(twin.step(2))
    env, twin = ready("race"), ready("race")
    assert plain(env.step({**RACE_ACTIONS, "robot_1": action})) == plain(twin.step({**RACE_ACTIONS, "robot_1": 2}))
