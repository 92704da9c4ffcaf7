"""POGEMA 1.4 stepped over stdin/stdout, run by POGEMA's own venv (it pins gymnasium 0.28.1).

The first line of stdin is a JSON task: ``map`` (rows of "." and "#"), ``agents_xy`` and
``targets_xy`` (POGEMA's (row, column), no border), ``collision_system``, ``on_target``. Every
further line is a JSON list of POGEMA actions, one per agent; after the reset and after each
step the driver prints one JSON line: ``[[row, column, active], ...]`` per agent.
"""

import json
import sys

from pogema import GridConfig, pogema_v0


def positions(env):
    grid = env.grid
    xy = grid.get_agents_xy(ignore_borders=True)
    return [[int(x), int(y), bool(grid.is_active[i])] for i, (x, y) in enumerate(xy)]


def main():
    task = json.loads(sys.stdin.readline())
    config = GridConfig(
        map="\n".join(task["map"]),
        agents_xy=[tuple(p) for p in task["agents_xy"]],
        targets_xy=[tuple(p) for p in task["targets_xy"]],
        collision_system=task["collision_system"],
        on_target=task["on_target"],
        obs_radius=task.get("obs_radius", 2),
        max_episode_steps=task.get("max_episode_steps", 10**9),
    )
    env = pogema_v0(grid_config=config)
    env.reset()
    print(json.dumps(positions(env)), flush=True)
    for line in sys.stdin:
        env.step(json.loads(line))
        print(json.dumps(positions(env)), flush=True)


if __name__ == "__main__":
    sys.setrecursionlimit(100_000)  # POGEMA reverts chains of robots recursively
    main()
