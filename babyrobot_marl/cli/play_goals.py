"""``babyrobot-marl play --goals own``: robot_0 of a race goes to its own target (a scripted or saved policy, or
your keys), alone or among shortest-path robots going to theirs; then its summary line."""

from __future__ import annotations

import argparse
from typing import TextIO

from ..core.level import Level
from ..envs.race import RaceEnv
from ..play.screen import animate
from ..render.ansi import robot_glyph
from .checks import policies_form
from .common import display_of
from .levels import level_label
from .race import RobotResult, race_frames, results_table, robot_policy

OTHERS = "shortest"  # the policy of the robots besides yours


def play_own_goal(args: argparse.Namespace, level: Level, seed: int, out: TextIO) -> int:
    """Play one episode of ``args`` (``--goals own``) on ``level``; robot_0 follows ``--policy``."""
    form = policies_form([args.policy]) if args.policy != "keys" else {}  # the observations a saved policy reads
    env = RaceEnv(level=level, n_robots=args.robots, collisions=args.collisions, start="fill", max_cycles=args.max_steps,
                  **{**form, "goals": "own", "lifelong": args.lifelong})
    names = [args.policy] + [OTHERS] * (args.robots - 1)
    policies = [None if name == "keys" else robot_policy(env, i, name, seed) for i, name in enumerate(names)]
    results = [RobotResult(robot_glyph(i, args.robots) + f" {agent}", names[i]) for i, agent in enumerate(env.possible_agents)]
    display = display_of(args, out)
    if args.policy == "keys":  # babyrobot_marl.play: you drive robot_0, the others run on by themselves
        from ..play.terminal import race_keys

        race_keys(env, policies, 0, seed, results, display.delay, display.colour, out, human_flag=False)
    else:
        frames = race_frames(env, policies, results, seed, display.colour)
        if display.clear:
            from ..play.watch import watch_race

            watch_race(env, policies, seed, frames, names, display.delay, display.colour, out)
        else:  # a file or pipe: the frames, then the key once
            from ..play.watch import legend

            animate(frames, display, out)
            out.write("\n".join(legend(names, level=env.level, goals="own", lifelong=args.lifelong)) + "\n")
    if args.robots > 1:
        out.write(f"\n{results_table(results, 'own', args.lifelong)}\n")
    out.write(f"\nlevel {level_label(level, args.level)}, policy {args.policy}, seed {seed}: {_outcome(env, results[0])}\n")
    return 0


def _outcome(env: RaceEnv, you: RobotResult) -> str:
    """Robot_0's steps, return and what it reached: its target, or under lifelong the targets and throughput."""
    head = f"{you.steps} steps, return {you.ret!r}"
    if env.lifelong:
        return (f"{head}, reached {you.reached} target(s) in {env.elapsed_steps} steps "
                f"(throughput {you.reached / max(env.elapsed_steps, 1):.3f} per step)")
    if you.reached:
        return f"{head}, reached its target {you.target}"
    return f"{head}, did not reach its target {you.target} (truncated after {env.max_cycles} steps)"
