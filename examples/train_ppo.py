"""Train Stable-Baselines3 PPO (or DQN) on BabyRobot-v0 and compare with the exact optimum.

    python examples/train_ppo.py                          # PPO, maze-8x8, 100k steps
    python examples/train_ppo.py --algo dqn --steps 150000
    python examples/train_ppo.py --level mixed-8x8 --gif out/mixed.gif

Trains with a progress bar on a terminal, and one line per evaluation elsewhere (a log, a pipe);
training episodes start on random free cells, which spreads the experience over the level.
Evaluates the deterministic policy from the level's start, prints the learnt against value
iteration's optimal return, saves the model and a GIF of the learnt policy. For the fast trainer
(many times faster), see examples/train_fast.py.
Needs the train extra, torch's CPU build first (else pip fetches a ~3 GB CUDA build):

    pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu
    pip install 'babyrobot_marl[train]'
"""

from __future__ import annotations

import argparse
import sys
import time

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.render.video import episode_frames, save_gif
from babyrobot_marl.training.progress import target_callback
from babyrobot_marl.training.single import evaluate_single, optimal_return, train_single, within


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", default="maze-8x8")
    p.add_argument("--algo", choices=("ppo", "dqn"), default="ppo")
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--save", default=None, help="model path (default: babyrobot_<algo>_<level>.zip)")
    p.add_argument("--gif", default=None, help="GIF path (default: babyrobot_<algo>_<level>.gif)")
    a = p.parse_args()
    stem = f"babyrobot_{a.algo}_{a.level}"
    env = BabyRobotEnv(level=a.level)
    optimum = optimal_return(env)
    tty = sys.stdout.isatty()

    def line(steps: int, seconds: float, mean: float) -> None:  # off a terminal: one line per evaluation
        print(f"{steps:>8} steps  {seconds:6.1f} s  greedy return {mean:g} (optimal {optimum:g})", flush=True)

    callback = None if tty else target_callback(lambda m: evaluate_single(m, env, episodes=5, seed=a.seed).mean,
                                                optimum - 0.05 * abs(optimum), every=10_000, stop=False, on_eval=line)
    t0 = time.perf_counter()
    agent = train_single(a.level, a.algo, steps=a.steps, seed=a.seed, progress_bar=tty, callback=callback,
                         env_kwargs={"start": "random"})
    print(f"trained {a.algo.upper()} for {a.steps} steps in {time.perf_counter() - t0:.0f} s")
    ev = evaluate_single(agent, env, episodes=20, seed=a.seed + 1000)
    print(f"learnt return {ev.mean:g} (+- {ev.std:g}, {ev.reached_exit}/{ev.episodes} reached the exit); "
          f"optimal return {optimum:g} (value iteration); within 95%: {within(ev.mean, optimum)}")
    agent.save(a.save or stem + ".zip")
    frames = episode_frames(BabyRobotEnv(level=a.level, render_mode="rgb_array"),
                            lambda obs: int(agent.predict(obs, deterministic=True)[0]), seed=a.seed)
    print(f"saved {a.save or stem + '.zip'} and {save_gif(frames, a.gif or stem + '.gif')}")


if __name__ == "__main__":
    main()
