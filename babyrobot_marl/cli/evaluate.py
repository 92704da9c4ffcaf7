"""``babyrobot-marl evaluate POLICY``: a saved policy beside the shortest-path and random robots on the same
seeded episodes (``experiments.evaluate``): a table, optionally a plot, and one JSON object as the last line."""

from __future__ import annotations

import argparse
from typing import Any, TextIO

from ..core.rules import COLLISION_MODES
from ..policies import POLICY_NAMES
from ..training.checks import CELL_NAMES, FINISHED_RULES
from .checks import (
    SEED_HELP,
    check_goal_flags,
    check_policy_goals,
    check_race_flags,
    crowd_policy,
    int_in,
    output_path,
    positive_int,
    seed_int,
    trained_collisions,
    trained_finished,
    trained_goals,
)
from .common import add_goal_args, add_level_arg

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
    p.add_argument("policy", type=crowd_policy, metavar="POLICY",
                   help="the path of a policy saved by 'train --save' (or shortest, random: a scripted crowd)")
    add_level_arg(p, default="maze:8..16")
    p.add_argument("--robots", type=positive_int, default=4, metavar="N", help="robots in each episode (default: 4)")
    p.add_argument("--episodes", type=int_in(1, MAX_EPISODES, " (episodes run one after another)"), default=200, metavar="N",
                   help="seeded episodes per crowd (default: 200)")
    p.add_argument("--seed", type=seed_int, default=0, metavar="N",
                   help=f"episode i resets with seed N + i, {SEED_HELP} (default: 0)")
    p.add_argument("--collisions", choices=COLLISION_MODES, default=None,
                   help="collision rule; soft: POGEMA's (default: the rule a saved policy was trained under, else block)")
    add_goal_args(p, policy_default=True)
    p.add_argument("--finished", choices=FINISHED_RULES, default=None,
                   help="with --goals own: remove: a robot leaves the board at its target; stay: it stays there, "
                   "racing on and blocking, and counts if it stands on its target when the episode ends, which ends early "
                   "only when every robot does (POGEMA's on_target='nothing', the rule of its published maze runs); default: the "
                   "rule a saved policy was trained under, else remove")
    p.add_argument("--plot", type=output_path, default=None, metavar="PATH",
                   help="also draw the metrics with their intervals to this PNG image (matplotlib: the plot extra)")
    p.add_argument("--greedy", action="store_true",
                   help="a saved policy takes its most likely action (default: it samples its actions, seeded by --seed: "
                   "a memoryless policy that always takes the same action where its views look alike can loop)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace, out: TextIO) -> int:
    from ..experiments.evaluate import evaluate

    given = args.goals is not None
    if not given:  # a saved policy is evaluated on the task it learnt (its file read once for it)
        args.goals = trained_goals(args.policy) or "exit"
    check_goal_flags(args.goals, args.lifelong)
    if args.collisions is None:  # a saved policy is evaluated under the collision rule it learnt
        args.collisions = trained_collisions(args.policy)
    if args.finished is None:  # a saved policy of own goals is evaluated under the rule it learnt at its target
        args.finished = trained_finished(args.policy) if args.goals == "own" and not args.lifelong else "remove"
    if given:
        check_policy_goals([args.policy], args.goals, "POLICY")  # what a saved policy was trained for
    check_race_flags(args.level, args.robots, args.collisions, args.goals, args.lifelong, args.finished)
    if args.plot:  # before the episodes: a missing matplotlib is known now
        _matplotlib()
    policy, form = _policy(args.policy, args.greedy, args.seed)
    ev = evaluate(policy, level=args.level, n_robots=args.robots, episodes=args.episodes, seed=args.seed,
                  collisions=args.collisions, policy_env=form, goals=args.goals, lifelong=args.lifelong,
                  finished=args.finished)
    out.write(ev.table() + "\n")
    if args.policy not in POLICY_NAMES:  # a saved policy: what it was trained with
        out.write(_trained_with(args.policy) + "\n")
    if args.plot:
        axes = ev.plot()
        axes[0].figure.savefig(args.plot, dpi=100)
        out.write(f"plot: {args.plot}\n")
    out.write(ev.json() + "\n")
    return 0


def _policy(spec: str, greedy: bool, seed: int) -> tuple[Any, dict[str, Any]]:
    """The policy of ``POLICY`` and the observation form its env needs (a saved file records it)."""
    from .. import policies

    if spec in policies.POLICY_NAMES:  # a baseline's crowd: played once, shown once
        return spec, {}
    from ..training.checks import GLOBAL_FORM
    from ..training.policy import load_checkpoint, load_policy

    # observe, obs_encoding (and view_radius, hint once recorded); files of format 1 and 2 read the global rows
    form = dict(load_checkpoint(spec).get("observation", GLOBAL_FORM))
    policy = load_policy(spec, deterministic=greedy, seed=seed)
    policy.name = spec
    return policy, {k: v for k, v in form.items() if k in _FORM and v is not None}


# the training settings a saved policy's line shows: the rollout, the knobs a crowd's result depends on
_SHOWN = ("n_envs", "n_steps", "batch_size", "ent_coef", "gamma", "near_radius", "blocked_cost")
_IMITATION_SHOWN = ("learning_rate", "batch_size", "n_epochs", "near_radius")  # a crowd that imitates a planner


def _trained_with(spec: str) -> str:
    """One line: what the saved policy at ``spec`` was trained on and with (its file's ``config``)."""
    from ..training.policy import load_checkpoint

    data = load_checkpoint(spec)
    config = data["config"]
    shown = _IMITATION_SHOWN if config.get("imitate") else _SHOWN
    settings = ", ".join(f"{k} {config[k]:g}" for k in shown if k in config)
    if config.get("imitate"):
        arch = ",".join(map(str, config["net_arch"]))
        settings = f"imitating {config['imitate'].upper()} (DAgger), net_arch {arch}, {settings}"
    remembers = [what for name, what in (("memory", "its last action"), ("trail", "its trail")) if config.get(name)]
    if config.get("recurrent"):
        remembers.append(f"{CELL_NAMES[config.get('cell', 'gru')]} of {config.get('hidden', 32)} units")
    if remembers:
        settings += "; each robot remembers " + " and ".join(remembers)
    if data.get("env", {}).get("finished") == "stay":
        settings += "; robots stayed on their targets (--finished stay)"
    return (f"{spec}: trained {data['timesteps']:,} timesteps on {data['level_name'] or 'its level'} with "
            f"{data['n_robots']} robot(s); {settings}")


_FORM = ("observe", "view_radius", "k", "obs_encoding", "hint")  # what a saved policy's observation form sets on its env


def _matplotlib() -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")  # a file, no window
    except ImportError:
        raise ValueError("--plot: needs matplotlib: pip install 'babyrobot_marl[plot]'") from None
