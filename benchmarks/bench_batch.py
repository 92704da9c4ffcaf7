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
   FrozenLake-v1 envs, same random actions, rounds interleaved (who goes first alternates): on
   the maze (walls only) and on mixed-8x8 (puddles and glass walls, where steps draw random
   numbers). Each step returns its full infos (``cell``, ``outcome``, ``intended`` and their
   masks). Beside them, the same steps on the batch engine alone (``BatchRace.step``, its
   observations, ended envs restarted; no action checks, no infos, no Gymnasium API): the
   difference is what the infos and the API cost. Timed in CPU time of this process
   (``time.process_time``; other jobs on a busy machine stretch wall time, not CPU time); each
   round's ratio is measured in that round, the figure is the median of the rounds' ratios.

Target: ``make_vec`` on maze-8x8 at least ``VECTOR_TARGET`` times ``SyncVectorEnv``'s env-steps per
second; the script exits with status 1 below it (with ``--all``, also when the race benchmark
misses its targets).

All in one process on one core (numpy runs these ops single-threaded); medians over rounds.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import gymnasium
import numpy as np

import babyrobot_marl  # noqa: F401  (registers the envs)
from babyrobot_marl import race_v0
from babyrobot_marl.core.batch import BatchRace

LEVEL = "maze-8x8"
VECTOR_TARGET = 25.0  # x SyncVectorEnv of BabyRobot-v0, make_vec with 64 envs on maze-8x8 (aim: 30x)


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
    """Env-steps per second of CPU time of a Gymnasium vector env (its own auto-reset)."""
    env.reset(seed=0)
    n = env.num_envs
    actions = rng.integers(0, 4, (steps, n))  # 0..3: valid for both BabyRobot and FrozenLake
    t0 = time.process_time()
    for a in actions:
        env.step(a)
    return steps * n / (time.process_time() - t0)


def engine_alone_rate(batch: BatchRace, steps: int, rng: np.random.Generator) -> float:
    """Env-steps per second of CPU time of the batch engine under ``make_vec``: the step, the
    observations and the restart of ended envs, without action checks, infos or the Gymnasium API."""
    batch.seed(range(batch.n_envs))
    batch.reset_envs(range(batch.n_envs))
    actions = rng.integers(0, 4, (steps, batch.n_envs, 1))
    t0 = time.process_time()
    for a in actions:
        over = batch.step(a)[4]
        batch.observations()
        if np.count_nonzero(over):
            batch.reset_envs(np.flatnonzero(over))
    return steps * batch.n_envs / (time.process_time() - t0)


MAKE_VEC, SYNC = "BabyRobot-v0 make_vec (batch engine)", "BabyRobot-v0 SyncVectorEnv"
ENGINE = "  the same steps, engine alone (no infos)"


def vector_envs(n: int, level: str) -> dict[str, gymnasium.vector.VectorEnv]:
    envs: dict[str, gymnasium.vector.VectorEnv] = {}
    try:
        envs[MAKE_VEC] = gymnasium.make_vec(
            "babyrobot_marl/BabyRobot-v0", num_envs=n, vectorization_mode="vector_entry_point", level=level
        )
    except (gymnasium.error.Error, ValueError, TypeError) as err:  # no vector entry point registered
        print(f"(no batch-engine vector env: {err})")
    envs[SYNC] = gymnasium.vector.SyncVectorEnv(
        [lambda: gymnasium.make("babyrobot_marl/BabyRobot-v0", level=level)] * n
    )
    envs["FrozenLake-v1 SyncVectorEnv"] = gymnasium.vector.SyncVectorEnv([lambda: gymnasium.make("FrozenLake-v1")] * n)
    return envs


def main(argv: list[str] | None = None) -> int:
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
    steps = 600 if args.quick else 1000  # past the maze's 256-step limit: every env's resets count
    vector_rounds = max(rounds, 5)  # judged on a median of per-round ratios: a few rounds even in quick mode
    judged = None
    # the maze has walls only (every step a table look-up); mixed-8x8 adds puddles and glass walls (draws)
    for number, level in (("2", LEVEL), ("2b", "mixed-8x8")):
        envs = vector_envs(n, level)
        engine_batch = babyrobot_marl.BabyRobotEnv(level=level).batch(n)
        names = [*envs, ENGINE]
        rates: dict[str, list[float]] = {name: [] for name in names}
        for r in range(vector_rounds):
            for name in names if r % 2 == 0 else names[::-1]:
                if name == ENGINE:
                    rates[name].append(engine_alone_rate(engine_batch, steps, rng))
                else:
                    rates[name].append(vector_rate(envs[name], steps, rng))
        base = rates[SYNC]
        print(f"\n{number}. Gymnasium vector envs, {n} envs, {level}, random actions, CPU time ({vector_rounds} rounds)")
        print(f"{'vector env':44s} {'env-steps/s':>13s} {'us/step':>8s} {'vs Sync BabyRobot (rounds)':>28s}")
        for name in names:
            ratios = [x / y for x, y in zip(rates[name], base)]
            rate = statistics.median(rates[name])
            spread = f"{statistics.median(ratios):8.1f}x ({min(ratios):.1f}-{max(ratios):.1f})"
            print(f"{name:44s} {rate:13,.0f} {n / rate * 1e6:8.1f} {spread:>28s}")
        if MAKE_VEC in rates:
            full, alone = statistics.median(rates[MAKE_VEC]), statistics.median(rates[ENGINE])
            extra = n / full - n / alone
            print(f"infos, action checks and the Gymnasium API: {extra * 1e6:.1f} us of make_vec's "
                  f"{n / full * 1e6:.1f} us a step ({extra * full / n:.0%})")
            if level == LEVEL:
                judged = statistics.median(x / y for x, y in zip(rates[MAKE_VEC], base))
    status = 0
    if judged is None:
        print("no batch-engine vector env: no target")
    else:
        ok = judged >= VECTOR_TARGET
        verdict = "met" if ok else "MISSED"
        print(f"target: make_vec on {LEVEL} at least {VECTOR_TARGET:.0f}x SyncVectorEnv; {judged:.1f}x: {verdict}")
        status = 0 if ok or args.quick else 1  # --quick: a smoke run on a possibly busy machine, not judged

    if args.all:
        import bench_race
        import bench_single

        print("\n3. single env vs FrozenLake")
        bench_single.main(["--quick"] if args.quick else [])
        print("\n4. race vs multigrid")
        status = max(status, bench_race.main(["--quick"] if args.quick else []))
    return status


if __name__ == "__main__":
    sys.exit(main())
