"""``collisions="soft"`` against POGEMA 1.4 itself (``collision_system="soft"``): the same map, starts
and joint random actions stepped in both, positions equal after every step.

POGEMA runs in its own venv (it pins gymnasium 0.28.1), driven over stdin/stdout by
``pogema/driver.py``; ``POGEMA_PYTHON`` names that venv's interpreter (.ci/integrations.sh builds it).

Finishing is matched rather than avoided: our level is POGEMA's map with one exit, every POGEMA
robot's target is that exit cell, and POGEMA's ``on_target="finish"`` hides a robot on its target
the way the race's ``finished="remove"`` takes a finished robot off the board. So robots that
reach the exit leave both boards in the same step, and the comparison runs on through the whole
episode (robots that finish, robots left).
"""

from __future__ import annotations

import json
import os
import subprocess
from collections import deque
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level
from babyrobot_marl.planning import goal_actions

DRIVER = Path(__file__).parent / "pogema" / "driver.py"
POGEMA_PYTHON = os.environ.get("POGEMA_PYTHON")
TO_POGEMA = (0, 1, 4, 2, 3)  # our STAY, NORTH, EAST, SOUTH, WEST as POGEMA's action numbers ((row, column) moves)

pytestmark = pytest.mark.skipif(not POGEMA_PYTHON, reason="POGEMA_PYTHON: POGEMA 1.4's venv (.ci/integrations.sh)")


def random_map(side: int, seed: int, density: float = 0.3) -> list[str]:
    """POGEMA's kind of map: each cell an obstacle with probability ``density``."""
    g = np.random.default_rng(seed)
    return ["".join("#" if g.random() < density else "." for _ in range(side)) for _ in range(side)]


