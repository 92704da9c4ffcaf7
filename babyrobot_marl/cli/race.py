"""``babyrobot-marl race``: several robots race to the exit in the terminal, or N seeded races' metrics (``--races``)."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TextIO

from ..core.rules import COLLISION_MODES
from ..envs.race import START_MODES, RaceEnv
from ..levels.files import load_level
from ..levels.sources import parse_level_family
from ..play.screen import animate
from ..render.ansi import robot_glyph
from ..training.policy import make_policy
from .checks import non_negative_int, policies_form, policy_list, positive_int, race_count
from .common import add_display_args, add_level_arg, add_seed_arg, display_of, fresh_seed


@dataclass
class RobotResult:
    """One robot's line of the results table."""

    name: str
    policy: str
    rank: int = 0  # 0: did not finish
    steps: int = 0
    ret: float = 0.0
    collisions: int = 0


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "race",
        help="watch several robots race to the exit in the terminal",
        description="Animate one race of race_v0 with scripted robots, then print the results table.",
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
    p.add_argument("--collisions", choices=COLLISION_MODES, default="block", help="collision rule (default: block)")
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
    add_display_args(p)
    p.set_defaults(func=run)


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


def run(args: argparse.Namespace, out: TextIO) -> int:
    family = parse_level_family(args.level) is not None  # maze:A..B: a new maze every race, drawn by the env
    level = args.level if family else load_level(args.level)
    if len(args.policies) not in (1, args.robots):
        raise ValueError(f"--policies: give one policy for all robots or one per robot ({args.robots}), got {len(args.policies)}")
    form = policies_form(args.policies)  # the observations the saved policies read
    # The env checks the robots against the level's starts and free cells before anything per robot exists
    env = RaceEnv(level=level, n_robots=args.robots, collisions=args.collisions, start=args.start,
                  max_cycles=args.max_cycles, **form)
    names = args.policies * args.robots if len(args.policies) == 1 else args.policies
    seed = fresh_seed() if args.seed is None else args.seed
    if args.races:  # experiments: the metrics table of N races (babyrobot_marl.experiments)
        if args.human is not None:
            raise ValueError("--human: you drive one race with frames; drop --races (N races without frames) or --human")
        from ..experiments.races import run_races

        kw = {"collisions": args.collisions, "start": args.start, "max_cycles": args.max_cycles, **form}
        out.write(f"{run_races(level, _race_policies(names, env), args.races, seed, **kw).table()}\nseed {seed}\n")
        return 0
    if family:  # the scripted robots plan on the level this seed draws (the race below resets with it again)
        env.reset(seed=seed)
    robot_policies = [make_policy(name, env.table, seed=seed + 7919 * (i + 1), env=env) for i, name in enumerate(names)]
    if args.human is not None and args.human < args.robots:
        names[args.human] = "keys"
    results = [RobotResult(robot_glyph(i, args.robots) + f" {agent}", names[i]) for i, agent in enumerate(env.possible_agents)]
    display = display_of(args, out)
    frames = _race_frames(env, robot_policies, results, seed, display.colour)
    if args.human is not None:  # babyrobot_marl.play: your keys for one robot; a paced, legended race on a terminal
        from ..play.terminal import race_keys

        race_keys(env, robot_policies, args.human, seed, results, display.delay, display.colour, out)
    elif display.clear:
        from ..play.watch import watch_race

        watch_race(env, robot_policies, seed, frames, names, display.delay, display.colour, out)
    else:  # a file or pipe: the frames, then the key once
        from ..play.watch import legend

        animate(frames, display, out)
        out.write("\n".join(legend(names, level=env.level)) + "\n")
    name = f"{env.level.name} (from {args.level})" if family else level.name or args.level
    out.write(
        f"\nrace on {name}, {args.robots} robots, collisions {args.collisions}, seed {seed}, "
        f"{env.elapsed_steps} steps\n\n{_results_table(results)}\n"
    )
    return 0


def _race_policies(names: list[str], env: RaceEnv) -> list:
    """``run_races``'s policies: scripted names as they are (seeded per race there), each saved policy
    loaded once (greedy: no seed) and reading ``env``'s observations."""
    from ..policies import POLICY_NAMES

    loaded = {n: make_policy(n, env.table, env=env) for n in dict.fromkeys(names) if n not in POLICY_NAMES}
    return [loaded.get(n, n) for n in names]
