"""Tabular Q-learning on a Baby Robot level, checked against value iteration on the model.

    python examples/q_learning.py --level puddles --steps 100000 --seed 0

Learns from the simulator only (observations, rewards), then prints the learnt greedy
policy beside the optimal one and how much return it loses from each cell (0: optimal).
"""

from __future__ import annotations

import argparse

import numpy as np

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.cli import solution_text
from babyrobot_marl.planning import model, policy_evaluation, q_learning, sarsa, value_iteration


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--level", default="puddles")
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--algo", choices=["q_learning", "sarsa"], default="q_learning")
    args = p.parse_args(argv)

    learn = q_learning if args.algo == "q_learning" else sarsa
    q = learn(BabyRobotEnv(level=args.level), steps=args.steps, seed=args.seed)
    m = model(args.level)
    best = value_iteration(m, gamma=1.0)
    greedy = np.where(m.terminal, 0, q.argmax(axis=1))
    try:
        learnt = policy_evaluation(m, greedy, gamma=1.0, max_iterations=50_000)
    except RuntimeError:
        print("the learnt greedy policy never reaches the exit from some cell: learn for more steps")
        return
    print(f"{args.algo}, {args.steps} steps, level {args.level}\n\nlearnt policy, evaluated on the model:")
    print(solution_text(learnt))
    print("optimal (value iteration):")
    print(solution_text(best))
    loss = np.abs(learnt.values - best.values)[~m.terminal].max()
    print(f"largest loss of return from any cell: {loss:.4f}" + ("  (optimal)" if loss < 1e-9 else ""))


if __name__ == "__main__":
    main()
