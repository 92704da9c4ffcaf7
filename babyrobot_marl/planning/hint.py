"""The goal hint (``hint=True`` on the race envs): in each cell, the optimal actions of one robot.

``optimal_actions(level)`` is ``uint8[H, W, 5]``, 1 where the action (``Action`` order: STAY,
NORTH, EAST, SOUTH, WEST) is optimal for the one-robot model of the level (value iteration on
``model(level, rules)``, ties within the planner's ``tie_tol``; other robots ignored), 0 on
exits, blocked cells and cells that reach no exit. It is what POGEMA-style learned agents get as
their goal direction. Planned once per level and rules (cached): an env on a fixed level plans
it once, an env drawing levels plans each new one.

``goal_actions(level, goal)`` is the hint of own goals (``goals="own"``): the actions that start a
shortest path to one cell, from a breadth-first search per goal cell (``core.goals``), kept.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from ..core.goals import goal_hints, own_goal_table
from ..core.level import Level
from ..core.rules import Rules, resolve_rules
from ..core.table import compile_level
from ..levels.resolve import resolve_level
from .checks import check_hint_rules
from .dp import value_iteration
from .mdp import model

HINT_CACHE = 64  # levels whose hints are kept (a family of mazes draws a new one at most resets)


def optimal_actions(level: str | Level, rules: Rules | dict[str, Any] | None = None) -> np.ndarray:
    """``uint8[H, W, 5]``: 1 where the action is optimal from that cell for one robot (read-only, cached).

    A ``ValueError`` naming the reward if a cell kind of the level rewards a robot (``> 0``): then no
    optimum is finite."""
    level, rules = resolve_level(level), resolve_rules(rules, {})
    check_hint_rules(level, rules)
    return _optimal(level, rules)


def goal_actions(level: str | Level, goal: tuple[int, int], rules: Rules | dict[str, Any] | None = None) -> np.ndarray:
    """``uint8[H, W, 5]``: 1 where the action starts a shortest path (in moves, one robot alone) to the
    cell ``goal``, the hint a robot gets with ``goals="own"``; 0 on the goal, blocked cells and cells
    that cannot reach it. The exits are floor. One breadth-first search per goal cell, kept."""
    table = own_goal_table(compile_level(resolve_level(level, need_exit=False), resolve_rules(rules, {})))
    cells = np.arange(table.n_cells)
    hints = goal_hints(table, cells, np.full_like(cells, table.cell_id(goal)))
    return hints.astype(np.uint8).reshape(table.height, table.width, -1)


@lru_cache(maxsize=HINT_CACHE)
def _optimal(level: Level, rules: Rules) -> np.ndarray:
    best = value_iteration(model(level, rules)).best_actions.astype(np.uint8)
    best.setflags(write=False)  # shared by every env on this level
    return best
