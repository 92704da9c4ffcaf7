"""Writes benchmarks/data/pogema_mazes.json: POGEMA's 128 validation mazes and their starts and goals.

Run by a Python that has POGEMA 1.4 and pogema-toolbox 0.1.1 (they pin gymnasium 0.28.1: a venv
of their own). ``bench_pogema_mazes.py --regenerate --pogema-python PY`` runs it and checks that
the shipped file is what it writes.

- Mazes: pogema-toolbox's ``MazeGenerator`` with the benchmark's settings (``MazeRangeSettings``
  with widths and heights 17..21, the other ranges at their defaults) and seeds 0..127, the maps
  ``validation-mazes-seed-000`` .. ``-127`` of POGEMA's benchmark (02-mazes/maps.yaml).
- Starts and goals: POGEMA's own generator, as the benchmark's MAPF runs draw them
  (02-mazes-mapf.yaml: ``seed: 0``, ``on_target: nothing``, ``collision_system: soft``,
  ``max_episode_steps: 128``, ``observation_type: MAPF``), at each robot count.

Starts and goals are flat lists ``[x0, y0, x1, y1, ...]``, ``(x, y)`` = POGEMA's (column, row)
without its border (this package's cell of the same name in ``Level.from_grid(grid)``).
"""

from __future__ import annotations

import json
import sys

from pogema import GridConfig, pogema_v0
from pogema_toolbox.generators.maze_generator import MazeGenerator, MazeRangeSettings

SEEDS = range(128)
ROBOTS = (8, 16, 24, 32, 48, 64)
SETTINGS = MazeRangeSettings(width_min=17, width_max=21, height_min=17, height_max=21)


def maze(seed: int) -> str:
    return MazeGenerator.generate_maze(**SETTINGS.sample(seed))


def scenario(grid: str, n_agents: int) -> dict[str, list[int]]:
    config = GridConfig(map=grid, num_agents=n_agents, seed=0, on_target="nothing", collision_system="soft",
                        max_episode_steps=128, observation_type="MAPF")
    env = pogema_v0(grid_config=config)
    env.reset(seed=0)
    starts = env.grid.get_agents_xy(ignore_borders=True)
    goals = env.grid.get_targets_xy(ignore_borders=True)
    return {"starts": [int(v) for r, c in starts for v in (c, r)], "goals": [int(v) for r, c in goals for v in (c, r)]}


def main() -> None:
    mazes = {f"validation-mazes-seed-{s:03d}": maze(s) for s in SEEDS}
    data = {
        "source": "POGEMA benchmark 02-mazes (MAPF): pogema-toolbox 0.1.1 mazes, POGEMA 1.4 starts and goals, seed 0",
        "robots": list(ROBOTS),
        "mazes": [
            {"name": name, "grid": grid, "scenarios": {str(n): scenario(grid, n) for n in ROBOTS}}
            for name, grid in mazes.items()
        ],
    }
    json.dump(data, sys.stdout, separators=(",", ":"))


if __name__ == "__main__":
    main()
