"""PPO training throughput on the race: Ray RLlib with 1 and 2 env runners beside SuperSuit + SB3.

    python benchmarks/bench_rllib.py            # a few minutes on 2 cores
    python benchmarks/bench_rllib.py --quick    # one short measured iteration each

Needs the ``rllib`` extra (and ``test`` for SuperSuit and Stable-Baselines3), in one venv.

Same level and robots for all (``race-4``, 4 robots), same PPO work per update: about 4,000
agent-steps per batch (RLlib: 1,000 env steps of 4 robots, finished robots leave; SB3: 4 race
copies x 4 robots x 250 steps, finished robots parked), 4 epochs, minibatches of 250, a
[64, 64] MLP over one-hot observations, CPU torch. Figures are env-steps (joint race steps)
per second of wall time, sampling and learning together, after one warm-up iteration; for
SB3 agent-steps are divided by the robots (with ``finished="freeze"`` every robot steps every
race step); medians over iterations, as other jobs share the machine. The first table compares
the two ways of giving RLlib the race, in a plain loop with random actions:
``ParallelPettingZooEnv`` over ``race_v0.parallel_env`` and the native ``RaceMultiAgentEnv``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from babyrobot_marl import race_v0  # noqa: E402

LEVEL, ROBOTS = "race-4", 4
ENV_CONFIG = {"level": LEVEL, "n_robots": ROBOTS}
RLLIB_BATCH = 1000  # env steps, ~4,000 agent-steps
SB3_COPIES, SB3_STEPS = 4, 250  # 4 copies x 4 robots x 250 = 4,000 agent-steps
EPOCHS, MINIBATCH = 4, 250  # 250 divides the 4,000 agent-steps of an SB3 rollout


def loop_rate(env, steps: int, seed: int = 0) -> float:
    """Env-steps/s of a random-action loop over an RLlib MultiAgentEnv."""
    rng = np.random.default_rng(seed)
    actions = rng.integers(0, 5, (steps, ROBOTS)).tolist()
    obs, _ = env.reset(seed=seed)
    racing = list(obs)
    t0 = time.perf_counter()
    for row in actions:
        _, _, terms, truncs, _ = env.step({a: row[int(a[6:])] for a in racing})
        if terms["__all__"] or truncs["__all__"]:
            obs, _ = env.reset()
            racing = list(obs)
        else:
            racing = [a for a in racing if not (terms[a] or truncs[a])]
    return steps / (time.perf_counter() - t0)


def wrapper_table(steps: int, rounds: int) -> None:
    from ray.rllib.env.wrappers.pettingzoo_env import ParallelPettingZooEnv

    from babyrobot_marl.integrations.rllib import RaceMultiAgentEnv

    envs = {
        "ParallelPettingZooEnv(race_v0)": ParallelPettingZooEnv(race_v0.parallel_env(**ENV_CONFIG)),
        "RaceMultiAgentEnv (native)": RaceMultiAgentEnv(ENV_CONFIG),
    }
    rates: dict[str, list[float]] = {name: [] for name in envs}
    for _ in range(rounds):  # interleaved rounds
        for name, env in envs.items():
            rates[name].append(loop_rate(env, steps))
    base = statistics.median(rates["ParallelPettingZooEnv(race_v0)"])
    print(f"RLlib env, {LEVEL}, {ROBOTS} robots, random actions    env-steps/s   vs wrapper")
    for name, rs in rates.items():
        r = statistics.median(rs)
        print(f"  {name:46s} {r:>11,.0f} {r / base:>11.2f}x")


def rllib_rate(num_env_runners: int, iterations: int) -> float:
    from babyrobot_marl.integrations.rllib import shared_policy_config

    config = shared_policy_config(ENV_CONFIG, num_env_runners=num_env_runners, seed=0).training(
        train_batch_size_per_learner=RLLIB_BATCH, minibatch_size=MINIBATCH, num_epochs=EPOCHS
    )
    algo = config.build_algo()
    try:
        algo.train()  # warm-up: actors, torch, first episodes
        rates = []
        for _ in range(iterations):
            t0 = time.perf_counter()
            steps = algo.train()["env_runners"]["num_env_steps_sampled"]
            rates.append(steps / (time.perf_counter() - t0))
        return statistics.median(rates)
    finally:
        algo.stop()


def sb3_rate(iterations: int) -> float:
    import supersuit as ss
    import torch
    from stable_baselines3 import PPO

    torch.manual_seed(0)
    torch.set_num_threads(1)  # as RLlib's learner in the driver; the other core is left to the runners
    vec = ss.pettingzoo_env_to_vec_env_v1(race_v0.parallel_env(**ENV_CONFIG, finished="freeze"))
    vec = ss.concat_vec_envs_v1(vec, SB3_COPIES, num_cpus=0, base_class="stable_baselines3")
    per_iter = SB3_COPIES * ROBOTS * SB3_STEPS
    model = PPO(
        "MlpPolicy", vec, n_steps=SB3_STEPS, batch_size=MINIBATCH, n_epochs=EPOCHS, verbose=0
    )  # no seed=: SuperSuit lacks seed()
    model.learn(per_iter)  # warm-up
    rates = []
    for _ in range(iterations):
        t0 = time.perf_counter()
        model.learn(per_iter, reset_num_timesteps=False)
        rates.append(per_iter / ROBOTS / (time.perf_counter() - t0))
    vec.close()
    return statistics.median(rates)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="one measured iteration each, short loops")
    parser.add_argument("--iterations", type=int, default=5, help="measured PPO iterations per set-up")
    args = parser.parse_args(argv)
    iterations = 1 if args.quick else args.iterations
    import ray

    from babyrobot_marl.integrations.rllib import init_local_ray

    init_local_ray(2, log_to_driver=False)  # listens on 127.0.0.1 only
    try:
        wrapper_table(steps=2_000 if args.quick else 20_000, rounds=1 if args.quick else 5)
        rates = {
            "RLlib PPO, 1 env runner": rllib_rate(1, iterations),
            "RLlib PPO, 2 env runners": rllib_rate(2, iterations),
        }
    finally:
        ray.shutdown()
    rates["SuperSuit + SB3 PPO (peer)"] = sb3_rate(iterations)
    peer = rates["SuperSuit + SB3 PPO (peer)"]
    print(f"\nPPO training, {LEVEL}, {ROBOTS} robots, sampling + learning   env-steps/s   vs SB3")
    for name, r in rates.items():
        print(f"  {name:46s} {r:>11,.0f} {r / peer:>9.2f}x")


if __name__ == "__main__":
    main()
