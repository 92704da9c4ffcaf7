"""``babyrobot-marl race``: several robots race to the exit (or each to its own target, ``--goals own``) in the
terminal, or N seeded races' metrics (``--races``)."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, TextIO

from ..core.rules import COLLISION_MODES
from ..envs.race import START_MODES, RaceEnv
from ..experiments.races import OwnGoalRobot
from ..levels.files import load_level
from ..levels.sources import parse_level_family
from ..play.screen import animate
from ..render.ansi import ROBOT_COLOURS, robot_glyph
from ..training.policy import make_policy
from .checks import (
    check_goal_flags,
    check_policy_goals,
    check_race_gif,
    non_negative_int,
    output_path,
    policies_form,
    policy_list,
    positive_int,
    race_count,
)
from .common import add_display_args, add_goal_args, add_level_arg, add_seed_arg, display_of, fresh_seed
from .levels import level_label


@dataclass
class RobotResult:
    """One robot's line of the results table."""

    name: str
    policy: str
    rank: int = 0  # 0: did not finish
    steps: int = 0
    ret: float = 0.0
    collisions: int = 0
    target: str = ""  # own goals: the robot's target cell, "(x, y)"
    reached: int = 0  # own goals: the targets it reached


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "race",
        help="watch several robots race to the exit (or each to its own target) in the terminal",
        description="Animate one race of race_v0 with scripted or saved policies, then print the results table "
        "(with --goals own: each robot's target and whether it reached it; with --lifelong: the targets each "
        "reached and the throughput).",
    )
    add_level_arg(p, default="race-4")
    p.add_argument("--robots", type=positive_int, default=4, metavar="N", help="how many robots race (default: 4)")
    p.add_argument(
        "--policies",
        type=policy_list,
        default=["shortest"],
        metavar="P1,P2,...",
        help="one policy per robot (random, shortest or a saved policy's path), or one for all (default: shortest)",
    )
    p.add_argument("--collisions", choices=COLLISION_MODES, default="block",
                   help="collision rule; soft: POGEMA's (default: block)")
    add_goal_args(p)
    p.add_argument(
        "--start",
        choices=START_MODES,
        default="fill",
        help="level: the level's numbered starts; fill: those, then random free cells; random: all random (default: fill)",
    )
    add_seed_arg(p)
    p.add_argument("--max-cycles", type=positive_int, default=None, metavar="N", help="truncate the race after N steps")
    p.add_argument("--human", type=non_negative_int, default=None, metavar="N", help="drive robot N yourself (arrow keys)")
    p.add_argument("--races", type=race_count, default=None, metavar="N", help="run N seeded races; print metrics, no frames")
    p.add_argument("--gif", type=output_path, default=None, metavar="PATH",
                   help="also save the race as a GIF here, one picture per step (imageio: the video extra)")
    add_display_args(p)
    p.set_defaults(func=run)


def race_frames(env: RaceEnv, robot_policies: list, results: list[RobotResult], seed: int, colour: bool,
                 pictures: list | None = None) -> Iterator[str]:
    """Run one race, yielding a frame after the reset and after every step (``pictures``: also each one's
    ``rgb_array`` picture, appended, for an env made with that render mode)."""
    obs, _ = env.reset(seed=seed)
    if pictures is not None:
        pictures.append(env.render())
    yield _with_targets(env, env.render_text(colour=colour), colour)
    while env.agents:
        actions = {a: robot_policies[env.possible_agents.index(a)](obs[a]) for a in env.agents}
        obs, rewards, terms, truncs, infos = env.step(actions)
        for a, info in infos.items():
            r = results[env.possible_agents.index(a)]
            r.steps = env.elapsed_steps
            if "rank" in info:
                r.rank = info["rank"]
        if pictures is not None:
            pictures.append(env.render())
        yield _with_targets(env, env.render_text(colour=colour), colour)
    _fill_goals(env, results)
    for r, ret, bumps in zip(results, env.returns, env.collisions_count):
        r.ret, r.collisions = ret, bumps


def glyph(i: int, n: int, colour: bool) -> str:
    """Robot ``i``'s letter, in its colour on a terminal."""
    g = robot_glyph(i, n)
    return f"\x1b[1;{ROBOT_COLOURS[i % len(ROBOT_COLOURS)]}m{g}\x1b[0m" if colour else g


SHOWN_TARGETS = 12  # robots whose target a frame's line names; the rest are counted


def _with_targets(env: RaceEnv, text: str, colour: bool) -> str:
    """A frame and, with own goals, a line of each racing robot's target (they change under --lifelong)."""
    if env.goals is None:
        return text
    racing = [i for i, rank in enumerate(env.ranks) if not rank]
    cells = env.goals
    shown = [f"{glyph(i, env.n_robots, colour)} {cells[env.possible_agents[i]]}" for i in racing[:SHOWN_TARGETS]]
    more = f"  ... and {len(racing) - SHOWN_TARGETS} more" if len(racing) > SHOWN_TARGETS else ""
    return f"{text}\ntargets: {'  '.join(shown)}{more}" if shown else text


def _fill_goals(env: RaceEnv, results: list[RobotResult]) -> None:
    """Own goals: each robot's target (the last one under --lifelong) and the targets it reached."""
    if env.goals is None:
        return
    for r, agent, reached in zip(results, env.possible_agents, env.goals_reached):
        r.target, r.reached = str(env.goals[agent]), reached


