"""The race beside POGEMA 1.4 on POGEMA's own ground: CPU time per agent-step.

    python benchmarks/bench_pogema.py --pogema-python PATH       # about three minutes on a shared 2-core machine
    python benchmarks/bench_pogema.py --quick --pogema-python PATH   # CI smoke run: one short round, two sizes

POGEMA pins gymnasium 0.28.1, so it runs in a venv of its own (``pip install "pogema==1.4.*"``),
in a subprocess this script drives over stdin/stdout; ``--pogema-python`` (or ``POGEMA_PYTHON``)
names that venv's interpreter.

For each size (robots, map side): POGEMA makes its random map (obstacle density 0.3, its seed) with
``obs_radius=2`` and ``on_target="nothing"`` (no robot leaves), and steps it with uniformly random actions.
The race runs on the same map (``Level.from_grid`` of POGEMA's obstacles, one exit added in the largest open
region) as ``race_v0.parallel_env(observe="local", view_radius=2, start="random", max_cycles=128)``, its
actions random too, a dict of actions built per step as a PettingZoo user does, a new race every 128 steps
(POGEMA's maze benchmark's episode; its resets timed). Beside it, in the same rounds: ``own``, the race with
``goals="own"`` and ``finished="stay"`` (each robot its own target, and robots stay on their targets: POGEMA's
task under POGEMA's rule here, ``on_target="nothing"``); ``leaving``, own goals where a robot leaves the board at
its target (``finished="remove"``); and the batch engine (``env.batch(1)``, every robot's step and "local" rows
as arrays, no per-agent dicts). Robots that reach the exit (or, leaving, their targets) leave the board, so
short races keep those crowds near full, as POGEMA's: in one long race the crowds would thin at their own paces,
and their figures would be taken at different crowd sizes. All are timed in CPU time of their own process
(``time.process_time``), after an untimed warm-up, in turns (who goes first alternates), so a busy machine
slows them alike; agent-steps count the robots present at each step. Printed: microseconds per agent-step,
median over rounds and its range, the ratio POGEMA / race (higher: the race is faster) and own's and leaving's
times over the race's to the exit (``own / exit``, ``leaving / exit``), each round's ratio measured within the
round.

Two pairings of collision rules (``--collisions``): ``soft``, POGEMA's soft rule in both (the
same rule, step for step), and ``default``, each env's default (POGEMA's ``"priority"``, robots
moved one at a time in index order; the race's ``"block"``). Both by default.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from collections import deque
from pathlib import Path

import numpy as np
from bench_race import Stepper  # the race benchmark's timing loop

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level

PAIRINGS = {"soft": ("soft", "soft"), "default": ("priority", "block")}  # name: (POGEMA's collision_system, the race's)
SIZES = ((64, 32), (64, 64), (256, 32), (256, 64), (1024, 64))  # (robots, map side): 1,024 robots need the 64x64 maps
QUICK_SIZES = ((64, 32), (256, 64))
DENSITY, VIEW_RADIUS = 0.3, 2
EPISODE = 128  # steps of a race before the next (POGEMA's maze benchmark's episode)

# POGEMA's side, run by its own interpreter: prints its map, then CPU seconds and agent-steps per request.
WORKER = r"""
import json, sys, time
import numpy as np
from pogema import GridConfig, pogema_v0

sys.setrecursionlimit(100_000)  # the soft rule reverts chains of robots recursively

task = json.loads(sys.stdin.readline())
config = GridConfig(num_agents=task["robots"], size=task["side"], density=task["density"], obs_radius=task["radius"],
                    seed=task["seed"], collision_system=task["collisions"], on_target="nothing", max_episode_steps=10**9)
env = pogema_v0(grid_config=config)
env.reset()
obstacles = env.grid.get_obstacles(ignore_borders=True)
print(json.dumps(["".join("#" if v else "." for v in row) for row in obstacles.tolist()]), flush=True)
rng = np.random.default_rng(task["seed"])
for line in sys.stdin:
    actions = rng.integers(0, 5, (int(line), task["robots"])).tolist()
    t0 = time.process_time()
    for row in actions:
        env.step(row)
    print(json.dumps([time.process_time() - t0, len(actions) * task["robots"]]), flush=True)
