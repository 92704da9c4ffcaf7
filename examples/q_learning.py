"""Tabular Q-learning and SARSA on Baby Robot, checked against value iteration.

    python examples/q_learning.py                     # default, walls and puddles
    python examples/q_learning.py --level mixed-8x8 --episodes 40000

For each level: learn, then print how many cells' greedy action is one of value iteration's
best actions, the largest error of the learnt values, and the learnt policy as arrows.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.planning import model, policy_text, value_iteration
from babyrobot_marl.planning.dp import Solution
from babyrobot_marl.training import q_learning, sarsa

EPISODES = {"default": 500, "walls": 3000, "puddles": 15000}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", action="append", help="level(s) to learn (default: default, walls, puddles)")
    parser.add_argument("--episodes", type=int, default=None, help="episodes per run (default: per level)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    for level in args.level or list(EPISODES):
        env = BabyRobotEnv(level=level)
        optimal = value_iteration(model(env))
        episodes = args.episodes or EPISODES.get(level, 20000)
        print(f"== {level}: optimal return from the start {optimal.values[env.table.cell_id(env.level.starts[0])]:g}")
        for name, learn, kwargs in (("Q-learning", q_learning, {}), ("SARSA", sarsa, {"epsilon": 0.5, "alpha_power": 0.6})):
            t0 = time.perf_counter()
            res = learn(env, episodes, seed=args.seed, **kwargs)
            seconds = time.perf_counter() - t0
            best = optimal.best_actions.reshape(-1, 5)[np.arange(env.table.n_cells), res.policy][optimal.active]
            err = np.abs(res.q.max(axis=1) - optimal.values)[optimal.active].max()
            print(f"{name:10s} {episodes} episodes, {res.steps} steps, {seconds:.1f} s: "
                  f"optimal action in {best.sum()}/{best.size} cells, max value error {err:.3f}")
            if name == "Q-learning":
                learnt = Solution(res.q.max(axis=1), res.q, res.policy, optimal.width, optimal.height,
                                  optimal.is_exit, optimal.blocked, 1.0, episodes, 1e-6)
                print(policy_text(learnt))


if __name__ == "__main__":
    main()