def results_table(results: list[RobotResult], goals: str = "exit", lifelong: bool = False) -> str:
    """One row per robot: its rank, steps, return and collisions; with own goals its target and whether it
    reached it (``lifelong``: how many targets it reached, in robot order, no ranks)."""
    if lifelong:
        rows = [("robot", "policy", "targets reached", "return", "collisions")]
        rows += [(r.name, r.policy, str(r.reached), f"{r.ret:g}", str(r.collisions)) for r in results]
        return _aligned(rows)
    own = goals == "own"
    rows = [("rank", "robot", "policy", *(("target", "reached") if own else ()), "steps", "return", "collisions")]
    order = sorted(results, key=lambda r: (r.rank == 0, r.rank, r.name))
    for r in order:
        rank = str(r.rank) if r.rank else "-"
        steps = str(r.steps) if r.rank else f"{r.steps} (not finished)"
        goal = (r.target, "yes" if r.reached else "no") if own else ()
        rows.append((rank, r.name, r.policy, *goal, steps, f"{r.ret:g}", str(r.collisions)))
    return _aligned(rows)


def _aligned(rows: list[tuple[str, ...]]) -> str:
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip() for row in rows)


def run(args: argparse.Namespace, out: TextIO) -> int:
    family = parse_level_family(args.level) is not None  # maze:A..B: a new maze every race, drawn by the env
    level = args.level if family else load_level(args.level)
    if len(args.policies) not in (1, args.robots):
        raise ValueError(f"--policies: give one policy for all robots or one per robot ({args.robots}), got {len(args.policies)}")
    check_goal_flags(args.goals, args.lifelong)
    check_policy_goals(args.policies, args.goals, "--policies")  # what each saved policy was trained for
    form = policies_form(args.policies)  # the observations the saved policies read
    goals = {"goals": args.goals, "lifelong": args.lifelong}
    if args.gif:
        check_race_gif(args)
    # The env checks the robots against the level's starts and free cells before anything per robot exists
    env = RaceEnv(level=level, n_robots=args.robots, collisions=args.collisions, start=args.start,
                  max_cycles=args.max_cycles, render_mode="rgb_array" if args.gif else None, **{**form, **goals})
    names = args.policies * args.robots if len(args.policies) == 1 else args.policies
    seed = fresh_seed() if args.seed is None else args.seed
    if args.races:  # experiments: the metrics table of N races (babyrobot_marl.experiments)
        if args.human is not None:
            raise ValueError("--human: you drive one race with frames; drop --races (N races without frames) or --human")
        from ..experiments.races import run_races

        kw = {"collisions": args.collisions, "start": args.start, "max_cycles": args.max_cycles, **form, **goals}
        out.write(f"{run_races(level, _race_policies(names, env), args.races, seed, **kw).table()}\nseed {seed}\n")
        return 0
    if family:  # the scripted robots plan on the level this seed draws (the race below resets with it again)
        env.reset(seed=seed)
    robot_policies = [robot_policy(env, i, name, seed) for i, name in enumerate(names)]
    if args.human is not None and args.human < args.robots:
        names[args.human] = "keys"
    results = [RobotResult(robot_glyph(i, args.robots) + f" {agent}", names[i]) for i, agent in enumerate(env.possible_agents)]
    display = display_of(args, out)
    pictures: list | None = [] if args.gif else None
    frames = race_frames(env, robot_policies, results, seed, display.colour, pictures)
    if args.human is not None:  # babyrobot_marl.play: your keys for one robot; a paced, legended race on a terminal
        from ..play.terminal import race_keys

        race_keys(env, robot_policies, args.human, seed, results, display.delay, display.colour, out)
    elif display.clear:
        from ..play.watch import watch_race

        watch_race(env, robot_policies, seed, frames, names, display.delay, display.colour, out)
    else:  # a file or pipe: the frames, then the key once
        from ..play.watch import legend

        animate(frames, display, out)
        out.write("\n".join(legend(names, level=env.level, goals=args.goals, lifelong=args.lifelong)) + "\n")
    name = f"{env.level.name} (from {args.level})" if family else level_label(level, args.level)
    task = {"exit": "", "own": ", own goals"}[args.goals] + (", lifelong" if args.lifelong else "")
    out.write(
        f"\nrace on {name}, {args.robots} robots, collisions {args.collisions}{task}, seed {seed}, "
        f"{env.elapsed_steps} steps\n\n{results_table(results, args.goals, args.lifelong)}\n"
    )
    if args.lifelong:  # POGEMA's lifelong measure
        reached = sum(env.goals_reached)
        out.write(f"\nthroughput: {reached / max(env.elapsed_steps, 1):.3f} targets reached per step "
                  f"({reached} targets in {env.elapsed_steps} steps)\n")
    if pictures:
        from ..render.video import save_gif

        out.write(f"GIF of the race ({len(pictures)} pictures): {save_gif(pictures, args.gif)}\n")
    return 0


def robot_policy(env: RaceEnv, i: int, name: str, seed: int) -> Any:
    """Robot ``i``'s policy: a scripted one seeded from ``seed`` (with own goals ``shortest`` walks to the robot's
    own target), or a saved policy reading ``env``'s observations."""
    if name == "shortest" and env.goals_mode == "own":
        return OwnGoalRobot(env, i)
    return make_policy(name, env.table, seed=seed + 7919 * (i + 1), env=env)


def _race_policies(names: list[str], env: RaceEnv) -> list:
    """``run_races``'s policies: scripted names as they are (seeded per race there), each saved policy
    loaded once (greedy: no seed) and reading ``env``'s observations."""
    from ..policies import POLICY_NAMES

    loaded = {n: make_policy(n, env.table, env=env) for n in dict.fromkeys(names) if n not in POLICY_NAMES}
    return [loaded.get(n, n) for n in names]
