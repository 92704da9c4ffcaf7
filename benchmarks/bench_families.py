"""Crowds that learn: the fast trainer on a level family, judged on unseen mazes beside the shortest-path and random robots.

    python benchmarks/bench_families.py --level maze:8..16 --robots 4 --hint --seconds 120
    python benchmarks/bench_families.py --level maze:8..16 --robots 4 --memory --seconds 600     # no hint, memory
    python benchmarks/bench_families.py --level maze:16..16 --robots 32 --hint --collisions bounce --seconds 600
    python benchmarks/bench_families.py --quick     # a smoke run: maze:8..8, 2 robots, hint, 3 s, 10 races

It trains as ``babyrobot-marl train --level L --robots N --observe local ...`` does with the same flags (the
same ``PPOConfig``: 256 envs, and for a crowd, several robots under ``block`` or ``bounce``, the crowd defaults
``near_radius`` 2 and ``blocked_cost`` 0.5 unless given), and prints that command first; ``babyrobot-marl
evaluate`` judges a saved policy on seeded episodes of its own.

Training: ``train_ppo(level, n_robots, config=PPOConfig(view_radius=..., hint=..., ...))`` for ``--seconds`` of
wall-clock training time (rollouts and updates), mazes from ``TRAIN_MAZE_SEEDS`` (an atlas of 64 on the batch
engine, drawn anew every 16 rollouts). Evaluation: ``--episodes`` seeded races of
``race_v0.parallel_env(level=<the family on EVAL_MAZE_SEEDS>, observe="local", view_radius=..., hint=...,
start="random", collisions=...)`` (``experiments.run_races``: every robot one policy), the trained policy
taking its most likely action and sampling it, then the shortest-path and the random robots on the same
seeded races, and a floor for the crowd's makespan: shortest-path robots that wait (stay) at random
on 20% of steps (``--wait``; they read the goal hint, the shortest-path robot's action).
Figures: ``success_rate`` (robots that reached the exit, Wilson 95% interval),
``all_reached_rate`` (races every robot finished), ``makespan`` (mean race length, 95% interval; its median beside it: a
few jammed races weigh on the mean), the
machine's load (``uptime``) before and after training, and the timesteps trained. ``--min-success X``:
exit 1 when the greedy policy's success rate is below X.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

from babyrobot_marl.experiments import run_races, wilson
from babyrobot_marl.levels.sources import EVAL_MAZE_SEEDS, parse_level_family
from babyrobot_marl.training.crowd import crowd_defaults, said


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def figures(stats, max_steps: int) -> dict[str, tuple[float, float, float]]:
    """Success rate, all-reached rate (Wilson intervals) and makespan (normal interval, within 0..max_steps)."""
    recs = stats.records
    n_robots = len(recs[0].ranks)
    done = sum(1 for r in recs for rank in r.ranks if rank)
    all_done = sum(1 for r in recs if all(r.ranks))
    span = np.array([r.steps for r in recs], dtype=float)
    half = 1.96 * span.std(ddof=1) / math.sqrt(len(span)) if len(span) > 1 else 0.0
    return {
        "success_rate": (done / (len(recs) * n_robots), *wilson(done, len(recs) * n_robots)),
        "all_reached_rate": (all_done / len(recs), *wilson(all_done, len(recs))),
        "makespan": (float(span.mean()), max(0.0, span.mean() - half), min(float(max_steps), span.mean() + half)),
    }


class WaitingShortest:
    """The shortest-path robot that stays put on a ``wait`` share of its steps, drawn from its own generator:
    blind randomness that breaks a crowd's livelock. It reads the goal hint (the last 5 entries of a local
    observation, one per action): the lowest optimal action, as ``ShortestPathPolicy``'s tie-break."""

    def __init__(self, wait: float, seed: int) -> None:
        self.wait, self.rng = wait, np.random.default_rng(seed)
        self.name = f"shortest, waits {wait:.0%}"

    def __call__(self, obs: np.ndarray) -> int:
        hint = np.asarray(obs[-5:])
        if self.rng.random() < self.wait or not hint.any():
            return 0  # STAY
        return int(np.argmax(hint))


