"""POGEMA's maze benchmark in this package: its 128 validation mazes, its starts and goals, its metrics.

    python benchmarks/bench_pogema_mazes.py            # 128 mazes x 8, 16, 32, 48, 64 robots
    python benchmarks/bench_pogema_mazes.py --quick    # 4 mazes, 8 robots (no POGEMA needed)
    python benchmarks/bench_pogema_mazes.py --regenerate --pogema-python PATH   # check the shipped data

The mazes (21x21 at most) and the starts and goals of POGEMA's benchmark (02-mazes, MAPF) ship in
``benchmarks/data/pogema_mazes.json``, made by ``pogema_mazes_data.py`` with pogema-toolbox's maze
generator and POGEMA 1.4's own start and goal generator (seed 0). Each maze is read with
``Level.from_grid`` and raced as ``race_v0.parallel_env(goals="own", collisions="soft",
max_cycles=128)``, the benchmark's starts and goals given by ``reset(options=...)``.

The robots are shortest-path robots: each follows a shortest path to its own goal as if alone (the
lowest-numbered action among the optimal ones, ``planning.goal_actions``), stops only when the
soft rule stops it. A robot leaves the board when it reaches its goal (POGEMA's
``on_target="finish"``); the published runs use ``on_target="nothing"`` (robots stay on their
targets and still block), so the two rules differ for robots that would pass over a finished
robot's target. Metrics are POGEMA's, named as ``babyrobot-marl evaluate`` names them:
``all_reached_rate`` (CSR), ``success_rate`` (ISR), ``sum_of_costs`` and ``makespan``, with 95%
intervals (Wilson for rates, over mazes for CSR and robots for ISR; normal for means).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level
from babyrobot_marl.experiments.evaluate import METRICS, Episode, crowd_metrics
from babyrobot_marl.planning import goal_actions

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "pogema_mazes.json"
MAKER = HERE / "pogema_mazes_data.py"
STEPS = 128
ROBOTS = (8, 16, 32, 48, 64)
QUICK_MAZES, QUICK_ROBOTS = 4, (8,)
SOURCE = "POGEMA's benchmark results (2025), 128 validation mazes, 128 steps, soft collisions"
PUBLISHED = {  # CSR (all robots reached) at 32 / 64 robots
    "LaCAM": (1.00, 0.91),
    "MAPF-GPT-DDG": (1.00, 0.82),
    "MAPF-GPT-85M": (0.97, 0.70),
    "SCRIMP": (0.55, 0.15),
    "DCC": (0.36, 0.02),
}


def load_mazes(path: Path = DATA) -> list[dict]:
    """The shipped mazes: ``name``, ``grid`` (rows of ``.`` and ``#``) and per robot count its flat
    ``starts`` and ``goals`` (``[x0, y0, x1, y1, ...]``)."""
    return json.loads(path.read_text())["mazes"]


def cells(flat: list[int]) -> list[tuple[int, int]]:
    return list(zip(flat[0::2], flat[1::2]))


@lru_cache(maxsize=256)
def level_of(grid: str) -> Level:
    """The maze as a level. One exit is added on its first free cell: with own goals an exit is
    plain floor (no reward, no finishing), and a level needs one to be built."""
    maze = Level.from_grid(grid)
    free = min((y, x) for y in range(maze.height) for x in range(maze.width) if (x, y) not in maze.blocked)
    return Level(width=maze.width, height=maze.height, blocked=maze.blocked, exits={free[::-1]})


@lru_cache(maxsize=4096)
def path_actions(grid: str, goal: tuple[int, int]) -> np.ndarray:
    """``int[H, W]``: a shortest-path robot's action toward ``goal`` (the lowest optimal; STAY on it)."""
    best = goal_actions(level_of(grid), goal)
    return np.where(best.any(axis=2), best.argmax(axis=2), 0)


def race(grid: str, starts: list[tuple[int, int]], goals: list[tuple[int, int]]) -> Episode:
    """One episode of shortest-path robots: each robot's finishing step (0: not in ``STEPS`` steps)."""
    env = race_v0.parallel_env(level=level_of(grid), n_robots=len(starts), goals="own", collisions="soft",
                               observe="nearest", k=1, start="random", max_cycles=STEPS)
    env.reset(seed=0, options={"starts": starts, "goals": goals})
    tables = [path_actions(grid, g) for g in goals]
    finish = [0] * len(starts)
    names = {a: i for i, a in enumerate(env.possible_agents)}
    t = 0
    while env.agents:
        t += 1
        moves = {a: int(tables[names[a]][env.robot_cells[names[a]][::-1]]) for a in env.agents}
        _, _, terminated, _, _ = env.step(moves)
        for a, done in terminated.items():
            if done:
                finish[names[a]] = t
    return Episode(seed=0, level=grid, steps=t, finish_steps=finish)


def run(mazes: list[dict], robots: tuple[int, ...]) -> dict[int, dict[str, float]]:
    """POGEMA's metrics with their intervals per robot count, over the given mazes."""
    out = {}
    for n in robots:
        episodes = []
        for m in mazes:
            s = m["scenarios"][str(n)]
            episodes.append(race(m["grid"], cells(s["starts"]), cells(s["goals"])))
        out[n] = crowd_metrics(episodes, n, STEPS)
    return out


def table(results: dict[int, dict[str, float]], n_mazes: int) -> str:
    """Our metrics per robot count (value [low, high]), then the published CSR with its source."""
    lines = [f"shortest-path robots on {n_mazes} of POGEMA's validation mazes, {STEPS} steps, soft collisions, "
             "a robot leaves at its goal; 95% intervals in brackets",
             f"{'robots':>6}  {'CSR (all_reached_rate)':<24}{'ISR (success_rate)':<24}{'sum of costs':<26}makespan"]
    for n, m in results.items():
        cols = [_shown(m, k, 2 if k.endswith("rate") else 1) for k in ("all_reached_rate", "success_rate",
                                                                         "sum_of_costs", "makespan")]
        lines.append(f"{n:>6}  {cols[0]:<24}{cols[1]:<24}{cols[2]:<26}{cols[3]}")
    ours = {n: results[n]["all_reached_rate"] for n in (32, 64) if n in results}
    lines += ["", f"CSR at 32 / 64 robots ({SOURCE}):"]
    for name, (a, b) in PUBLISHED.items():
        lines.append(f"  {name:<28}{a:.2f} / {b:.2f}")
    if ours:
        shown = " / ".join(f"{ours[n]:.2f}" if n in ours else "-" for n in (32, 64))
        lines.append(f"  {'shortest-path robots (ours)':<28}{shown}")
    return "\n".join(lines)


def _shown(m: dict[str, float], k: str, digits: int) -> str:
    return f"{m[k]:.{digits}f} [{m[k + '_low']:.{digits}f}, {m[k + '_high']:.{digits}f}]"


def regenerate(python: str) -> str:
    """The data file as POGEMA's venv writes it now (``pogema_mazes_data.py``)."""
    done = subprocess.run([python, str(MAKER)], capture_output=True, text=True, check=False)
    if done.returncode:
        raise SystemExit(f"--pogema-python: {MAKER.name} failed: {done.stderr.strip().splitlines()[-1:]}")
    return done.stdout


def refuse_policy(path: str) -> str:
    """The one line that says why a saved policy cannot run here (its file checked first)."""
    from babyrobot_marl.training.policy import load_checkpoint

    try:
        data = load_checkpoint(path)
    except ValueError as err:
        return f"--policy: {str(err).removeprefix('policy: ')}"
    if data.get("goals", "exit") != "own":
        return (f"--policy: {path!r} was trained for the race to the exits; the benchmark needs a policy "
                "trained with own goals, which 'babyrobot-marl train' cannot train yet")
    return f"--policy: {path!r}: policies trained with own goals are not run by this benchmark yet"


def counts(text: str) -> tuple[int, ...]:
    allowed = (8, 16, 24, 32, 48, 64)
    try:
        values = tuple(int(v) for v in text.split(","))
    except ValueError:
        values = ()
    if not values or any(v not in allowed for v in values):
        raise argparse.ArgumentTypeError(f"robot counts from {', '.join(map(str, allowed))}, comma-separated; "
                                         f"got {text!r}")
    return values


def n_mazes(text: str) -> int:
    if not text.isdigit() or not 1 <= int(text) <= 128:
        raise argparse.ArgumentTypeError(f"an integer from 1 to 128, got {text!r}")
    return int(text)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--robots", type=counts, default=ROBOTS, help="robot counts (default: 8,16,32,48,64)")
    p.add_argument("--mazes", type=n_mazes, default=128, help="the first N of the 128 mazes (default: 128)")
    p.add_argument("--quick", action="store_true", help=f"CI smoke run: {QUICK_MAZES} mazes, 8 robots")
    p.add_argument("--policy", metavar="FILE", help="a policy saved by 'babyrobot-marl train' (own goals)")
    p.add_argument("--json", action="store_true", help="end with one JSON line of the metrics")
    p.add_argument("--regenerate", action="store_true",
                   help="make the data again with POGEMA's venv (--pogema-python) and compare with the shipped file")
    p.add_argument("--pogema-python", default=os.environ.get("POGEMA_PYTHON"), metavar="PATH",
                   help="the python of a venv with pogema 1.4 and pogema-toolbox 0.1.1 (for --regenerate)")
    args = p.parse_args(argv)
    if args.policy is not None:
        p.exit(2, refuse_policy(args.policy) + "\n")
    if args.regenerate:
        if not args.pogema_python or not Path(args.pogema_python).is_file():
            p.error(f"--pogema-python: the python of a venv with pogema 1.4 and pogema-toolbox, "
                    f"got {args.pogema_python!r}")
        same = json.loads(regenerate(args.pogema_python)) == json.loads(DATA.read_text())
        print(f"{DATA.name}: {'the same as' if same else 'DIFFERENT from'} what POGEMA's venv makes now")
        if not same:
            return 1
    mazes, robots = load_mazes()[: QUICK_MAZES if args.quick else args.mazes], QUICK_ROBOTS if args.quick else args.robots
    results = run(mazes, robots)
    print(table(results, len(mazes)))
    if args.json:
        print(json.dumps({str(n): {k: m[k] for k in m if k.split("_low")[0].split("_high")[0] in METRICS}
                          for n, m in results.items()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
