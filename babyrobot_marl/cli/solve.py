"""``babyrobot-marl solve``: value or policy iteration on one level, its value grid and policy arrows."""

from __future__ import annotations

import argparse
from typing import TextIO

from .checks import SEED_HELP, int_at_least, positive_float, probability, seed_int
from .common import add_level_arg
from .levels import level_of


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "solve",
        help="solve a level exactly (value or policy iteration) and print values and policy",
        description="Dynamic programming on the exact model of one robot: prints the value grid and the greedy policy "
        "as arrows (o: STAY, E: exit, #: blocked, .: no exit reachable).",
    )
    add_level_arg(p, family="one square maze of side A..B, drawn from --seed")
    p.add_argument("--method", choices=("value", "policy"), default="value", help="value or policy iteration (default: value)")
    p.add_argument("--gamma", type=probability, default=1.0, metavar="X", help="discount in (0, 1] (default: 1)")
    p.add_argument(
        "--theta", type=positive_float, default=1e-9, metavar="X", help="stop when no value moves by X (default: 1e-9)"
    )
    p.add_argument("--decimals", type=int_at_least(0), default=1, metavar="N", help="decimals of the values (default: 1)")
    p.add_argument("--seed", type=seed_int, default=0, metavar="N",
                   help=f"with --level maze:A..B: the seed that draws the maze, as an env reset with it does, {SEED_HELP} "
                   "(default: 0)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace, out: TextIO) -> int:
    from ..planning import model, policy_iteration, policy_text, value_iteration, value_text

    level = level_of(args.level, args.seed)  # maze:A..B: the maze the seed draws
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