def cli_command(args: argparse.Namespace) -> str:
    """The ``babyrobot-marl train`` command that trains as this run does (flags left at the CLI's defaults omitted)."""
    flags = [f"--level {args.level}", f"--robots {args.robots}", f"--collisions {args.collisions}", "--observe local"]
    flags += ["--hint"] * args.hint + ["--memory"] * args.memory
    flags += [f"--view-radius {args.view_radius}"] * (args.view_radius != 2)
    for flag, value, default in (("--n-envs", args.n_envs, 256), ("--batch-size", args.batch_size, 16384),
                                 ("--ent-coef", args.ent_coef, 0.01), ("--gamma", args.gamma, 0.99),
                                 ("--near-radius", args.near_radius, None), ("--blocked-cost", args.blocked_cost, None)):
        if value is not None and value != default:
            flags.append(f"{flag} {value:g}")
    return f"babyrobot-marl train {' '.join(flags)} --seconds {args.seconds:g} --seed {args.seed}"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--level", default="maze:8..16")
    p.add_argument("--robots", type=int, default=4)
    p.add_argument("--hint", action="store_true")
    p.add_argument("--collisions", default="block")
    p.add_argument("--seconds", type=float, default=600.0, help="wall-clock training budget")
    p.add_argument("--episodes", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--n-envs", type=int, default=256)
    p.add_argument("--batch-size", type=int, default=16384)
    p.add_argument("--ent-coef", type=float, default=0.01)
    p.add_argument("--near-radius", type=int, default=None, help="default: 1, or the crowd default")
    p.add_argument("--gamma", type=float, default=0.99)
    p.add_argument("--blocked-cost", type=float, default=None, help="PPOConfig.blocked_cost: a robot's training reward "
                   "loses this on a step another robot stops its move (default: 0, or the crowd default)")
    p.add_argument("--view-radius", type=int, default=2)
    p.add_argument("--memory", action="store_true", help="PPOConfig.memory: the net also reads the robot's last action "
                   "(one bound policy per robot and race remembers it)")
    p.add_argument("--wait", type=float, default=0.2, help="the waiting shortest-path robots' share of steps spent "
                   "waiting (needs --hint; 0: no such row)")
    p.add_argument("--skip-baselines", action="store_true", help="no shortest-path and random rows (the same seeded "
                   "races give the same figures whatever was trained: minutes of evaluation on a livelocked crowd)")
    p.add_argument("--save", default=None)
    p.add_argument("--load", default=None, help="evaluate this saved policy instead of training")
    p.add_argument("--min-success", type=float, default=None)
    p.add_argument("--skip-greedy", action="store_true", help="judge the sampled policy only (a greedy crowd may "
                   "livelock to the step limit: minutes of evaluation)")
    p.add_argument("--quick", action="store_true", help="a smoke run: maze:8..8, 2 robots, hint, 3 s, 10 races")
    args = p.parse_args(argv)
    import torch

    torch.set_num_threads(1)  # a busy machine: torch's own threads wait on each other (5 ms per 1-row forward pass)
    if args.quick:
        args.level, args.robots, args.hint, args.seconds, args.episodes = "maze:8..8", 2, True, 3.0, 10
    from babyrobot_marl.training.policy import load_policy
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    env = {"start": "random", "observe": "local", "view_radius": args.view_radius, "hint": args.hint,
           "collisions": args.collisions}
    if args.load:
        policy = load_policy(args.load)
        print(f"policy {args.load}")
    else:
        chosen = {k: v for k, v in (("near_radius", args.near_radius), ("blocked_cost", args.blocked_cost)) if v is not None}
        crowd = crowd_defaults(args.robots, args.collisions, chosen)
        config = PPOConfig(n_envs=args.n_envs, batch_size=args.batch_size, hint=args.hint, ent_coef=args.ent_coef,
                           gamma=args.gamma, view_radius=args.view_radius, memory=args.memory, eval_every=0,
                           **chosen, **crowd)
        print(f"the same training: {cli_command(args)}" + (f" (crowd defaults {said(crowd)})" if crowd else ""))
        before = load()
        result = train_ppo(args.level, args.robots, 2**62, args.seed, config, max_seconds=args.seconds,
                           env_kwargs={"collisions": args.collisions})
        print(f"trained {result.timesteps:,} timesteps in {result.seconds:.0f} s wall-clock ({result.cpu_seconds:.0f} s CPU) "
              f"on {args.level}, {args.robots} robots, collisions {args.collisions}, hint {args.hint}, memory {args.memory}; "
              f"load average before {before}, after {load()}")
        if args.save:
            result.save(args.save)
        policy = result.policy()
    family = parse_level_family(args.level, EVAL_MAZE_SEEDS)
    from babyrobot_marl.core.level import Level
    from babyrobot_marl.envs.single import default_max_steps

    max_steps = default_max_steps(Level(*family.largest, exits=[(0, 0)]))
    print(f"{args.episodes} races on unseen mazes ({args.level}, EVAL_MAZE_SEEDS), {args.robots} robots each, "
          f"collisions {args.collisions}; success and all-reached: Wilson 95%; makespan: mean, 95% interval")
    print(f"{'robots':18s} {'success_rate':>22s} {'all_reached_rate':>22s} {'makespan':>24s} {'median':>7s}")
    greedy: float | None = None
    sampled = type(policy)(policy.net, policy.form, policy.n_robots, deterministic=False, seed=args.seed)
    rows = [("policy (greedy)", policy)] * (not args.skip_greedy) + [("policy (sampled)", sampled)]
    if args.hint and args.wait > 0:
        rows.append((f"shortest, waits {args.wait:.0%}", "wait"))
    rows += [("shortest", "shortest"), ("random", "random")] * (not args.skip_baselines)
    for name, who in rows:
        t0 = time.perf_counter()
        robots = ([WaitingShortest(args.wait, args.seed + 7 + k) for k in range(args.robots)] if who == "wait"
                  else [who] * args.robots)
        stats = run_races(family, robots, n_races=args.episodes, seed=args.seed + 1, **env)
        f = figures(stats, max_steps)
        if greedy is None:
            greedy = f["success_rate"][0]  # the first policy row
        cells = [f"{m:.3f} [{lo:.3f}, {hi:.3f}]" if k != "makespan" else f"{m:.1f} [{lo:.1f}, {hi:.1f}]"
                 for k, (m, lo, hi) in f.items()]
        median = float(np.median([r.steps for r in stats.records]))
        print(f"{name:18s} {cells[0]:>22s} {cells[1]:>22s} {cells[2]:>24s} {median:7.1f}   "
              f"({time.perf_counter() - t0:.0f} s)", flush=True)
    print(f"load average now {load()}")
    if args.min_success is not None and greedy < args.min_success:
        print(f"below the floor: greedy success rate {greedy:.3f} < {args.min_success}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
