"""Training benchmark (not a test): the fast PPO trainer against Stable-Baselines3 PPO, in one run.

    python benchmarks/bench_train.py              # full run (a few minutes)
    python benchmarks/bench_train.py --runs 3     # three runs and their spread
    python benchmarks/bench_train.py --quick      # CI smoke run: tiny budgets, targets not checked

1. Speed, end to end (rollouts and updates): the same PPO run with the same network (the one-hot
   of the robot's cell, in a race plus the four near-robot bits of ``training.ppo.Inputs``; 64x64
   tanh actor and critic), the same rollout, minibatch and epochs, timed for the same
   timesteps: ``training.ppo.train_ppo`` against SB3 ``PPO`` on the batch engine's own SB3 vec env
   (its fastest path), for one robot on maze-8x8 and a 4-robot race on race-4. Steps per second
   of the process's CPU time (wall time beside it: on a shared machine it also counts the others).
   Floor: 20x SB3 (aim 50x), for each. Then the fast trainer alone after it has learnt: steps per
   second of CPU time over the second half of 8M timesteps (short episodes: resets weigh).
2. Time to 95% of the optimum (value iteration) from the level's start, greedy policy, training
   seconds (evaluations excluded): fast trainer beside SB3 with this package's tuned SB3 settings,
   on maze-8x8 (aim: under 5 s) and maze-16x16.
3. The race: race-4, 4 robots, 60 s of training at most: robot_0 from the level's start against 3
   random robots (target: win rate >= 0.95) and against 3 shortest-path robots (win and tie rates);
   then against 3 shortest-path robots from random starts, beside the shortest-path robot in
   robot_0's seat (from race-4's own starts robot_0 is furthest from the exit: nobody wins or ties
   from there). SB3 trained for the same 60 s beside it.
4. The recurrent trainer (``--recurrent``): 4 robots on ``maze:8..16`` as ``babyrobot-marl train`` runs a
   crowd on a level family (256 envs, near_radius 2, blocked_cost 0.5), env steps per second of CPU time
   (each of the 4 robots' steps counts once) over 48 rollouts after the first (3 atlases of mazes), as ``train``
   reports its speed: the GRU, the minGRU (``--cell mingru``), the light recipe (``LIGHT``: ``--cell mingru
   --hidden 16 --net-arch 32 --n-epochs 1 --n-envs 8192 --n-steps 32 --batch-size 262144``), and beside them
   the same run with ``--memory`` (feed-forward). Target: 500,000 steps/s (the fastest recurrent run).

Exits 1 when a target (not an aim) is missed. Torch runs on one thread in both trainers.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time

import numpy as np
import torch

from babyrobot_marl import BabyRobotEnv, levels
from babyrobot_marl.training.evaluate import race_rates
from babyrobot_marl.training.ppo import PPOConfig, near_offsets, train_ppo
from babyrobot_marl.training.race import evaluate_race, race_near_features_class
from babyrobot_marl.training.single import cell_features_class, evaluate_single, optimal_return

SPEED_FLOOR, SPEED_AIM = 20.0, 50.0
RACE_TARGET, RACE_SECONDS = 0.95, 60.0
MAZE8_AIM = 5.0
RECURRENT_TARGET = 500_000

# The run both trainers make for the speed comparison (SB3's names).
# The fast trainer's defaults (PPOConfig): many envs, short rollouts, big minibatches.
SPEED_RUN = {"n_envs": 1024, "n_steps": 16, "batch_size": 16384, "n_epochs": 4, "learning_rate": 3e-3, "gamma": 0.99,
             "gae_lambda": 0.95, "clip_range": 0.2, "ent_coef": 0.01}


def sb3_ppo(level: str, n_robots: int, seed: int, run: dict, **env_kwargs):
    """SB3 PPO on the batch engine's SB3 vec env with the fast trainer's network and input."""
    from stable_baselines3 import PPO

    from babyrobot_marl.envs.vector import sb3_vec_env

    lv = levels.get(level)
    run = dict(run)
    n_envs = run.pop("n_envs")
    venv = sb3_vec_env(level, n_envs=n_envs, n_robots=n_robots, start="random", **env_kwargs)
    venv.seed(seed)
    if n_robots == 1:
        features = {"features_extractor_class": cell_features_class(),
                    "features_extractor_kwargs": {"width": lv.width, "height": lv.height}}
    else:
        features = {"features_extractor_class": race_near_features_class(),
                    "features_extractor_kwargs": {"width": lv.width, "height": lv.height, "n_robots": n_robots,
                                                  "near": near_offsets(PPOConfig().near_radius)}}
    policy_kwargs = {"net_arch": {"pi": [64, 64], "vf": [64, 64]}, **features}
    return PPO("MlpPolicy", venv, seed=seed, device="cpu", policy_kwargs=policy_kwargs, **run)


def fast_config(run: dict, **more) -> PPOConfig:
    return PPOConfig(**run, eval_every=0, **more)


# ---------------------------------------------------------------------------- 1. speed
def speed(level: str, n_robots: int, timesteps: int, seed: int) -> dict:
    """Steps per second of CPU time (the process's, one torch thread in both): on a machine that
    others share, wall time measures the others too; on an idle one the two agree."""
    cfg = fast_config(SPEED_RUN)
    train_ppo(level, n_robots, cfg.n_envs * cfg.n_steps * n_robots, seed, cfg)  # warm-up: imports, allocations
    c0, t0 = time.process_time(), time.perf_counter()
    fast = train_ppo(level, n_robots, timesteps, seed, cfg)
    fast_cpu, fast_wall = time.process_time() - c0, time.perf_counter() - t0
    model = sb3_ppo(level, n_robots, seed, SPEED_RUN)
    c0, t0 = time.process_time(), time.perf_counter()
    model.learn(timesteps)
    sb3_cpu, sb3_wall = time.process_time() - c0, time.perf_counter() - t0
    return {"fast": fast.timesteps / fast_cpu, "sb3": model.num_timesteps / sb3_cpu,
            "fast_wall": fast.timesteps / fast_wall, "sb3_wall": model.num_timesteps / sb3_wall}


# the light recipe: a minGRU of 16 units on one layer of 32, one epoch, 8,192 envs, segments of 32 steps (minibatches
# of 262,144 robot-steps)
LIGHT = {"recurrent": True, "cell": "mingru", "hidden": 16, "net_arch": (32,), "n_epochs": 1, "n_envs": 8192,
         "n_steps": 32, "batch_size": 262144}
FAMILY_RUNS = {"recurrent": {"recurrent": True}, "mingru": {"recurrent": True, "cell": "mingru"}, "memory": {"memory": True},
               "light": LIGHT}
FAMILY_ROLLOUTS = 48  # three atlases of mazes (one every 16 rollouts): their building counts


def family_speed(rollouts: int, seed: int, warm_up: bool = True, **run) -> float:
    """Steps per second of CPU time of the fast trainer on 4 robots in ``maze:8..16`` as ``train`` runs a crowd on a
    level family (256 envs unless ``run`` says), with ``run`` (one of ``FAMILY_RUNS``): from the end of the first
    rollout and update to the end of the last of ``rollouts``, as ``train`` reports its speed (no setting up, no
    evaluation)."""
    cfg = PPOConfig(**{"n_envs": 256, "eval_every": 0, "near_radius": 2, "blocked_cost": 0.5, **run})
    per = cfg.n_envs * cfg.n_steps * 4
    if warm_up:  # imports, allocations
        train_ppo("maze:8..16", 4, per, seed, cfg)
    marks = update_marks("maze:8..16", 4, per * rollouts, seed, cfg)
    (t0, c0), (t1, c1) = marks[0], marks[-1]
    return (t1 - t0) / (c1 - c0)


def update_marks(level: str, n_robots: int, timesteps: int, seed: int, cfg: PPOConfig) -> list[tuple[int, float]]:
    """A training run's timesteps and the process's CPU time at the end of each of its updates."""
    marks: list[tuple[int, float]] = []
    train_ppo(level, n_robots, timesteps, seed, cfg, on_update=lambda t, s, r: marks.append((t, time.process_time())))
    return marks


# ---------------------------------------------------------------------------- 2. time to 95%
FAST_MAZE: dict = {}  # the defaults


def late_speed(level: str, n_robots: int, timesteps: int, seed: int) -> float:
    """The fast trainer's steps per second of CPU time over the second half of ``timesteps`` (SB3's run, the
    same): once the policy has learnt, episodes are short and starting them weighs."""
    marks = update_marks(level, n_robots, timesteps, seed, fast_config(SPEED_RUN))
    half = [m for m in marks if m[0] >= timesteps // 2] or marks
    (t0, c0), (t1, c1) = half[0], marks[-1]
    return (t1 - t0) / (c1 - c0) if c1 > c0 else float("nan")


def to_95_fast(level: str, budget: int, every: int, seed: int) -> dict:
    env = BabyRobotEnv(level=level)
    optimum = optimal_return(env)
    target = optimum - 0.05 * abs(optimum)
    cfg = PPOConfig(**FAST_MAZE, eval_every=every)
    r = train_ppo(level, 1, budget, seed, cfg, evaluate=lambda res: evaluate_single(res.policy(), env, episodes=5).mean,
                  target=target, stop_at_target=True)
    return {"optimum": optimum, "reached": r.reached, "seconds": r.seconds, "timesteps": r.timesteps}


def to_95_sb3(level: str, budget: int, every: int, seed: int) -> dict:
    from babyrobot_marl.training.progress import target_callback
    from babyrobot_marl.training.single import train_single

    env = BabyRobotEnv(level=level)
    optimum = optimal_return(env)
    target = optimum - 0.05 * abs(optimum)
    cb = target_callback(lambda m: evaluate_single(m, env, episodes=5).mean, target, every=every)
    train_single(level, "ppo", steps=budget, seed=seed, callback=cb, env_kwargs={"start": "random"})
    return {"optimum": optimum, "reached": cb.reached}


# ---------------------------------------------------------------------------- 3. the race
RACE_RUN = {"n_envs": 16, "n_steps": 32, "batch_size": 512, "n_epochs": 4, "learning_rate": 1e-3}


def race_fast(seconds: float, every: int, seed: int, races: int) -> dict:
    lv = levels.get("race-4")
    cfg = PPOConfig(**RACE_RUN, eval_every=every)
    r = train_ppo(lv, 4, 10**9, seed, cfg, evaluate=lambda res: race_rates(res.policy(), lv, 4, "random", 100, seed + 1).win_rate,
                  target=RACE_TARGET, max_seconds=seconds)
    pol = r.policy()
    rnd, sho = (race_rates(pol, lv, 4, o, races, seed + 1) for o in ("random", "shortest"))
    # from random starts robot_0 is sometimes nearest the exit: beside it, the shortest-path robot in its seat
    sho_any = race_rates(pol, lv, 4, "shortest", races, seed + 1, start="random")
    ref_any = race_rates("shortest", lv, 4, "shortest", races, seed + 1, start="random")
    return {"seconds": r.seconds, "timesteps": r.timesteps, "reached": r.reached, "random": rnd, "shortest": sho,
            "shortest_any": sho_any, "reference_any": ref_any}


def race_sb3(seconds: float, seed: int, races: int) -> dict:
    from stable_baselines3.common.callbacks import BaseCallback

    class Clock(BaseCallback):
        def _on_training_start(self) -> None:
            self.t0 = time.perf_counter()

        def _on_step(self) -> bool:
            return time.perf_counter() - self.t0 < seconds

    model = sb3_ppo("race-4", 4, seed, {**SPEED_RUN, **RACE_RUN})
    t0 = time.perf_counter()
    model.learn(10**9, callback=Clock())
    took = time.perf_counter() - t0
    rnd, sho = (evaluate_race(model, "race-4", n_robots=4, opponent=o, races=races, seed=seed + 1, start="fill")
                for o in ("random", "shortest"))
    sho_any = evaluate_race(model, "race-4", n_robots=4, opponent="shortest", races=races, seed=seed + 1, start="random")
    return {"seconds": took, "timesteps": model.num_timesteps, "random": rnd, "shortest": sho, "shortest_any": sho_any}


# ---------------------------------------------------------------------------- report
def spread(values: list[float], fmt: str = "{:.1f}") -> str:
    if len(values) == 1:
        return fmt.format(values[0])
    return f"{fmt.format(statistics.median(values))} (min {fmt.format(min(values))}, max {fmt.format(max(values))})"


def race_summary(rows: dict, failures: list) -> None:
    rf, rs = rows["race fast"], rows["race sb3"]
    wins = [r["random"].win_rate for r in rf]
    print(f"race-4, 4 robots, {RACE_SECONDS:g} s of training at most: vs 3 random: fast {spread(wins, '{:.3f}')} | SB3 "
          f"{spread([r['random'].win_rate for r in rs], '{:.3f}')} (target >= {RACE_TARGET})")
    print(f"  vs 3 shortest: fast win {spread([r['shortest'].win_rate for r in rf], '{:.3f}')}, tie "
          f"{spread([r['shortest'].tie_rate for r in rf], '{:.3f}')} | SB3 win "
          f"{spread([r['shortest'].win_rate for r in rs], '{:.3f}')}, "
          f"tie {spread([r['shortest'].tie_rate for r in rs], '{:.3f}')}")
    print(f"  vs 3 shortest, random starts: fast win {spread([r['shortest_any'].win_rate for r in rf], '{:.3f}')}, tie "
          f"{spread([r['shortest_any'].tie_rate for r in rf], '{:.3f}')} | SB3 win "
          f"{spread([r['shortest_any'].win_rate for r in rs], '{:.3f}')}, tie "
          f"{spread([r['shortest_any'].tie_rate for r in rs], '{:.3f}')} | the shortest-path robot in that seat: win "
          f"{spread([r['reference_any'].win_rate for r in rf], '{:.3f}')}, tie "
          f"{spread([r['reference_any'].tie_rate for r in rf], '{:.3f}')}")
    print(f"  training timesteps in that time: fast {spread([r['timesteps'] for r in rf], '{:,.0f}')} | SB3 "
          f"{spread([r['timesteps'] for r in rs], '{:,.0f}')}")
    if min(wins) < RACE_TARGET:
        failures.append(f"race vs random: win rate {min(wins):.3f} < {RACE_TARGET}")


def machine() -> str:
    """The CPU's model name, its count and the versions that time: absolute steps per second are this machine's."""
    model = platform.processor() or platform.machine()
    try:  # Linux: the model's name, and its family and number (a virtual machine may show a generic name)
        with open("/proc/cpuinfo") as f:
            info = dict(line.split(":", 1) for line in f.read().split("\n\n")[0].splitlines() if ":" in line)
        info = {k.strip(): v.strip() for k, v in info.items()}
        if "model name" in info:
            model = f"{info['model name']} (cpu family {info.get('cpu family', '?')}, model {info.get('model', '?')})"
    except OSError:
        pass
    return (f"{model}, {os.cpu_count()} CPUs; Python {platform.python_version()}, torch {torch.__version__}, "
            f"numpy {np.__version__}")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="tiny budgets: checks that the script runs, figures meaningless")
    p.add_argument("--runs", type=int, default=1, help="repeat everything and report the median and range")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--skip-sb3-16", action="store_true", help="no SB3 run on maze-16x16 (minutes)")
    p.add_argument("--only", choices=("speed", "late", "maze", "race", "recurrent"), default=None,
                   help="one part only (no summary targets)")
    a = p.parse_args()
    torch.set_num_threads(1)
    quick = a.quick
    speed_steps = 4096 if quick else 2**20
    late_steps = 2**18 if quick else 8_000_000
    budget8, budget16, every = (4096, 4096, 2048) if quick else (5_000_000, 30_000_000, 32768)
    sb3_budget8, sb3_budget16 = (2048, 2048) if quick else (200_000, 400_000)
    race_seconds, race_every, races = (2.0, 8192, 20) if quick else (RACE_SECONDS, 32768, 500)
    family_rollouts = 2 if quick else FAMILY_ROLLOUTS
    rows: dict[str, list] = {}
    print(f"machine: {machine()}", flush=True)

    def add(key: str, value) -> None:
        rows.setdefault(key, []).append(value)

    for run in range(a.runs):
        seed = a.seed + run
        print(f"== run {run + 1}/{a.runs} (seed {seed})", flush=True)
        if a.only in (None, "speed"):
            for name, level, n in (("one robot, maze-8x8", "maze-8x8", 1), ("4-robot race, race-4", "race-4", 4)):
                s = speed(level, n, speed_steps, seed)
                print(f"  speed {name}: fast {s['fast']:,.0f} steps/s, SB3 {s['sb3']:,.0f} steps/s of CPU time: "
                      f"{s['fast'] / s['sb3']:.1f}x (wall time: {s['fast_wall'] / s['sb3_wall']:.1f}x)", flush=True)
                add(f"speed {name}", s)
        if a.only in (None, "late"):
            for name, level, n in (("one robot, maze-8x8", "maze-8x8", 1), ("4-robot race, race-4", "race-4", 4)):
                rate = late_speed(level, n, late_steps, seed)
                print(f"  speed after learning, {name}: fast {rate:,.0f} steps/s of CPU time (the second half of "
                      f"{late_steps:,} timesteps)", flush=True)
                add(f"late {name}", rate)
        if a.only in (None, "maze"):
            for level, budget, sb3_budget in (("maze-8x8", budget8, sb3_budget8), ("maze-16x16", budget16, sb3_budget16)):
                f = to_95_fast(level, budget, every, seed)
                add(f"95 fast {level}", f)
                line = (f"  to 95% on {level} (optimum {f['optimum']:g}): fast "
                        + (f"{f['reached'][1]:.2f} s, {f['reached'][0]} timesteps" if f["reached"] else f"not within {budget}"))
                if level == "maze-16x16" and a.skip_sb3_16:
                    print(line, flush=True)
                    continue
                s = to_95_sb3(level, sb3_budget, every, seed)
                add(f"95 sb3 {level}", s)
                print(line + "; SB3 " + (f"{s['reached'][1]:.2f} s, {s['reached'][0]} timesteps" if s["reached"]
                                         else f"not within {sb3_budget} timesteps"), flush=True)
        if a.only in (None, "race"):
            rf = race_fast(race_seconds, race_every, seed, races)
            add("race fast", rf)
            print(f"  race-4, 4 robots, {rf['seconds']:.0f} s ({rf['timesteps']} timesteps): fast vs random win "
                  f"{rf['random'].win_rate:.3f}, vs shortest win {rf['shortest'].win_rate:.3f} tie {rf['shortest'].tie_rate:.3f}"
                  + (f"; first >= {RACE_TARGET} at {rf['reached'][1]:.1f} s" if rf["reached"] else ""), flush=True)
            rs = race_sb3(race_seconds, seed, races)
            add("race sb3", rs)
            print(f"  race-4, 4 robots, {rs['seconds']:.0f} s ({rs['timesteps']} timesteps): SB3 vs random win "
                  f"{rs['random'].win_rate:.3f}, vs shortest win {rs['shortest'].win_rate:.3f} tie {rs['shortest'].tie_rate:.3f}",
                  flush=True)

        if a.only in (None, "recurrent"):
            runs = {k: {**r, "n_envs": 16} if quick else r for k, r in FAMILY_RUNS.items()}  # quick: 16 envs
            rates = {kind: family_speed(family_rollouts, seed, not quick, **run) for kind, run in runs.items()}
            print(f"  4 robots on maze:8..16: recurrent (GRU) {rates['recurrent']:,.0f} steps/s, minGRU "
                  f"{rates['mingru']:,.0f}, memory (feed-forward) {rates['memory']:,.0f}, light recipe (minGRU) "
                  f"{rates['light']:,.0f} steps/s of CPU time", flush=True)
            add("recurrent", rates)

    print("\n== summary" + (f" over {a.runs} runs: median (min, max)" if a.runs > 1 else ""))
    failures = []
    for name in ("one robot, maze-8x8", "4-robot race, race-4") if "speed one robot, maze-8x8" in rows else ():
        runs = rows[f"speed {name}"]
        ratios = [s["fast"] / s["sb3"] for s in runs]
        print(f"speed, {name}: fast {spread([s['fast'] for s in runs], '{:,.0f}')} steps/s | SB3 "
              f"{spread([s['sb3'] for s in runs], '{:,.0f}')} steps/s (CPU time) | {spread(ratios)}x "
              f"(floor {SPEED_FLOOR:g}x, aim {SPEED_AIM:g}x); wall time "
              f"{spread([s['fast_wall'] / s['sb3_wall'] for s in runs])}x")
        if min(ratios) < SPEED_FLOOR:
            failures.append(f"speed {name}: {min(ratios):.1f}x < {SPEED_FLOOR:g}x")
    for name in ("one robot, maze-8x8", "4-robot race, race-4") if "late one robot, maze-8x8" in rows else ():
        print(f"speed after learning, {name}: fast {spread(rows[f'late {name}'], '{:,.0f}')} steps/s (CPU time)")
    for level in ("maze-8x8", "maze-16x16") if "95 fast maze-8x8" in rows else ():
        fast = rows[f"95 fast {level}"]
        secs = [f["reached"][1] for f in fast if f["reached"]]
        steps = [f["reached"][0] for f in fast if f["reached"]]
        text = f"to 95% on {level}: fast {spread(secs, '{:.2f}')} s, {spread(steps, '{:.0f}')} timesteps" if secs else \
            f"to 95% on {level}: fast not reached"
        if len(secs) < len(fast):
            text += f" (not reached in {len(fast) - len(secs)} runs)"
        sb3 = rows.get(f"95 sb3 {level}", [])
        sb3_secs = [s["reached"][1] for s in sb3 if s["reached"]]
        if sb3:
            text += (f" | SB3 {spread(sb3_secs, '{:.2f}')} s, {spread([s['reached'][0] for s in sb3 if s['reached']], '{:.0f}')} "
                     f"timesteps" if sb3_secs else " | SB3 not reached") + (
                f" (not reached in {len(sb3) - len(sb3_secs)} runs)" if sb3_secs and len(sb3_secs) < len(sb3) else "")
        if level == "maze-8x8":
            text += f" (aim: under {MAZE8_AIM:g} s)"
        print(text)
    if "race fast" in rows:
        race_summary(rows, failures)
    if "recurrent" in rows:
        rec = {kind: [r[kind] for r in rows["recurrent"]] for kind in FAMILY_RUNS}
        print(f"recurrent, 4 robots on maze:8..16: GRU {spread(rec['recurrent'], '{:,.0f}')} steps/s, minGRU "
              f"{spread(rec['mingru'], '{:,.0f}')}, light recipe (minGRU) {spread(rec['light'], '{:,.0f}')} (CPU time; "
              f"target {RECURRENT_TARGET:,}); memory {spread(rec['memory'], '{:,.0f}')} steps/s; the light recipe over "
              f"the feed-forward run: {spread([a / b for a, b in zip(rec['light'], rec['memory'])], '{:.1f}x')}")
        best = max(min(rec[kind]) for kind in ("recurrent", "mingru", "light"))
        if best < RECURRENT_TARGET:
            failures.append(f"recurrent speed: {best:,.0f} < {RECURRENT_TARGET:,} steps/s")
    if quick:
        print("\nquick mode: tiny budgets, figures meaningless, targets not checked")
        return 0
    for f in failures:
        print(f"MISSED: {f}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