"""


class Pogema:
    """POGEMA 1.4 in a subprocess: ``rows`` (its map), ``run(steps)`` -> (CPU seconds, agent-steps)."""

    def __init__(self, python: str, robots: int, side: int, seed: int, collisions: str):
        self.proc = subprocess.Popen([python, "-c", WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        task = {"robots": robots, "side": side, "density": DENSITY, "radius": VIEW_RADIUS, "seed": seed, "collisions": collisions}
        self.rows: list[str] = json.loads(self._ask(json.dumps(task)))
        self.seconds, self.agent_steps = 0.0, 0

    def _ask(self, line: str) -> str:
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()
        answer = self.proc.stdout.readline()
        if not answer:
            raise RuntimeError(f"POGEMA's worker stopped (exit status {self.proc.wait()})")
        return answer

    def run(self, steps: int) -> None:
        seconds, agent_steps = json.loads(self._ask(str(steps)))
        self.seconds += seconds
        self.agent_steps += agent_steps

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def largest_region_cell(rows: list[str]) -> tuple[int, int]:
    """A free cell (x, y) of the largest open region, nearest the centre: the race's exit."""
    h, w = len(rows), len(rows[0])
    seen: set[tuple[int, int]] = set()
    best: list[tuple[int, int]] = []
    for y0 in range(h):
        for x0 in range(w):
            if rows[y0][x0] != "." or (x0, y0) in seen:
                continue
            region, todo = [], deque([(x0, y0)])
            seen.add((x0, y0))
            while todo:
                x, y = todo.popleft()
                region.append((x, y))
                for nx, ny in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                    if 0 <= nx < w and 0 <= ny < h and rows[ny][nx] == "." and (nx, ny) not in seen:
                        seen.add((nx, ny))
                        todo.append((nx, ny))
            best = max(best, region, key=len)
    return min(best, key=lambda c: (abs(c[0] - w // 2) + abs(c[1] - h // 2), c))


def race_on(rows: list[str], robots: int, collisions: str, goals: str = "exit", finished: str = "remove"):
    """The race on POGEMA's map, one exit added (``goals="own"``: each robot its own target instead)."""
    grid = Level.from_grid("\n".join(rows))
    level = Level(width=grid.width, height=grid.height, blocked=grid.blocked, exits={largest_region_cell(rows)})
    return race_v0.parallel_env(level=level, n_robots=robots, collisions=collisions, start="random", observe="local",
                                view_radius=VIEW_RADIUS, max_cycles=EPISODE, goals=goals, finished=finished)


class BatchStepper:
    """The race's batch engine (one env): steps and "local" rows as arrays, CPU time per agent-step
    (every robot counts, finished ones parked as the engine keeps them); a new race when one is over."""

    def __init__(self, env, actions: list[list[int]]):
        self.batch = env.batch(1)
        self.batch.seed([0])
        self.batch.reset_envs([0])
        self.actions, self.done, self.seconds, self.agent_steps = np.array(actions, dtype=np.int64), 0, 0.0, 0

    def run(self, steps: int) -> None:
        batch, rows = self.batch, self.actions[self.done : self.done + steps]
        t0 = time.process_time()
        for row in rows:
            if batch.over[0]:
                batch.reset_envs([0])
            batch.step(row[None, :])
            batch.observations()
        self.seconds += time.process_time() - t0
        self.done += len(rows)
        self.agent_steps += len(rows) * batch.n_robots


def spread(values: list[float], scale: float = 1.0, digits: int = 2) -> str:
    return f"{statistics.median(values) * scale:.{digits}f} [{min(values) * scale:.{digits}f}, {max(values) * scale:.{digits}f}]"


def measure(
    python: str, pairing: str, robots: int, side: int, rounds: int, agent_steps: int, seed: int
) -> dict[str, list[float]]:
    """Per round: CPU seconds per agent-step of the race, the race with own goals, the batch engine and
    POGEMA, and the ratios POGEMA / race and own / exit."""
    theirs, ours_rule = PAIRINGS[pairing]
    pogema = Pogema(python, robots, side, seed, theirs)
    steps = max(20, agent_steps // robots)
    actions = np.random.default_rng(seed).integers(0, 5, (steps * (rounds + 1), robots)).tolist()
    env = race_on(pogema.rows, robots, ours_rule)
    runners = {
        "race": Stepper(env, actions, clock=time.process_time),
        "own": Stepper(race_on(pogema.rows, robots, ours_rule, "own", "stay"), actions, clock=time.process_time),
        "own, leaving": Stepper(race_on(pogema.rows, robots, ours_rule, "own"), actions, clock=time.process_time),
        "batch": BatchStepper(env, actions),
        "pogema": pogema,
    }
    try:
        for runner in runners.values():
            runner.run(max(5, steps // 10))  # warm-up, untimed
        out: dict[str, list[float]] = {name: [] for name in (*runners, "ratio", "own / exit", "leaving / exit", "on board",
                                                             "leaving on board")}  # fmt: skip
        for r in range(rounds):
            order = list(runners.values())[:: 1 if r % 2 == 0 else -1]  # who goes first alternates
            for runner in order:
                runner.seconds = runner.agent_steps = 0
                runner.run(steps)
            for name, runner in runners.items():
                out[name].append(runner.seconds / runner.agent_steps)
            out["ratio"].append(out["pogema"][-1] / out["race"][-1])
            out["own / exit"].append(out["own"][-1] / out["race"][-1])
            out["leaving / exit"].append(out["own, leaving"][-1] / out["race"][-1])
            out["on board"].append(runners["race"].agent_steps / steps)  # robots not yet finished, on average
            out["leaving on board"].append(runners["own, leaving"].agent_steps / steps)
        return out
    finally:
        pogema.close()


def positive(text: str) -> int:
    """An integer >= 1 (``--rounds``, ``--agent-steps``)."""
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"an integer >= 1, got {text!r}")
    return int(text)


def seed(text: str) -> int:
    """An integer >= 0 (``--seed``: POGEMA's seeds are)."""
    if not text.isdigit():
        raise argparse.ArgumentTypeError(f"an integer >= 0, got {text!r}")
    return int(text)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pogema-python", default=os.environ.get("POGEMA_PYTHON"), metavar="PATH",
                   help="the python of a venv with pogema 1.4 (default: $POGEMA_PYTHON)")
    p.add_argument("--quick", action="store_true", help="CI smoke run: one short round, two sizes")
    p.add_argument("--collisions", choices=[*PAIRINGS, "both"], default="both",
                   help="soft: the soft rule in both; default: POGEMA's priority beside the race's block (default: both)")
    p.add_argument("--rounds", type=positive, default=5, help="rounds per size (default: 5)")
    p.add_argument("--agent-steps", type=positive, default=150_000, help="agent-steps per round and env (default: 150,000)")
    p.add_argument("--seed", type=seed, default=0, help="POGEMA's map seed and the actions' (default: 0)")
    args = p.parse_args(argv)
    if not args.pogema_python or not Path(args.pogema_python).exists():
        p.error(f"--pogema-python: the python of a venv with pogema 1.4, got {args.pogema_python!r}; "
                'make one with: python3 -m venv VENV && VENV/bin/pip install "pogema==1.4.*"')
    rounds, agent_steps = (1, 10_000) if args.quick else (args.rounds, args.agent_steps)
    sizes = QUICK_SIZES if args.quick else SIZES
    print(f"race_v0.parallel_env(observe='local', view_radius={VIEW_RADIUS}) beside POGEMA 1.4 (obs_radius={VIEW_RADIUS}), "
          f"POGEMA's random maps at density {DENSITY}, random actions; the race: a new one every {EPISODE} steps")
    print(f"CPU us per agent-step, median [min, max] over {rounds} round(s) of {agent_steps:,} agent-steps each")
    print("race: goals='exit'; own: goals='own', finished='stay' (robots stay on their targets: POGEMA's rule here);")
    print("leaving: goals='own', a robot leaves at its target (finished='remove'); batch: the batch engine (env.batch(1));")
    print("own / exit, leaving / exit: their times over race's; on board: robots still racing, mean over the steps,")
    print("race / leaving (POGEMA and own keep every robot)")
    print(f"{'collisions':>18s} {'robots':>6s} {'map':>6s} {'race':>20s} {'own':>20s} {'leaving':>20s} {'batch':>20s} "
          f"{'POGEMA':>20s} {'POGEMA / race':>18s} {'own / exit':>18s} {'leaving / exit':>18s} {'on board':>13s}")
    for pairing in PAIRINGS if args.collisions == "both" else (args.collisions,):
        theirs, ours_rule = PAIRINGS[pairing]
        for robots, side in sizes:
            got = measure(args.pogema_python, pairing, robots, side, rounds, agent_steps, args.seed)
            times = " ".join(f"{spread(got[name], 1e6):>20s}" for name in ("race", "own", "own, leaving", "batch", "pogema"))
            print(f"{f'{ours_rule} / {theirs}':>18s} {robots:6d} {f'{side}x{side}':>6s} {times} "
                  f"{spread(got['ratio']):>18s} {spread(got['own / exit']):>18s} {spread(got['leaving / exit']):>18s} "
                  f"{statistics.mean(got['on board']):>6.1f} / {statistics.mean(got['leaving on board']):<4.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
