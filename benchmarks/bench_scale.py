"""Races of many robots: cost per agent-step, build time and memory by observation mode; the
worst-case collision queue; the batch engine beside ``parallel_env`` from 4096 x 1 to 1 x 1000.

    python benchmarks/bench_scale.py            # about two minutes on a shared 2-core machine
    python benchmarks/bench_scale.py --quick    # CI smoke run: fewer steps, one round, no targets judged
    python benchmarks/bench_scale.py --part batch   # part 3 alone (about 40 seconds)

1. ``race_v0.parallel_env`` on ``maze-64x64``, random starts, random actions, robots 4, 10, 16,
   64, 256, 1024, each ``observe`` mode: microseconds per agent-step (median over rounds), the
   build time of the env (the level compiled once before: envs share compiled levels), the memory
   the build and a reset allocate (``tracemalloc`` peak) and the observation bytes of one step.
   Target: with "local" and "nearest", the time per agent-step at 1024 robots at most 1.5x that
   at 10 robots.
2. The collision queue: 3,000 robots in a corridor all pressing west, the robot at the wall
   the highest-numbered (then the lowest-numbered): one ``step`` (``observe="local"``), median
   of 5. Target: under 50 ms.
3. The batch engine (``BatchRace.step`` + ``observations``, and the Gymnasium ``RaceVectorEnv``)
   beside ``parallel_env`` with the same robots, per agent-step, for (envs x robots) from
   (4096 x 1) to (1 x 1000), "global" and "local" observations. Target: the batch engine at
   least as fast as ``parallel_env`` (ratio >= 1.0) for every shape; the vector env's ratio is
   printed beside it. The rounds interleave the three, so a busy machine slows all of them alike.

The script exits with status 1 when a target is missed (``--quick`` prints the figures only:
a few thousand steps on a busy CI machine are too few to judge a ratio).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import tracemalloc

import numpy as np
from bench_race import agent_step_time  # the same timing loop as the race benchmark

from babyrobot_marl import race_v0
from babyrobot_marl.envs.vector import RaceVectorEnv

LEVEL = "maze-64x64"
MODES = ("global", "local", "nearest")
ROBOTS = (4, 10, 16, 64, 256, 1024)
SHAPES = ((4096, 1), (1024, 4), (256, 16), (64, 64), (16, 256), (4, 1000), (1, 1000))
QUEUE = 3000


def parallel_time(env, n: int, agent_steps: int, rng: np.random.Generator) -> float:
    """Seconds per agent-step of ``parallel_env`` under random actions (a reset when the race ends)."""
    steps = max(30, agent_steps // n)
    return agent_step_time(env, rng.integers(0, 5, (steps, n)).tolist())


def part_modes(rounds: int, agent_steps: int, judge: bool = True) -> bool:
    print(f"1. parallel_env on {LEVEL}, random starts and actions (median of {rounds})")
    print(f"{'observe':8s} {'robots':>6s} {'us/agent-step':>14s} {'build s':>8s} {'build MB':>9s} {'obs KB/step':>12s}")
    race_v0.parallel_env(level=LEVEL, n_robots=1)  # compiles the level once: later envs share it
    per_mode: dict[str, dict[int, float]] = {}
    for mode in MODES:
        per_mode[mode] = {}
        for n in ROBOTS:
            tracemalloc.start()
            t0 = time.perf_counter()
            env = race_v0.parallel_env(level=LEVEL, n_robots=n, start="random", max_cycles=10**6, observe=mode)
            build = time.perf_counter() - t0
            obs, _ = env.reset(seed=0)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            obs_bytes = sum(o.nbytes for o in obs.values())
            rng = np.random.default_rng(0)
            t = statistics.median(parallel_time(env, n, agent_steps, rng) for _ in range(rounds))
            per_mode[mode][n] = t
            print(f"{mode:8s} {n:6d} {t * 1e6:14.2f} {build:8.3f} {peak / 2**20:9.1f} {obs_bytes / 1024:12.1f}", flush=True)
    ok = True
    for mode in ("local", "nearest"):
        ratio = per_mode[mode][1024] / per_mode[mode][10]
        met = ratio <= 1.5
        ok &= met
        verdict = ("met" if met else "MISSED") if judge else "(not judged)"
        print(f"target: {mode}, time per agent-step at 1024 robots <= 1.5x at 10: {ratio:.2f}x {verdict}")
    return ok


def corridor(n: int) -> str:
    return "\n".join(["+" + "-+" * (n + 1), "|" + " " * (2 * n) + "E|", "+" + "-+" * (n + 1)])


def part_queue(judge: bool = True) -> bool:
    print(f"\n2. a queue of {QUEUE:,} robots in a corridor pressing west against the wall, one step (median of 5)")
    text = corridor(QUEUE)
    ok = True
    for name, xs in (("highest", range(QUEUE - 1, -1, -1)), ("lowest", range(QUEUE))):
        env = race_v0.parallel_env(level=text, n_robots=QUEUE, start="random", observe="local", view_radius=1, max_cycles=100)
        env.reset(seed=0)
        env.set_cells([(x, 0) for x in xs])
        west = dict.fromkeys(env.agents, 4)
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            _, _, _, _, infos = env.step(west)
            times.append(time.perf_counter() - t0)
        assert sum(i["blocked"] for i in infos.values()) == QUEUE - 1  # everyone behind the head stays
        t = statistics.median(times)
        met = t < 0.050
        ok &= met
        verdict = ("met" if met else "MISSED") if judge else "not judged"
        print(f"head at the wall is the {name}-numbered robot: {t * 1e3:7.1f} ms per step  (target < 50 ms: {verdict})")
    return ok


def part_batch(
    rounds: int,
    agent_steps: int,
    judge: bool = True,
    shapes: tuple[tuple[int, int], ...] = SHAPES,
    modes: tuple[str, ...] = ("global", "local"),
) -> bool:
    print(f"\n3. batch engine and RaceVectorEnv beside parallel_env, {LEVEL}, us per agent-step (median of {rounds})")
    print(
        f"{'observe':8s} {'envs x robots':>14s} {'batch':>8s} {'vector env':>11s} {'parallel':>9s} "
        f"{'batch vs parallel':>18s} {'vector vs parallel':>19s}"
    )
    ok = True
    lowest = float("inf")
    for mode in modes:
        for n_envs, n in shapes:
            kw = dict(level=LEVEL, n_robots=n, start="random", max_cycles=10**6, observe=mode)
            env = race_v0.parallel_env(**kw)
            rng = np.random.default_rng(0)
            steps = max(30, agent_steps // (n_envs * n))
            actions = rng.integers(0, 5, (steps, n_envs, n))
            batch = env.batch(n_envs)
            vec = RaceVectorEnv(n_envs, **kw)
            tb, tv, tp = [], [], []
            for _ in range(rounds):
                batch.seed(range(n_envs))
                batch.reset_envs(range(n_envs))
                t0 = time.perf_counter()
                for a in actions:
                    batch.step(a)
                    batch.observations()
                tb.append((time.perf_counter() - t0) / (steps * n_envs * n))
                vec.reset(seed=0)
                flat = actions.reshape(steps, -1)
                t0 = time.perf_counter()
                for a in flat:
                    vec.step(a)
                tv.append((time.perf_counter() - t0) / (steps * n_envs * n))
                tp.append(parallel_time(env, n, agent_steps, rng))
            b, v, p = (statistics.median(x) for x in (tb, tv, tp))
            met = p / b >= 1.0
            ok &= met
            lowest = min(lowest, p / b)
            shape = f"{n_envs} x {n}"
            figures = f"{b * 1e6:8.3f} {v * 1e6:11.3f} {p * 1e6:9.3f} {p / b:17.2f}x {p / v:18.2f}x"
            print(f"{mode:8s} {shape:>14s} {figures}{'' if met or not judge else '  MISSED'}", flush=True)
    verdict = ("met" if ok else "MISSED") if judge else "(not judged)"
    target = "batch engine at least as fast as parallel_env per agent-step for every shape"
    print(f"target: {target} (lowest {lowest:.2f}x): {verdict}")
    return ok


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps, one round (CI)")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--agent-steps", type=int, default=20_000, help="agent-steps per measurement")
    parser.add_argument("--part", choices=("all", "modes", "queue", "batch"), default="all", help="run one part only")
    args = parser.parse_args(argv)
    rounds, agent_steps = (1, 3_000) if args.quick else (args.rounds, args.agent_steps)
    judge = not args.quick  # a few thousand steps on a busy machine are too few to judge a ratio
    ok = True
    if args.part in ("all", "modes"):
        ok &= part_modes(rounds, agent_steps, judge)
    if args.part in ("all", "queue"):
        ok &= part_queue(judge)
    if args.part in ("all", "batch"):
        ok &= part_batch(rounds, agent_steps, judge)
    return 0 if ok or not judge else 1


if __name__ == "__main__":
    sys.exit(main())
