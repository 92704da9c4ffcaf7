"""``babyrobot-marl play``: one robot plays one episode in the terminal (a scripted or saved policy, or your keys):
to the exit, or with ``--goals own`` to its own target (``--robots N``: among shortest-path robots going to theirs)."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TextIO

from ..core.actions import Action
from ..core.outcomes import OUTCOME_NAMES
from ..core.rules import COLLISION_MODES
from ..envs.single import BabyRobotEnv
from ..play.screen import animate
from ..render.ansi import frame, symbols
from ..training.policy import make_policy
from .checks import check_play_flags, policy_spec, positive_int
from .common import add_display_args, add_goal_args, add_level_arg, add_seed_arg, display_of, fresh_seed
from .levels import level_of


@dataclass
class EpisodeSummary:
    """Filled in while an episode's frames are drawn."""

    seed: int
    steps: int = 0
    ret: float = 0.0
    reached_exit: bool = False


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "play",
        help="watch one robot play one episode in the terminal",
        description="Animate one episode of BabyRobot-v0 with a scripted policy, then print steps, return and outcome. "
        "With --goals own the robot (robot_0 of race_v0) goes to its own target instead, alone or, with --robots N, "
        "among shortest-path robots going to theirs under --collisions.",
    )
    add_level_arg(p)
    p.add_argument(
        "--policy",
        default="shortest",
        type=policy_spec,
        help="random: uniform actions; shortest: the shortest path to the exit; keys: you drive (arrow keys); or the "
        "path of a policy saved by 'train --save' (default: shortest)",
    )
    add_seed_arg(p)
    p.add_argument(
        "--max-steps",
        type=positive_int,
        default=None,
        metavar="N",
        help="truncate after N steps (default: 4 per cell, at least 100)",
    )
    add_goal_args(p, "go")
    p.add_argument("--robots", type=positive_int, default=1, metavar="N",
                   help="with --goals own: robots on the board, yours (robot_0, --policy) and N-1 shortest-path robots "
                   "(default: 1)")
    p.add_argument("--collisions", choices=COLLISION_MODES, default=None,
                   help="with --robots 2 or more: the collision rule; soft: POGEMA's (default: block)")
    add_display_args(p)
    p.set_defaults(func=run)


def _episode_frames(env: BabyRobotEnv, policy: Callable, summary: EpisodeSummary, colour: bool, key: str = "") -> Iterator[str]:
    """Run one episode, yielding a frame after the reset and after every step (``key``: a line under each)."""
    obs, _ = env.reset(seed=summary.seed)
    key = f"\n{key}" if key else ""
    yield frame(env.level, [env.robot_cell], f"step 0/{env.max_steps}  return 0{key}", colour=colour)
    while True:
        action = policy(obs)
        obs, reward, terminated, truncated, info = env.step(action)
        summary.steps += 1
        summary.ret += reward
        summary.reached_exit = terminated
        outcome = OUTCOME_NAMES[info["outcome"]]
        status = f"step {summary.steps}/{env.max_steps}  return {summary.ret:g}  {Action(action).name} -> {outcome}{key}"
        yield frame(env.level, [env.robot_cell], status, colour=colour)
        if terminated or truncated:
            return


def run(args: argparse.Namespace, out: TextIO) -> int:
    check_play_flags(args)
    seed = fresh_seed() if args.seed is None else args.seed
    level = level_of(args.level, seed)  # maze:A..B: the maze the seed draws
    if args.goals == "own":  # a race of robot_0 (and shortest-path robots) to their own targets
        from .play_goals import play_own_goal

        return play_own_goal(args, level, seed, out)
    env = BabyRobotEnv(level=level, max_steps=args.max_steps)
    if args.policy == "keys":  # the keyboard game: babyrobot_marl.play.terminal
        from ..play.terminal import play_keys

        return play_keys(env, seed, level.name or args.level, display_of(args, out).colour, out)
    policy = make_policy(args.policy, env.table, seed, env=env)  # a saved policy reads this env's observations
    display = display_of(args, out)
    summary = EpisodeSummary(seed=seed)
    key = symbols(env.level, "R robot")
    animate(_episode_frames(env, policy, summary, display.colour, key if display.clear else ""), display, out)
    if not display.clear:  # a log: the key once, under the frames
        out.write(f"{key}\n")
    outcome = "reached the exit" if summary.reached_exit else f"did not reach the exit (truncated after {env.max_steps} steps)"
    out.write(
        f"\nlevel {level.name or args.level}, policy {args.policy}, seed {seed}: "
        f"{summary.steps} steps, return {summary.ret!r}, {outcome}\n"
    )
    return 0
