"""The ``babyrobot-marl`` command: list and show levels, watch an episode in the terminal.

::

    babyrobot-marl levels                      # the built-in levels: size, starts, exits, features
    babyrobot-marl levels maze-8x8             # one level's text (also: --show NAME, or a file path)
    babyrobot-marl play --level walls --policy shortest --seed 0
    babyrobot-marl race --level race-4 --robots 4 --policies shortest,shortest,random,random
    python -m babyrobot_marl play --level default --policy random --no-delay
    babyrobot-marl solve --level puddles       # value iteration: the value grid and the policy arrows
    babyrobot-marl train --level maze-8x8 --steps 3000000 --save ppo.pt  # PPO (the 'train' extra)
    babyrobot-marl play --level maze-8x8 --policy ppo.pt       # replay a saved policy

Each subcommand is a ``_add_<name>_parser`` function that registers its arguments and a
``_cmd_<name>(args, out)`` handler; the shared pieces (``--level``, ``--seed``, the display
options; ``animation.animate`` shows the frames) are small functions so that further
subcommands reuse them.

Bad input (an unknown level or policy, a negative seed, a bad delay, a broken level file, a
directory or FIFO or device given as a level, a level past the size limits) ends with exit
status 2 and one line on stderr, ``babyrobot-marl: error: ...``, never a traceback. Argument
types live in ``cli_args``, level loading (bounded file reads) in ``level_files``.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import NoReturn, TextIO

from . import __version__, levels
from .animation import DEFAULT_DELAY, Display
from .animation import animate as _animate
from .animation import isatty as _isatty
from .cli_args import (
    int_at_least,
    non_negative_int,
    policy_list,
    policy_spec,
    positive_float,
    positive_int,
    probability,
    race_count,
    seconds,
)
from .core.actions import Action
from .core.level import Level
from .core.rules import COLLISION_MODES
from .envs.common import OUTCOME_NAMES
from .envs.race import START_MODES, RaceEnv
from .envs.single import BabyRobotEnv
from .level_files import load_level
from .render.ansi import frame, robot_glyph
from .training.deps import MissingTrainExtraError
from .training.policy import make_policy

PROG = "babyrobot-marl"
EXIT_USAGE = 2  # bad input, as argparse uses
EXIT_INTERRUPTED = 130  # Ctrl-C, as a shell reports it


class _Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are one line: no usage block, no traceback."""

    def error(self, message: str) -> NoReturn:
        # argparse quotes the arguments it rejects: keep a newline or a huge argument from breaking the one line
        self.exit(EXIT_USAGE, f"{self.prog}: error: {_one_line(message)} (see '{self.prog} --help')\n")


# Argument types live in cli_args (kept importable here under their former names).
_int_at_least, _non_negative_int, _positive_int = int_at_least, non_negative_int, positive_int
_seconds, _probability, _positive_float = seconds, probability, positive_float
_policy_list, _policy_spec = policy_list, policy_spec


# ------------------------------------------------------------------------ shared arguments
def _add_level_arg(p: argparse.ArgumentParser, default: str = "default") -> None:
    p.add_argument(
        "--level",
        default=default,
        metavar="NAME|FILE",
        help=f"a built-in level (see '{PROG} levels'), maze-WxH[-sSEED], or the path of a level text file (default: {default})",
    )


def _add_seed_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--seed",
        type=_non_negative_int,
        default=None,
        metavar="N",
        help="seed of the episode and of random policies (default: a fresh one, printed at the end so it can be replayed)",
    )


def _add_display_args(p: argparse.ArgumentParser) -> None:
    delay = p.add_mutually_exclusive_group()
    delay.add_argument(
        "--delay",
        type=_seconds,
        default=None,
        metavar="SECONDS",
        help=f"pause between frames (default: {DEFAULT_DELAY} on a terminal, 0 when the output is a file or pipe)",
    )
    delay.add_argument("--no-delay", dest="delay", action="store_const", const=0.0, help="no pause between frames")
    p.add_argument("--no-color", action="store_true", help="no ANSI colours (also: set the NO_COLOR environment variable)")


# ------------------------------------------------------------------------ shared helpers
def _display(args: argparse.Namespace, out: TextIO) -> Display:
    tty = _isatty(out)
    colour = tty and not args.no_color and not os.environ.get("NO_COLOR")
    delay = args.delay if args.delay is not None else (DEFAULT_DELAY if tty else 0.0)
    return Display(colour=colour, clear=tty, delay=delay)


