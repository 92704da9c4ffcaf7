"""Train one PPO policy shared by every robot of the race (SuperSuit), then race it against
scripted opponents.

    python examples/train_race.py                             # race-4, 4 robots, 300k steps
    python examples/train_race.py --level race-2 --robots 2 --steps 100000
    python examples/train_race.py --backend native            # the batch engine instead of SuperSuit

The vector env is SuperSuit's pettingzoo_env_to_vec_env_v1 + concat_vec_envs_v1(base_class=
"stable_baselines3") over race_v0 with finished="freeze"; babyrobot_marl.training.race explains
how its pitfalls (same episodes in every copy, PPO(seed=...) failing, no truncation flag) are
handled. Prints the win rate and mean finishing steps against 'random' and 'shortest' robots.
Needs the train extra, torch's CPU build first (else pip fetches a ~3 GB CUDA build):

    pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu
    pip install 'babyrobot_marl[train]'
"""

from __future__ import annotations

import argparse
import time

from babyrobot_marl.training.race import evaluate_race, train_race


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", default="race-4")
    p.add_argument("--robots", type=int, default=4)
    p.add_argument("--steps", type=int, default=300_000)
    p.add_argument("--races", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--backend", choices=("supersuit", "native"), default="supersuit")
    p.add_argument("--save", default=None, help="model path (default: babyrobot_race_<level>.zip)")
    a = p.parse_args()
    t0 = time.perf_counter()
    agent = train_race(a.level, n_robots=a.robots, steps=a.steps, seed=a.seed, backend=a.backend, progress_bar=True)
    print(f"trained a shared PPO policy for {a.steps} steps in {time.perf_counter() - t0:.0f} s ({a.backend})")
    for opponent in ("random", "shortest"):
        r = evaluate_race(agent, a.level, n_robots=a.robots, opponent=opponent, races=a.races, seed=a.seed + 1)
        print(f"vs {opponent:8s}: win rate {r.win_rate:.2f} ({r.wins}/{r.races}), finished {r.finished}, "
              f"mean finishing steps {r.mean_steps:.1f} (opponents {r.opponent_mean_steps:.1f})")
    path = a.save or f"babyrobot_race_{a.level}.zip"
    agent.save(path)
    print(f"saved {path}")


if __name__ == "__main__":
    main()
