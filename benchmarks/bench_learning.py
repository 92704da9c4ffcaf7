"""Learning benchmark (not a test): how fast PPO learns the 8x8 level, and how the trained racer
does against scripted opponents.

    python benchmarks/bench_learning.py              # full: single robot up to 100k steps, race 300k
    python benchmarks/bench_learning.py --quick      # a smoke run (CI): tiny budgets, figures meaningless

Prints, for PPO on BabyRobot-v0 (level maze-8x8 unless --level): the optimal return (value
iteration), the timesteps and wall time until the deterministic policy's mean return first reaches
95% of it (evaluated every --every steps), side by side with the budget (target: <= 100k steps);
then the race (level race-4 unless --race-level): the win rate and mean finishing steps of the
shared PPO policy against 'random' and against 'shortest' opponents (target: >= 90% vs random,
from the level's starts), from the level's starts and from random starts, beside the scripted
shortest-path robot's. Exits 1 when a target is missed (not in --quick mode, whose budgets are tiny).
"""

from __future__ import annotations

import argparse
import sys
import time

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.training.progress import target_callback
from babyrobot_marl.training.race import evaluate_race, train_race
from babyrobot_marl.training.single import evaluate_single, optimal_return, train_single, within

SINGLE_TARGET_STEPS = 100_000
RACE_TARGET = 0.90


def single(level: str, budget: int, every: int, seed: int) -> list[str]:
    env = BabyRobotEnv(level=level)
    optimum = optimal_return(env)
    target = optimum - 0.05 * abs(optimum)
    cb = target_callback(lambda m: evaluate_single(m, env, episodes=5, seed=seed).mean, target, every=every)
    t0 = time.perf_counter()
    # exploring starts: training episodes begin on random free cells; evaluation from the level start
    agent = train_single(level, "ppo", steps=budget, seed=seed, callback=cb, env_kwargs={"start": "random"})
    total = time.perf_counter() - t0
    final = evaluate_single(agent, env, episodes=20, seed=seed + 1000)
    print(f"single robot, PPO, {level}: optimal return {optimum:g}, target (95%) {target:g}")
    for steps, seconds, mean in cb.history:
        print(f"  {steps:>7} steps  {seconds:6.1f} s  mean return {mean:g}")
    if cb.reached:
        steps, seconds = cb.reached
        print(f"  reached 95% of optimal at {steps} timesteps, {seconds:.1f} s of training "
              f"({steps / budget:.2f} of the {budget} budget; target <= {SINGLE_TARGET_STEPS})")
    else:
        print(f"  did NOT reach 95% of optimal within {budget} timesteps ({total:.1f} s)")
    print(f"  final policy: mean return {final.mean:g} over {final.episodes} episodes, "
          f"within 95%: {within(final.mean, optimum)}")
    if cb.reached is None or cb.reached[0] > SINGLE_TARGET_STEPS:
        return [f"single robot: 95% of optimal not reached within {SINGLE_TARGET_STEPS} timesteps"]
    return []


class _Scripted:
    """A scripted policy behind SB3's ``predict``: the reference racer beside the trained one."""

    def __init__(self, policy) -> None:
        self.policy = policy

    def predict(self, obs, deterministic: bool = True):
        return self.policy(obs), None


def race(level: str, robots: int, budget: int, seed: int, races: int) -> list[str]:
    from babyrobot_marl import compile_level, levels, policies

    t0 = time.perf_counter()
    agent = train_race(level, n_robots=robots, steps=budget, seed=seed)
    seconds = time.perf_counter() - t0
    shortest = _Scripted(policies.make("shortest", compile_level(levels.get(level))))
    print(f"race, shared PPO via SuperSuit, {level}, {robots} robots: {budget} timesteps, {seconds:.1f} s")
    print("  robot_0 against scripted opponents; 'level' starts: the level's numbered starts (the race as")
    print("  designed); 'random' starts: every robot on a random free cell (an opponent may start next to the exit)")
    head = f"  {'starts':7s} {'opponents':9s} {'trained PPO win rate':>21s} {'steps':>6s}"
    print(head + f" {'shortest robot win rate':>24s} {'steps':>6s}")
    missed = []
    for start in ("level", "random"):
        for opponent in ("random", "shortest"):
            res = evaluate_race(agent, level, n_robots=robots, opponent=opponent, races=races, seed=seed + 1, start=start)
            ref = evaluate_race(shortest, level, n_robots=robots, opponent=opponent, races=races, seed=seed + 1, start=start)
            row = f"  {start:7s} {opponent:9s} {res.win_rate:21.2f} {res.mean_steps:6.1f}"
            print(row + f" {ref.win_rate:24.2f} {ref.mean_steps:6.1f}")
            if start == "level" and opponent == "random" and res.win_rate < RACE_TARGET:
                missed.append(f"race: win rate {res.win_rate:.2f} < {RACE_TARGET:.2f} against random opponents")
    print(f"  target: >= {RACE_TARGET:.2f} against random opponents from the level's starts")
    return missed


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", default="maze-8x8")
    p.add_argument("--race-level", default="race-4")
    p.add_argument("--robots", type=int, default=4)
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--race-steps", type=int, default=300_000)
    p.add_argument("--every", type=int, default=5000)
    p.add_argument("--races", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true", help="tiny budgets: checks that the script runs")
    p.add_argument("--only", choices=("single", "race"), default=None)
    a = p.parse_args()
    if a.quick:
        a.steps, a.race_steps, a.every, a.races = 2048, 2048, 1024, 10
    missed = []
    if a.only != "race":
        missed += single(a.level, a.steps, a.every, a.seed)
    if a.only != "single":
        missed += race(a.race_level, a.robots, a.race_steps, a.seed, a.races)
    if a.quick:
        print("quick mode: tiny budgets, targets not checked")
        return 0
    for m in missed:
        print(f"MISSED: {m}")
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
