"""Train PPO in seconds with the fast trainer (babyrobot_marl.training.ppo), then replay the policy.

    python examples/train_fast.py                                 # maze-8x8, one robot
    python examples/train_fast.py --level maze-16x16 --steps 5000000
    python examples/train_fast.py --level race-4 --robots 4 --steps 2000000   # one policy, four robots

PPO with Stable-Baselines3's knobs, stepped on the batch engine: one robot is judged against value
iteration's optimum, a race robot against three random and three shortest-path robots. Prints a
line per evaluation, saves the policy (a torch file) and plays one episode with it, as
`babyrobot-marl play --policy PATH` does.

Needs the train extra, torch's CPU build first (else pip fetches a ~3 GB CUDA build):

    pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu
    pip install 'babyrobot_marl[train]'
"""

from __future__ import annotations

import argparse

from babyrobot_marl import BabyRobotEnv, levels
from babyrobot_marl.training.evaluate import race_rates
from babyrobot_marl.training.policy import load_policy
from babyrobot_marl.training.ppo import PPOConfig, train_ppo
from babyrobot_marl.training.single import evaluate_single, optimal_return


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", default="maze-8x8")
    p.add_argument("--robots", type=int, default=1)
    p.add_argument("--steps", type=int, default=2_000_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--save", default="policy.pt")
    a = p.parse_args()
    level = levels.get(a.level)
    env = BabyRobotEnv(level=level)
    if a.robots == 1:
        optimum = optimal_return(env)
        target = optimum - 0.05 * abs(optimum)

        def evaluate(result) -> float:  # the greedy policy from the level's start
            return evaluate_single(result.policy(), env, episodes=5).mean
    else:
        target = 0.95

        def evaluate(result) -> float:  # robot_0 against random robots
            return race_rates(result.policy(), level, a.robots, "random", races=100, seed=a.seed).win_rate

    def line(point) -> None:
        print(f"{point.timesteps:>9} steps  {point.seconds:6.2f} s  training return {point.train_return:8.3g}  "
              f"evaluation {point.score:.3g}", flush=True)

    config = PPOConfig() if a.robots == 1 else PPOConfig(n_envs=64, batch_size=1024, eval_every=32768)
    result = train_ppo(level, a.robots, a.steps, a.seed, config, evaluate=evaluate, target=target, stop_at_target=True,
                       on_eval=line)
    print(f"{result.timesteps} timesteps in {result.seconds:.2f} s of training ({result.steps_per_second:,.0f} steps/s); "
          + (f"target {target:g} first met at {result.reached[0]} timesteps" if result.reached else "target not met"))
    print(f"saved {result.save(a.save)}")
    if a.robots > 1:
        for opponent in ("random", "shortest"):
            r = race_rates(result.policy(), level, a.robots, opponent, races=500, seed=a.seed + 1)
            print(f"vs {a.robots - 1} {opponent} robots: win rate {r.win_rate:.3f}, tie rate {r.tie_rate:.3f}")
        return
    policy = load_policy(a.save, env.table)  # any robot's interface: policy(obs) -> action
    obs, _ = env.reset(seed=a.seed)
    total, done = 0.0, False
    while not done:
        obs, reward, terminated, truncated, _ = env.step(policy(obs))
        total += reward
        done = terminated or truncated
    print(f"replayed the saved policy: return {total:g} (optimal {optimum:g})")


if __name__ == "__main__":
    main()
