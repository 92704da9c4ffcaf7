"""Steps per second of BabyRobot-v0 against Gymnasium's FrozenLake-v1, measured in the same run.

    python benchmarks/bench_single.py            # 50,000 steps per env per round, 7 rounds
    python benchmarks/bench_single.py --quick    # a few seconds
    python benchmarks/bench_single.py --steps 200000 --rounds 9

Every env runs the same loop: pre-drawn random actions (Python ints), ``step``, and ``reset``
when an episode ends (terminated or truncated); resets count in the time, as in training.
The envs take turns within each round (A B C ... A B C ...), so a slow spell of a shared
machine hits them all alike; each env's figure is the median over rounds of the time per step.
A first warm-up round is not counted.

Rows: ``gymnasium.make`` (with the default wrappers every user gets: order enforcing, the
passive env checker, FrozenLake's TimeLimit) and the raw env (``.unwrapped``). The ratio is
FrozenLake's time per step over the row's, like for like (made vs made, raw vs raw): above
1.0, BabyRobot is the faster. This is a report, not a test: nothing here asserts on speed.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from time import perf_counter

import gymnasium
import numpy as np

import babyrobot_marl  # noqa: F401  (registers babyrobot_marl/BabyRobot-v0)


@dataclass
class Case:
    name: str
    make: Callable[[], gymnasium.Env]
    baseline: str | None  # the FrozenLake row this one is compared with
    seconds_per_step: list[float] = field(default_factory=list)
    resets: int = 0


def cases() -> list[Case]:
    def made(env_id: str, **kwargs) -> Callable[[], gymnasium.Env]:
        return lambda: gymnasium.make(env_id, **kwargs)

    def raw(env_id: str, **kwargs) -> Callable[[], gymnasium.Env]:
        return lambda: gymnasium.make(env_id, **kwargs).unwrapped

    br = "babyrobot_marl/BabyRobot-v0"
    return [
        Case("FrozenLake-v1", made("FrozenLake-v1"), None),
        Case("BabyRobot maze-8x8", made(br, level="maze-8x8"), "FrozenLake-v1"),
        Case("BabyRobot default 3x3", made(br, level="default"), "FrozenLake-v1"),
        Case("FrozenLake-v1 (raw)", raw("FrozenLake-v1"), None),
        Case("BabyRobot maze-8x8 (raw)", raw(br, level="maze-8x8"), "FrozenLake-v1 (raw)"),
    ]


def run(env: gymnasium.Env, actions: list[int], seed: int) -> tuple[float, int]:
    """Seconds for ``len(actions)`` steps (resets included) and the number of resets."""
    env.reset(seed=seed)
    step, reset = env.step, env.reset
    resets = 0
    t0 = perf_counter()
    for a in actions:
        _, _, terminated, truncated, _ = step(a)
        if terminated or truncated:
            reset()
            resets += 1
    return perf_counter() - t0, resets


def measure(steps: int, rounds: int, seed: int = 0) -> list[Case]:
    todo = cases()
    envs = [c.make() for c in todo]
    rng = np.random.default_rng(seed)
    actions = [rng.integers(env.action_space.n, size=steps).tolist() for env in envs]  # FrozenLake 4, BabyRobot 5
    for r in range(rounds + 1):
        for case, env, acts in zip(todo, envs, actions, strict=True):
            seconds, resets = run(env, acts, seed + r)
            if r > 0:  # round 0 warms caches and lazy imports
                case.seconds_per_step.append(seconds / steps)
                case.resets = resets
    for env in envs:
        env.close()
    return todo


def report(results: list[Case], steps: int, rounds: int) -> str:
    median = {c.name: statistics.median(c.seconds_per_step) for c in results}
    cols = ("env", "us/step", "steps/s", "resets/run", "FrozenLake/this")
    rows = [cols]
    for c in results:
        t = median[c.name]
        ratio = f"{median[c.baseline] / t:.2f}" if c.baseline else "-"
        rows.append((c.name, f"{t * 1e6:.2f}", f"{1 / t:,.0f}", str(c.resets), ratio))
    widths = [max(len(r[i]) for r in rows) for i in range(len(cols))]
    lines = [
        f"{steps:,} random steps per env per round, {rounds} rounds, median; "
        f"Python {platform.python_version()}, gymnasium {gymnasium.__version__}, numpy {np.__version__}, "
        f"{os.cpu_count()} CPUs, {platform.machine()}",
        "",
    ]
    for i, r in enumerate(rows):
        lines.append("  ".join(r[0].ljust(widths[0]) if j == 0 else r[j].rjust(widths[j]) for j in range(len(cols))))
        if i == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="5,000 steps x 3 rounds: a few seconds")
    p.add_argument("--steps", type=int, default=None, help="steps per env per round (default 50,000)")
    p.add_argument("--rounds", type=int, default=None, help="timed rounds (default 7)")
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    steps = args.steps if args.steps is not None else (5_000 if args.quick else 50_000)
    rounds = args.rounds if args.rounds is not None else (3 if args.quick else 7)
    if steps < 1 or rounds < 1:
        p.error("--steps and --rounds must be >= 1")
    print(report(measure(steps, rounds, args.seed), steps, rounds))
    return 0


if __name__ == "__main__":
    sys.exit(main())
