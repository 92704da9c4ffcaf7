"""Generalisation: one PPO policy shared by all robots, trained with local views on random 8x8 mazes,
judged on mazes it never saw, beside the shortest-path robot and the random robot.

    python benchmarks/bench_generalise.py              # a few minutes on a shared 2-core machine
    python benchmarks/bench_generalise.py --steps 20000 --races 20   # a smoke run

Training: ``race_v0.parallel_env(level=maze_family(8, 8, seeds=range(500)), n_robots=4,
start="random", observe="local", view_radius=2)``, a new maze drawn at every reset from the env's
generator, SuperSuit + Stable-Baselines3 PPO with one policy for every robot
(``babyrobot_marl.training.race.train_race``; needs the ``train`` extra). Evaluation: ``--races``
seeded races (``babyrobot_marl.experiments.run_races``) on the training mazes and on unseen ones
(maze seeds 100,000 and up), four robots of one policy each time: the success rate is the share
of robots reaching the exit within ``max_cycles`` (256 steps), with its 95% interval. The PPO
policy is judged twice: taking its most likely action, and sampling its action (seeded).

No target: the figure is what a memoryless policy that sees a 5x5 window and its own position
achieves on unseen mazes; the shortest-path robot knows the whole maze.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from babyrobot_marl.experiments import run_races, wilson
from babyrobot_marl.levels.sources import maze_family

TRAIN_SEEDS = range(500)
UNSEEN_SEEDS = range(100_000, 100_500)
ENV = {"start": "random", "observe": "local", "view_radius": 2, "collisions": "block"}
ROBOTS = 4


def success(stats) -> tuple[float, float, float]:
    """Share of robots (all races, all robots) that finished, with its Wilson interval."""
    done = sum(1 for r in stats.records for rank in r.ranks if rank)
    total = len(stats.records) * len(stats.records[0].ranks)
    low, high = wilson(done, total)
    return done / total, low, high


def ppo_success(model, seeds: range, n_races: int, seed: int, deterministic: bool) -> tuple[float, float, float]:
    """``success`` for the PPO policy, its robots' actions predicted together each step (one call
    instead of one per robot): the same races as ``run_races`` (race ``i`` reset with ``seed + i``)."""
    from babyrobot_marl import race_v0

    env = race_v0.parallel_env(level=maze_family(8, 8, seeds), n_robots=ROBOTS, **ENV)
    model.set_random_seed(seed)  # the sampled actions (deterministic=False) repeat too
    done = 0
    for i in range(n_races):
        obs, _ = env.reset(seed=seed + i)
        while env.agents:
            agents = env.agents
            actions, _ = model.predict(np.stack([obs[a] for a in agents]), deterministic=deterministic)
            obs, *_ = env.step(dict(zip(agents, map(int, actions))))
        done += sum(1 for r in env.ranks if r)
    low, high = wilson(done, n_races * ROBOTS)
    return done / (n_races * ROBOTS), low, high


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=300_000, help="PPO timesteps (agent-steps)")
    parser.add_argument("--races", type=int, default=100, help="evaluation races per row")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    from babyrobot_marl.training.race import train_race

    t0 = time.perf_counter()
    model = train_race(
        level=maze_family(8, 8, TRAIN_SEEDS), n_robots=ROBOTS, steps=args.steps, seed=args.seed, n_envs=8, race_kwargs=ENV
    )
    seconds = time.perf_counter() - t0

    print(f"trained {args.steps:,} timesteps in {seconds:.0f} s on 8x8 mazes {TRAIN_SEEDS.start}..{TRAIN_SEEDS.stop - 1}")
    print(f"success rate: robots reaching the exit within 256 steps, {args.races} races of {ROBOTS} robots, 95% interval")
    print(f"{'policy':24s} {'training mazes':>24s} {'unseen mazes':>24s}")
    for name in ("ppo, most likely action", "ppo, sampled action", "shortest", "random"):
        cells = []
        for seeds in (TRAIN_SEEDS, UNSEEN_SEEDS):
            if name == "shortest" or name == "random":
                stats = run_races(maze_family(8, 8, seeds), [name] * ROBOTS, n_races=args.races, seed=args.seed + 1, **ENV)
                rate, low, high = success(stats)
            else:
                rate, low, high = ppo_success(model, seeds, args.races, args.seed + 1, deterministic="likely" in name)
            cells.append(f"{rate:.2f} [{low:.2f}, {high:.2f}]")
        print(f"{name:24s} {cells[0]:>24s} {cells[1]:>24s}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
