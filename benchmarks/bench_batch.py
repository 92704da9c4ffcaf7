"""Batched stepping: the batch engine and the vector envs beside their peers, in one run.

    python benchmarks/bench_batch.py            # about a minute
    python benchmarks/bench_batch.py --quick    # CI: a few seconds
    python benchmarks/bench_batch.py --all      # also the single-env and race benchmarks

1. The batch engine (``core.batch.BatchRace``) on an 8x8 level with 4 robots, random starts
   and random actions, n_envs = 1, 64, 1024, 4096: agent-steps per second, observations
   built every step and finished races restarted (as a training loop needs), and the bytes
   of per-env state.
2. The Gymnasium vector env (``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")``)
   with 64 envs beside ``gymnasium.vector.SyncVectorEnv`` of 64 BabyRobot-v0 envs and of 64
   FrozenLake-v1 envs, same random actions, rounds interleaved: on the maze (walls only) and
   on mixed-8x8 (puddles and glass walls, where steps draw random numbers).

All in one process on one core (numpy runs these ops single-threaded); medians over rounds.
"""

from __future__ import annotations

import argparse
import statistics
import time

import gymnasium
import numpy as np

import babyrobot_marl  # noqa: F401  (registers the envs)
from babyrobot_marl import race_v0
from babyrobot_marl.core.batch import BatchRace

LEVEL = "maze-8x8"


def engine(n_envs: int, n_robots: int = 4) -> BatchRace:
    env = race_v0.parallel_env(level=LEVEL, n_robots=n_robots, start="random")
    batch = env.batch(n_envs)
    batch.seed(range(n_envs))
    batch.reset_envs(range(n_envs))
    return batch


def engine_rate(batch: BatchRace, steps: int, rng: np.random.Generator) -> float:
    """Agent-steps per second: step, observe, restart finished races."""
    actions = rng.integers(0, 5, (steps, batch.n_envs, batch.n_robots))
    t0 = time.perf_counter()
    for a in actions:
        _, _, _, _, over = batch.step(a)
        batch.observations()
        done = np.flatnonzero(over)
        if done.size:
            batch.reset_envs(done)
    return steps * batch.n_envs * batch.n_robots / (time.perf_counter() - t0)


def vector_rate(env: gymnasium.vector.VectorEnv, steps: int, rng: np.random.Generator) -> float:
    """Env-steps per second of a Gymnasium vector env (its own auto-reset)."""
    env.reset(seed=0)
    n = env.num_envs
    actions = rng.integers(0, 4, (steps, n))  # 0..3: valid for both BabyRobot and FrozenLake
    t0 = time.perf_counter()
    for a in actions:
        env.step(a)
    return steps * n / (time.perf_counter() - t0)


def vector_envs(n: int, level: str) -> dict[str, gymnasium.vector.VectorEnv]:
    envs: dict[str, gymnasium.vector.VectorEnv] = {}
    try:
        envs["BabyRobot-v0 make_vec (batch engine)"] = gymnasium.make_vec(
            "babyrobot_marl/BabyRobot-v0", num_envs=n, vectorization_mode="vector_entry_point", level=level
        )
    except (gymnasium.error.Error, ValueError, TypeError) as err:  # no vector entry point registered
        print(f"(no batch-engine vector env: {err})")
    envs["BabyRobot-v0 SyncVectorEnv"] = gymnasium.vector.SyncVectorEnv(
        [lambda: gymnasium.make("babyrobot_marl/BabyRobot-v0", level=level)] * n
    )
    envs["FrozenLake-v1 SyncVectorEnv"] = gymnasium.vector.SyncVectorEnv([lambda: gymnasium.make("FrozenLake-v1")] * n)
    return envs


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="a few seconds (CI)")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--all", action="store_true", help="also run bench_single.py and bench_race.py")
    args = p.parse_args(argv)
    rounds = 1 if args.quick else args.rounds
    rng = np.random.default_rng(0)

    print(f"1. batch engine, {LEVEL}, 4 robots, random actions (median of {rounds})")
    print(f"{'n_envs':>8s} {'agent-steps/s':>15s} {'us/batch step':>14s} {'state bytes/env':>16s}")
    for n_envs in (1, 64, 1024, 4096):
        batch = engine(n_envs)
        steps = max(20, (200 if args.quick else 4000) * 64 // max(n_envs, 64))
        rate = statistics.median(engine_rate(batch, steps, rng) for _ in range(rounds))
        per_step = n_envs * batch.n_robots / rate * 1e6
        print(f"{n_envs:8d} {rate:15,.0f} {per_step:14.1f} {batch.nbytes / n_envs:16.0f}")

    n = 64
    steps = 50 if args.quick else 1000
    # the maze has walls only (every step a table look-up); mixed-8x8 adds puddles and glass walls (draws)
    for number, level in (("2", LEVEL), ("2b", "mixed-8x8")):
        envs = vector_envs(n, level)
        times: dict[str, list[float]] = {name: [] for name in envs}
        for _ in range(rounds):
            for name, env in envs.items():
                times[name].append(vector_rate(env, steps, rng))
        print(f"\n{number}. Gymnasium vector envs, {n} envs, {level}, random actions (median of {rounds})")
        base = statistics.median(times["BabyRobot-v0 SyncVectorEnv"])
        print(f"{'vector env':40s} {'env-steps/s':>13s} {'vs Sync BabyRobot':>18s}")
        for name, rates in times.items():
            rate = statistics.median(rates)
            print(f"{name:40s} {rate:13,.0f} {rate / base:17.1f}x")

    if args.all:
        import bench_race
        import bench_single

        print("\n3. single env vs FrozenLake")
        bench_single.main(["--quick"] if args.quick else [])
        print("\n4. race vs multigrid")
        bench_race.main(["--quick"] if args.quick else [])


if __name__ == "__main__":
    main()