# ------------------------------------------------------------------------ levels
def _add_levels_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "levels",
        help="list the built-in levels, or show one",
        description="List the built-in levels, or print one level's text.",
    )
    p.add_argument(
        "name", nargs="?", metavar="NAME", help="print this level's text (a built-in name, maze-WxH[-sSEED] or a file)"
    )
    p.add_argument("--show", metavar="NAME", help="the same as giving NAME")
    p.set_defaults(func=_cmd_levels)


def _features(level: Level) -> str:
    kinds = [
        ("walls", level.walls),
        ("glass", level.glass),
        ("puddles", level.small_puddles | level.large_puddles),
        ("blocked", level.blocked),
    ]
    return ", ".join(name for name, items in kinds if items) or "-"


def _cmd_levels(args: argparse.Namespace, out: TextIO) -> int:
    if args.name and args.show and args.name != args.show:
        raise ValueError(f"levels: give one level to show, got {args.name!r} and --show {args.show!r}")
    name = args.name or args.show
    if name:
        out.write(load_level(name).to_ascii() + "\n")
        return 0
    rows = [("name", "size", "starts", "exits", "features")]
    for n in levels.names():
        lv = levels.get(n)
        rows.append((n, f"{lv.width}x{lv.height}", str(len(lv.starts)), str(len(lv.exits)), _features(lv)))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]
    for r in rows:
        out.write("  ".join(c.ljust(w) for c, w in zip(r[:-1], widths, strict=True)) + "  " + r[-1] + "\n")
    out.write(f"\nalso maze-WxH and maze-WxH-sSEED for any size and seed; show one with '{PROG} levels NAME'\n")
    return 0


# ------------------------------------------------------------------------ play
@dataclass
class EpisodeSummary:
    """Filled in while an episode's frames are drawn."""

    seed: int
    steps: int = 0
    ret: float = 0.0
    reached_exit: bool = False


def _add_play_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "play",
        help="watch one robot play one episode in the terminal",
        description="Animate one episode of BabyRobot-v0 with a scripted policy, then print steps, return and outcome.",
    )
    _add_level_arg(p)
    p.add_argument(
        "--policy",
        default="shortest",
        type=_policy_spec,
        help="random: uniform actions; shortest: the shortest path to the exit; keys: you drive (arrow keys); or the "
        "path of a policy saved by 'train --save' (default: shortest)",
    )
    _add_seed_arg(p)
    p.add_argument(
        "--max-steps",
        type=_positive_int,
        default=None,
        metavar="N",
        help="truncate after N steps (default: 4 per cell, at least 100)",
    )
    _add_display_args(p)
    p.set_defaults(func=_cmd_play)


def _fresh_seed() -> int:
    return int.from_bytes(os.urandom(4), "little") >> 1  # < 2**31: short enough to retype


def _episode_frames(env: BabyRobotEnv, policy: Callable, summary: EpisodeSummary, colour: bool) -> Iterator[str]:
    """Run one episode, yielding a frame after the reset and after every step."""
    obs, _ = env.reset(seed=summary.seed)
    yield frame(env.level, [env.robot_cell], f"step 0/{env.max_steps}  return 0", colour=colour)
    while True:
        action = policy(obs)
        obs, reward, terminated, truncated, info = env.step(action)
        summary.steps += 1
        summary.ret += reward
        summary.reached_exit = terminated
        outcome = OUTCOME_NAMES[info["outcome"]]
        status = f"step {summary.steps}/{env.max_steps}  return {summary.ret:g}  {Action(action).name} -> {outcome}"
        yield frame(env.level, [env.robot_cell], status, colour=colour)
        if terminated or truncated:
            return


def _cmd_play(args: argparse.Namespace, out: TextIO) -> int:
    level = load_level(args.level)
    env = BabyRobotEnv(level=level, max_steps=args.max_steps)
    seed = _fresh_seed() if args.seed is None else args.seed
    if args.policy == "keys":  # the keyboard game: babyrobot_marl.play.terminal
        from .play.terminal import play_keys

        return play_keys(env, seed, level.name or args.level, _display(args, out).colour, out)
    policy = make_policy(args.policy, env.table, seed, env=env)  # a saved policy reads this env's observations
    display = _display(args, out)
    summary = EpisodeSummary(seed=seed)
    _animate(_episode_frames(env, policy, summary, display.colour), display, out)
    outcome = "reached the exit" if summary.reached_exit else f"did not reach the exit (truncated after {env.max_steps} steps)"
    out.write(
        f"\nlevel {level.name or args.level}, policy {args.policy}, seed {seed}: "
        f"{summary.steps} steps, return {summary.ret!r}, {outcome}\n"
    )
    return 0


