"""Train PPO on a Baby Robot race with Ray RLlib, then race the trained robot against scripted ones.

    python examples/rllib_race.py --iterations 1 --num-env-runners 1      # a few minutes on 2 cores
    python examples/rllib_race.py --level race-4 --robots 4 --iterations 20 --per-robot
    ray start --head                                                       # on a cluster: the head node
    python examples/rllib_race.py --address auto --num-env-runners 16     # joins it

Without ``--address`` the script starts a local Ray, listening on 127.0.0.1 only (reachable from
this machine alone), and stops it at the end; an ``--address`` given is joined as it is. Needs the
``rllib`` extra, torch's CPU build first
(``pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu && pip install -e ".[rllib]"``).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a source checkout too


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--level", default="race-2", help="a race level (babyrobot-marl levels), default race-2")
    parser.add_argument("--robots", type=int, default=2, help="robots in the race (default 2)")
    parser.add_argument("--iterations", type=int, default=10, help="PPO training iterations (default 10)")
    parser.add_argument(
        "--num-env-runners",
        type=int,
        default=None,
        help="remote env runners (default: one per CPU; 0: sample in the driver)",
    )
    policy = parser.add_mutually_exclusive_group()
    policy.add_argument("--shared", dest="shared", action="store_true", default=True, help="one policy for all robots (default)")
    policy.add_argument("--per-robot", dest="shared", action="store_false", help="one policy per robot")
    parser.add_argument("--address", default=None, help="join this Ray cluster ('auto' after `ray start --head`)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--batch", type=int, default=4000, help="env steps per iteration (default 4000)")
    parser.add_argument("--races", type=int, default=100, help="races per opponent in the final evaluation")
    parser.add_argument("--quick", action="store_true", help="CI: small batches and few evaluation races")
    args = parser.parse_args(argv)
    for name in ("robots", "iterations", "batch", "races"):
        if getattr(args, name) < 1:
            parser.error(f"--{name}: must be >= 1")
    if args.num_env_runners is not None and args.num_env_runners < 0:
        parser.error("--num-env-runners: must be >= 0")
    if args.quick:
        args.batch, args.races = min(args.batch, 400), min(args.races, 20)
    return args


def progress_row(it: int, result: dict, seconds: float, robots: list[str]) -> str:
    runners = result["env_runners"]
    steps = runners.get("num_env_steps_sampled", 0)
    returns = runners.get("agent_episode_returns_mean", {})
    cells = " ".join(f"{returns[r]:>9.1f}" if r in returns else f"{'-':>9s}" for r in robots)
    return f"{it:>4d} {steps:>8,.0f} {steps / seconds:>9,.0f} {runners.get('episode_len_mean', float('nan')):>8.1f} {cells}"


def main(argv: list[str] | None = None) -> None:
    args = parse_args(argv)
    import ray

    from babyrobot_marl.integrations.rllib import (
        SHARED_POLICY,
        RaceMultiAgentEnv,
        greedy_policy,
        init_local_ray,
        race_config,
        win_rate,
    )

    env_config = {"level": args.level, "n_robots": args.robots}
    if args.address:
        ray.init(address=args.address)
    else:
        init_local_ray(os.cpu_count(), log_to_driver=False)  # listens on 127.0.0.1 only
    algo = None
    try:
        runners = args.num_env_runners
        if runners is None:
            runners = max(1, int(ray.cluster_resources().get("CPU", 1)))
        config = race_config(env_config, shared=args.shared, num_env_runners=runners, seed=args.seed).training(
            lr=3e-4,
            train_batch_size_per_learner=args.batch,
            minibatch_size=min(256, args.batch),
            num_epochs=10 if not args.quick else 2,
            entropy_coeff=0.01,
        )
        algo = config.build_algo()
        robots = [f"robot_{i}" for i in range(args.robots)]
        print(
            f"PPO on {args.level}, {args.robots} robots, {'one shared policy' if args.shared else 'one policy per robot'}, "
            f"{runners} env runner(s), {args.batch} env steps per iteration"
        )
        print(f"{'iter':>4s} {'steps':>8s} {'steps/s':>9s} {'ep len':>8s} " + " ".join(f"{r:>9s}" for r in robots))
        for it in range(1, args.iterations + 1):
            t0 = time.perf_counter()
            result = algo.train()
            print(progress_row(it, result, time.perf_counter() - t0, robots), flush=True)

        module_id = SHARED_POLICY if args.shared else "robot_0"
        space = RaceMultiAgentEnv(env_config).observation_spaces["robot_0"]
        policy = greedy_policy(algo.get_module(module_id), space)
        print(f"\nwin rate of the trained robot_0 (greedy, policy {module_id!r}) over {args.races} races:")
        for opponent in ("shortest", "random"):
            rate = win_rate(policy, env_config, opponent, races=args.races, seed=args.seed)
            print(f"  against {args.robots - 1} {opponent:8s} robot(s): {rate:6.1%}")
    finally:
        if algo is not None:
            algo.stop()
        ray.shutdown()


if __name__ == "__main__":
    main()
