"""PIBT, priority inheritance with backtracking (Okumura et al., Artificial Intelligence 2022): a planner
for robots with targets of their own (``goals="own"``), one step at a time.

>>> planner = PIBT(level, goals, seed=0)          # goals: one (x, y) per robot
>>> moves = planner.actions(env.robot_cells)     # each step: one action per robot, in robot order

Each step every robot asks for the cell next to it (or its own) nearest its target, in order of
priority: a robot's priority grows by one each step it stands off its target and falls back below
one when it arrives. A robot that asks for a cell another robot stands on makes that robot plan
first (it inherits the asker's priority); if that robot finds no cell, the asker tries its next one.
The moves never collide (no two robots end in one cell, no two swap), so every collision rule steps
them alike, as long as moves are sure (no puddles, no glass walls in the way).

A centralised planner, not a learnt crowd: it is the yardstick the learnt ones are read against on
POGEMA's maze benchmark (``benchmarks/bench_pogema_mazes.py --pibt``), where LaCAM, first in POGEMA's
tables, is a search over PIBT's steps. Same seed, same plan (ties between equally near cells are
drawn from the planner's own generator).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.goals import goal_distances, own_goal_table
from ..core.level import Level
from ..core.rules import Rules, resolve_rules
from ..core.table import compile_level
from ..levels.resolve import resolve_level

FAR = 1 << 30  # the distance of a cell from which the target is out of reach


class PIBT:
    """The planner of one episode: the level, each robot's target and the robots' priorities."""

    def __init__(self, level: str | Level, goals: Sequence[tuple[int, int]], seed: int | None = None,
                 rules: Rules | dict[str, Any] | None = None):
        self.table = table = own_goal_table(compile_level(resolve_level(level, need_exit=False), resolve_rules(rules, {})))
        self.goals = [table.cell_id(tuple(g)) for g in goals]
        dist = goal_distances(table)
        which = dist.rows_for(np.array(self.goals, dtype=np.int64))  # searches new goals first: then read the rows
        self._dist = [[d if d >= 0 else FAR for d in row] for row in dist.rows[which].tolist()]
        # per cell: the cells one action reaches, STAY's first (a move into a wall is STAY), and the action to each
        self._action_to = [{t: a for a, t in reversed(list(enumerate(row)))} for row in table.target.tolist()]
        self._moves = [sorted(to, key=to.__getitem__) for to in self._action_to]
        self.rng = np.random.default_rng(seed)
        # a fraction below one apart from every other robot's: the order among robots on their targets
        self.priority = (self.rng.permutation(len(self.goals)) / max(len(self.goals), 1)).tolist()

    def actions(self, cells: Sequence[tuple[int, int]]) -> list[int]:
        """One action per robot (``Action`` values) that takes it to its planned cell this step."""
        if len(cells) != len(self.goals):
            raise ValueError(f"cells: one (x, y) per robot, {len(self.goals)} robots; got {len(cells)}")
        here = [self.table.cell_id(tuple(c)) for c in cells]
        for i, (c, g) in enumerate(zip(here, self.goals)):
            self.priority[i] = self.priority[i] + 1 if c != g else self.priority[i] % 1
        step = _Step(here, self._dist, self._moves, self.rng)
        for i in sorted(range(len(here)), key=self.priority.__getitem__, reverse=True):
            if step.to[i] < 0:
                step.plan(i)
        return [self._action_to[c][t] for c, t in zip(here, step.to)]


class _Step:
    """One step's reservations: where each robot stands, where it goes (-1: not planned yet)."""

    def __init__(self, here: list[int], dist: list[list[int]], moves: list[list[int]], rng: np.random.Generator):
        self.here, self.dist, self.moves, self.rng = here, dist, moves, rng
        self.standing = {c: i for i, c in enumerate(here)}
        self.taken: dict[int, int] = {}  # cell -> the robot that goes there
        self.to = [-1] * len(here)

    def plan(self, i: int) -> bool:
        """Give robot ``i`` a cell, asking whoever stands there to move first; False if it must stay."""
        here, dist = self.here[i], self.dist[i]
        options = self.moves[here]
        order = self.rng.permutation(len(options)).tolist()  # ties drawn, then nearest first
        for k in sorted(order, key=lambda k: dist[options[k]]):
            cell = options[k]
            if cell in self.taken:
                continue
            j = self.standing.get(cell)
            if j is not None and self.to[j] == here:  # it comes into this robot's cell: a swap
                continue
            self.to[i], self.taken[cell] = cell, i
            if j is not None and j != i and self.to[j] < 0 and not self.plan(j):
                continue  # it could not make way: the next cell
            return True
        self.to[i], self.taken[here] = here, i
        return False