# ------------------------------------------------------------------------ race
@dataclass
class RobotResult:
    """One robot's line of the results table."""

    name: str
    policy: str
    rank: int = 0  # 0: did not finish
    steps: int = 0
    ret: float = 0.0
    collisions: int = 0


def _add_race_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "race",
        help="watch several robots race to the exit in the terminal",
        description="Animate one race of race_v0 with scripted robots, then print the results table.",
    )
    _add_level_arg(p, default="race-4")
    p.add_argument("--robots", type=_positive_int, default=4, metavar="N", help="how many robots race (default: 4)")
    p.add_argument(
        "--policies",
        type=_policy_list,
        default=["shortest"],
        metavar="P1,P2,...",
        help="one policy per robot (random, shortest or a saved policy's path), or one for all (default: shortest)",
    )
    p.add_argument("--collisions", choices=COLLISION_MODES, default="block", help="collision rule (default: block)")
    p.add_argument(
        "--start",
        choices=START_MODES,
        default="fill",
        help="level: the level's numbered starts; fill: those, then random free cells; random: all random (default: fill)",
    )
    _add_seed_arg(p)
    p.add_argument("--max-cycles", type=_positive_int, default=None, metavar="N", help="truncate the race after N steps")
    p.add_argument("--human", type=_non_negative_int, default=None, metavar="N", help="drive robot N yourself (arrow keys)")
    p.add_argument("--races", type=race_count, default=None, metavar="N", help="run N seeded races; print metrics, no frames")
    _add_display_args(p)
    p.set_defaults(func=_cmd_race)


def _race_frames(env: RaceEnv, robot_policies: list, results: list[RobotResult], seed: int, colour: bool) -> Iterator[str]:
    """Run one race, yielding a frame after the reset and after every step."""
    obs, _ = env.reset(seed=seed)
    yield env.render_text(colour=colour)
    while env.agents:
        actions = {a: robot_policies[env.possible_agents.index(a)](obs[a]) for a in env.agents}
        obs, rewards, terms, truncs, infos = env.step(actions)
        for a, info in infos.items():
            r = results[env.possible_agents.index(a)]
            r.steps = env.elapsed_steps
            if "rank" in info:
                r.rank = info["rank"]
        yield env.render_text(colour=colour)
    for r, ret, bumps in zip(results, env.returns, env.collisions_count):
        r.ret, r.collisions = ret, bumps


def _results_table(results: list[RobotResult]) -> str:
    rows = [("rank", "robot", "policy", "steps", "return", "collisions")]
    order = sorted(results, key=lambda r: (r.rank == 0, r.rank, r.name))
    for r in order:
        rank = str(r.rank) if r.rank else "-"
        steps = str(r.steps) if r.rank else f"{r.steps} (not finished)"
        rows.append((rank, r.name, r.policy, steps, f"{r.ret:g}", str(r.collisions)))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip() for row in rows)


def _cmd_race(args: argparse.Namespace, out: TextIO) -> int:
    level = load_level(args.level)
    if len(args.policies) not in (1, args.robots):
        raise ValueError(f"policies: give one policy for all robots or one per robot ({args.robots}), got {len(args.policies)}")
    # The env checks the robots against the level's starts and free cells before anything per robot exists.
    env = RaceEnv(
        level=level, n_robots=args.robots, collisions=args.collisions, start=args.start, max_cycles=args.max_cycles
    )
    names = args.policies * args.robots if len(args.policies) == 1 else args.policies
    seed = _fresh_seed() if args.seed is None else args.seed
    if args.races:  # experiments: the metrics table of N races (babyrobot_marl.experiments)
        if args.human is not None:
            raise ValueError("--human: you drive one race with frames; drop --races (N races without frames) or --human")
        from .experiments import run_races

        kw = {"collisions": args.collisions, "start": args.start, "max_cycles": args.max_cycles}
        out.write(f"{run_races(level, _race_policies(names, env), args.races, seed, **kw).table()}\nseed {seed}\n")
        return 0
    robot_policies = [make_policy(name, env.table, seed=seed + 7919 * (i + 1), env=env) for i, name in enumerate(names)]
    if args.human is not None and args.human < args.robots:
        names[args.human] = "keys"
    results = [RobotResult(robot_glyph(i, args.robots) + f" {agent}", names[i]) for i, agent in enumerate(env.possible_agents)]
    display = _display(args, out)
    frames = _race_frames(env, robot_policies, results, seed, display.colour)
    if args.human is not None:  # babyrobot_marl.play: your keys for one robot; a paced, legended race on a terminal
        from .play.terminal import race_keys

        race_keys(env, robot_policies, args.human, seed, results, display.delay, display.colour, out)
    elif display.clear:
        from .play.watch import watch_race

        watch_race(env, robot_policies, seed, frames, names, display.delay, display.colour, out)
    else:
        _animate(frames, display, out)
    out.write(
        f"\nrace on {level.name or args.level}, {args.robots} robots, collisions {args.collisions}, seed {seed}, "
        f"{env.elapsed_steps} steps\n\n{_results_table(results)}\n"
    )
    return 0