def exit_cell(rows: list[str]) -> tuple[int, int]:
    """A free cell of the largest open region, nearest the centre: (x, y)."""
    h, w = len(rows), len(rows[0])
    seen: set[tuple[int, int]] = set()
    best: list[tuple[int, int]] = []
    for y in range(h):
        for x in range(w):
            if rows[y][x] == "#" or (x, y) in seen:
                continue
            region, todo = [], deque([(x, y)])
            seen.add((x, y))
            while todo:
                cx, cy = todo.popleft()
                region.append((cx, cy))
                for nx, ny in ((cx + 1, cy), (cx - 1, cy), (cx, cy + 1), (cx, cy - 1)):
                    if 0 <= nx < w and 0 <= ny < h and rows[ny][nx] == "." and (nx, ny) not in seen:
                        seen.add((nx, ny))
                        todo.append((nx, ny))
            if len(region) > len(best):
                best = region
    return min(best, key=lambda c: (abs(c[0] - w // 2) + abs(c[1] - h // 2), c))


class Pogema:
    """POGEMA 1.4 in a subprocess of its own venv: ``step(actions)`` -> ``[(x, y, active), ...]``."""

    def __init__(self, rows: list[str], starts: list[tuple[int, int]], target: tuple[int, int] | list[tuple[int, int]],
                 on_target: str = "finish"):
        self.proc = subprocess.Popen(
            [POGEMA_PYTHON, str(DRIVER)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1
        )
        task = {
            "map": rows,
            "agents_xy": [[y, x] for x, y in starts],  # POGEMA: (row, column)
            "targets_xy": [[t[1], t[0]] for t in (target if isinstance(target, list) else [target] * len(starts))],
            "collision_system": "soft",
            "on_target": on_target,
        }
        self.first = self._send(task)

    def _send(self, message: object) -> list[tuple[int, int, bool]]:
        self.proc.stdin.write(json.dumps(message) + "\n")
        line = self.proc.stdout.readline()
        assert line, "POGEMA's driver stopped"
        return [(col, row, active) for row, col, active in json.loads(line)]

    def step(self, actions: list[int]) -> list[tuple[int, int, bool]]:
        return self._send([TO_POGEMA[a] for a in actions])

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def on_board(env) -> list[tuple[int, int, bool]]:
    """Each robot's cell and whether it is still racing, as POGEMA reports its agents."""
    racing = set(env.agents)
    return [(x, y, a in racing) for a, (x, y) in zip(env.possible_agents, env.robot_cells)]


def same_robots(t: int, ours: list[tuple[int, int, bool]], theirs: list[tuple[int, int, bool]]) -> None:
    """After step ``t + 1`` every robot is where POGEMA has it; else the robots that differ."""
    assert theirs == ours, f"step {t + 1}: robots differ: " + ", ".join(
        f"{i}: ours {o}, POGEMA {p}" for i, (o, p) in enumerate(zip(ours, theirs)) if o != p
    )


def step_beside(env, pogema: Pogema, steps: int, actions_for: Callable[[], list[int]],
                ours: Callable[[Any], list[tuple[int, int, bool]]]) -> tuple[int, list[dict]]:  # fmt: skip
    """Steps ``env`` and POGEMA with the same joint actions (``actions_for()``, one per robot) until ``steps`` or
    the race's end, the robots compared after every step (``ours(env)``: ours as POGEMA reports its agents);
    the last step's index and every step's infos."""
    seen, t = [], -1
    try:
        assert pogema.first == on_board(env)
        for t in range(steps):
            if not env.agents:
                break
            actions = actions_for()
            _, _, _, _, infos = env.step({a: actions[i] for i, a in enumerate(env.possible_agents) if a in env.agents})
            seen.append(infos)
            same_robots(t, ours(env), pogema.step(actions))
    finally:
        pogema.close()
    return t, seen


@pytest.mark.parametrize(("n_robots", "side", "steps"), [(8, 16, 1500), (32, 24, 1000), (64, 32, 600), (256, 48, 400)])
def test_soft_collisions_step_as_pogema_does(n_robots, side, steps):
    rows = random_map(side, seed=n_robots)
    grid = Level.from_grid("\n".join(rows))
    target = exit_cell(rows)
    level = Level(width=grid.width, height=grid.height, blocked=grid.blocked, exits={target})
    env = race_v0.parallel_env(level=level, n_robots=n_robots, collisions="soft", start="random", max_cycles=steps + 1)
    env.reset(seed=n_robots)
    pogema = Pogema(rows, list(env.robot_cells), target)
    g = np.random.default_rng(n_robots)
    t, seen = step_beside(env, pogema, steps, lambda: g.integers(0, 5, n_robots).tolist(), on_board)
    blocked = sum(info["blocked"] for infos in seen for info in infos.values())
    finished = n_robots - len(env.agents)
    print(f"{n_robots} robots, {side}x{side}: {t + 1} steps equal, {blocked} stops by robots, {finished} finished")
    assert t + 1 >= min(steps, 300) and blocked >= 100  # long runs, robots stopped by robots all along


@pytest.mark.parametrize(("n_robots", "side", "steps"), [(8, 16, 600), (64, 32, 400), (256, 48, 300)])
def test_robots_that_stay_on_their_own_goals_step_as_pogemas_on_target_nothing(n_robots, side, steps):
    """``goals="own", finished="stay"`` against POGEMA's ``on_target="nothing"``: each robot its own target, most
    moves towards it (so robots reach their targets, stay, and are pushed against), the rest random."""
    rows = random_map(side, seed=n_robots + 1)
    level = Level.from_grid("\n".join(rows))
    env = race_v0.parallel_env(level=level, n_robots=n_robots, collisions="soft", start="random", goals="own",
                               finished="stay", max_cycles=steps + 1)
    env.reset(seed=n_robots)
    goals = [env.goals[a] for a in env.possible_agents]
    towards = [goal_actions(level, g) for g in goals]  # [y, x, action]: optimal moves towards each goal
    pogema = Pogema(rows, list(env.robot_cells), goals, on_target="nothing")
    g = np.random.default_rng(n_robots)

    def actions() -> list[int]:
        chosen = []
        for k, (x, y) in enumerate(env.robot_cells):
            best = np.flatnonzero(towards[k][y, x])
            chosen.append(int(best[0]) if best.size and g.random() < 0.8 else int(g.integers(0, 5)))
        return chosen

    # nobody leaves the board (the race may end: every robot on its goal)
    t, seen = step_beside(env, pogema, steps, actions, lambda e: [(x, y, True) for x, y in e.robot_cells])
    assert env.agents or list(env.robot_cells) == goals  # ended early only when every robot stood on its goal
    on_goal = sum(info["finished"] for infos in seen for info in infos.values())
    print(f"{n_robots} robots, {side}x{side}: {t + 1} steps equal, {on_goal} robot-steps on their goals")
    assert (t + 1 >= min(steps, 100) or not env.agents) and on_goal >= 10 * n_robots  # on their goals, racing on
