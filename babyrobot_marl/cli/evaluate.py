"""``babyrobot-marl evaluate POLICY``: a saved policy beside the shortest-path and random robots on the same
seeded episodes (``experiments.evaluate``): a table, optionally a plot, and one JSON object as the last line."""

from __future__ import annotations

import argparse
from typing import Any, TextIO

from ..core.goals import GOAL_MODES
from ..core.rules import COLLISION_MODES
from .checks import check_race_flags, int_in, non_negative_int, output_path, policy_spec, positive_int
from .common import add_level_arg

MAX_EPISODES = 100_000  # episodes of one run, each kept for the metrics


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "evaluate",
        help="a saved policy beside the shortest-path and random robots: success rate, sum of costs, makespan",
        description="Run a policy's crowd, the shortest-path robots and random robots on the same seeded episodes "
        "(same levels, from mazes never trained on, same random starts) and print success_rate, all_reached_rate, "
        "sum_of_costs and makespan with 95% intervals; the last line is one JSON object "
        '{"policy": M, "shortest": M, "random": M}.',
    )
    p.add_argument("policy", type=policy_spec, metavar="POLICY",
                   help="the path of a policy saved by 'train --save' (or shortest, random: a scripted crowd)")
    add_level_arg(p, default="maze:8..16")
    p.add_argument("--robots", type=positive_int, default=4, metavar="N", help="robots in each episode (default: 4)")
    p.add_argument("--episodes", type=int_in(1, MAX_EPISODES, " (episodes run one after another)"), default=200, metavar="E",
                   help="seeded episodes per crowd (default: 200)")
    p.add_argument("--seed", type=non_negative_int, default=0, metavar="S", help="episode i resets with S + i (default: 0)")
    p.add_argument("--collisions", choices=COLLISION_MODES, default="block", help="collision rule (default: block)")
    p.add_argument("--goals", choices=GOAL_MODES, default="exit",
                   help="exit: the robots race to the exits (default); own: each robot has its own target cell, drawn "
                   "at each episode's start (the exits are floor)")
    p.add_argument("--lifelong", action="store_true",
                   help="with --goals own: a robot on its target gets a new one and keeps going; adds throughput "
                   "(targets reached per step)")
    p.add_argument("--plot", type=output_path, default=None, metavar="FILE.png",
                   help="also draw the metrics with their intervals to this image (matplotlib: the plot extra)")
    p.add_argument("--greedy", action="store_true",
                   help="a saved policy takes its most likely action (default: it samples its actions, seeded by --seed: "
                   "a memoryless policy that always takes the same action where its views look alike can loop)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace, out: TextIO) -> int:
    from ..experiments.evaluate import evaluate

    if args.plot:  # before the episodes: a missing matplotlib is known now
        _matplotlib()
    if args.lifelong and args.goals != "own":
        raise ValueError("--lifelong: new targets replace reached ones, so it needs --goals own")
    policy, form = _policy(args.policy, args.greedy, args.seed)
    check_race_flags(args.level, args.robots, args.collisions)
    ev = evaluate(policy, level=args.level, n_robots=args.robots, episodes=args.episodes, seed=args.seed,
                  collisions=args.collisions, policy_env=form, goals=args.goals, lifelong=args.lifelong)
    out.write(ev.table() + "\n")
    if args.plot:
        axes = ev.plot()
        axes[0].figure.savefig(args.plot, dpi=100)
        out.write(f"plot: {args.plot}\n")
    out.write(ev.json() + "\n")
    return 0


def _policy(spec: str, greedy: bool, seed: int) -> tuple[Any, dict[str, Any]]:
    """The policy of ``POLICY`` and the observation form its env needs (a saved file records it)."""
    from .. import policies

    if spec in policies.POLICY_NAMES:  # a scripted crowd: it reads [x, y] of any form
        return _Scripted(spec), {}
    from ..training.policy import load_checkpoint, load_policy

    form = dict(load_checkpoint(spec)["observation"])  # observe, obs_encoding (and view_radius, hint once recorded)
    policy = load_policy(spec, deterministic=greedy, seed=seed)
    policy.name = spec
    return policy, {k: v for k, v in form.items() if k in _FORM and v is not None}


_FORM = ("observe", "view_radius", "k", "obs_encoding", "hint")  # what a saved policy's observation form sets on its env


class _Scripted:
    """A scripted policy's crowd on each episode's level: bound to the env at every episode (``for_env``)."""

    def __init__(self, name: str):
        self.name = name

    def for_env(self, env: Any) -> Any:
        from .. import policies

        if self.name == "shortest" and env.goals_mode == "own":  # each robot to its own target
            from ..envs.race_goals import OwnGoalShortest

            return OwnGoalShortest(env.table)
        return policies.make(self.name, env.table, seed=env.np_random.integers(2**63))

    def __call__(self, obs: Any) -> int:  # never called unbound
        raise RuntimeError("bind with for_env(env) first")


def _matplotlib() -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")  # a file, no window
    except ImportError:
        raise ValueError("--plot: needs matplotlib: pip install 'babyrobot_marl[plot]'") from None