def _race_policies(names: list[str], env: RaceEnv) -> list:
    """``run_races``'s policies: scripted names as they are (seeded per race there), each saved policy
    loaded once (greedy: no seed) and reading ``env``'s observations."""
    from .policies import POLICY_NAMES

    loaded = {n: make_policy(n, env.table, env=env) for n in dict.fromkeys(names) if n not in POLICY_NAMES}
    return [loaded.get(n, n) for n in names]


# ------------------------------------------------------------------------ solve
def _add_solve_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "solve",
        help="solve a level exactly (value or policy iteration) and print values and policy",
        description="Dynamic programming on the exact model of one robot: prints the value grid and the greedy policy "
        "as arrows (o: STAY, E: exit, #: blocked, .: no exit reachable).",
    )
    _add_level_arg(p)
    p.add_argument("--method", choices=("value", "policy"), default="value", help="value or policy iteration (default: value)")
    p.add_argument("--gamma", type=_probability, default=1.0, metavar="G", help="discount in (0, 1] (default: 1)")
    p.add_argument(
        "--theta", type=_positive_float, default=1e-9, metavar="T", help="stop when no value moves by T (default: 1e-9)"
    )
    p.add_argument("--decimals", type=_int_at_least(0), default=1, metavar="N", help="decimals of the values (default: 1)")
    p.set_defaults(func=_cmd_solve)


def _cmd_solve(args: argparse.Namespace, out: TextIO) -> int:
    from .planning import model, policy_iteration, policy_text, value_iteration, value_text

    level = load_level(args.level)
    m = model(level)
    solve = value_iteration if args.method == "value" else policy_iteration
    sol = solve(m, gamma=args.gamma, theta=args.theta)
    unit = "sweeps" if args.method == "value" else "improvement rounds"
    out.write(f"{args.method} iteration on {level.name or args.level} ({level.width}x{level.height}), "
              f"gamma {args.gamma:g}, theta {args.theta:g}: {sol.iterations} {unit}\n\n")
    out.write("values\n" + value_text(sol, args.decimals) + "\n\npolicy\n" + policy_text(sol) + "\n")
    if level.starts:
        start = m.table.cell_id(level.starts[0])
        out.write(f"\noptimal return from the start {level.starts[0]}: {sol.values[start]:.{args.decimals}f}\n")
    return 0


# ------------------------------------------------------------------------ entry point
def build_parser() -> argparse.ArgumentParser:
    """The parser of ``babyrobot-marl`` with all subcommands."""
    parser = _Parser(prog=PROG, description="Baby Robot grid worlds: levels, and episodes watched in the terminal.")
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    _add_levels_parser(sub)
    _add_play_parser(sub)
    _add_race_parser(sub)
    _add_solve_parser(sub)
    from .training.cli import add_train_parser  # the train command lives with the trainers

    add_train_parser(sub)  # each further subcommand: one _add_<name>_parser(sub) line here
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 bad input, 130 interrupted)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    out = sys.stdout
    if args.command is None:
        parser.print_help(out)
        return 0
    try:
        return args.func(args, out)
    except MissingTrainExtraError as err:  # e.g. a saved policy without torch: how to install it, on one line
        print(f"{PROG}: error: {_one_line(err)}", file=sys.stderr)
        return EXIT_USAGE
    except (ValueError, TypeError) as err:
        print(f"{PROG}: error: {_one_line(err)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # The reader went away (e.g. '| head'): stop quietly; point stdout at devnull so that
        # Python's flush at exit does not raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except OSError as err:  # e.g. an output path that cannot be written
        print(f"{PROG}: error: {_one_line(err)}", file=sys.stderr)
        return EXIT_USAGE
    except MemoryError:  # the last resort: the limits (README "Limits") should stop large inputs before this
        print(f"{PROG}: error: out of memory; try a smaller level or fewer robots", file=sys.stderr)
        return EXIT_USAGE


def _one_line(err: BaseException | str, limit: int = 1000) -> str:
    """The message on one line, at most ``limit`` characters."""
    text = " ".join(str(err).split()) or type(err).__name__
    return text if len(text) <= limit else f"{text[: limit - 40]}... ({len(text):,} characters)"
