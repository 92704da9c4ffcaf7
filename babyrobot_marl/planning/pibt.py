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

Two robots that meet head on in a corridor cannot pass by pushing: one would park on the other's
target for ever. With ``swap=True`` (the default; LaCAM*'s swap technique, Okumura 2024) the one in
front backs off, pulling the other behind it, until a junction lets them trade places: on POGEMA's
maze benchmark this lifts the share of episodes in which all 32 robots arrive from 0.41 to 0.98.

``actions(cells, preferences)`` takes one score per action for each robot (a policy's action
probabilities, or one for the action it chose): each robot then tries its cells in that order,
equal scores nearest first, and the planner only keeps the moves from colliding (a collision
shield over a learnt crowd, as CS-PIBT, Veerapaneni et al. 2024).

A centralised planner, not a learnt crowd: it is the yardstick the learnt ones are read against on
POGEMA's maze benchmark (``benchmarks/bench_pogema_mazes.py --pibt``). Same seed, same plan (ties
between equally near cells are drawn from the planner's own generator).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.goals import goal_distances, own_goal_table
from ..core.level import Level
from ..core.rules import Rules, resolve_rules
from ..core.table import compile_level
from ..levels.resolve import resolve_level

FAR = 1 << 30  # the distance of a cell from which the target is out of reach


class PIBT:
    """The planner of one episode: the level, each robot's target and the robots' priorities."""

    def __init__(self, level: str | Level, goals: Sequence[tuple[int, int]], seed: int | None = None,
                 rules: Rules | dict[str, Any] | None = None, swap: bool = True):
        self.table = table = own_goal_table(compile_level(resolve_level(level, need_exit=False), resolve_rules(rules, {})))
        self.goals = [table.cell_id(tuple(g)) for g in goals]
        dist = goal_distances(table)
        which = dist.rows_for(np.array(self.goals, dtype=np.int64))  # searches new goals first: then read the rows
        self._dist = [[d if d >= 0 else FAR for d in row] for row in dist.rows[which].tolist()]
        # per cell: the cells one action reaches, STAY's first (a move into a wall is STAY), and the action to each
        self._action_to = [{t: a for a, t in reversed(list(enumerate(row)))} for row in table.target.tolist()]
        self._moves = [sorted(to, key=to.__getitem__) for to in self._action_to]
        self.swap = swap
        self.rng = np.random.default_rng(seed)
        # a fraction below one apart from every other robot's: the order among robots on their targets
        self.priority = (self.rng.permutation(len(self.goals)) / max(len(self.goals), 1)).tolist()

    def actions(self, cells: Sequence[tuple[int, int]], preferences: Any = None) -> list[int]:
        """One action per robot (``Action`` values) that takes it to its planned cell this step.

        ``preferences``: one score per action for each robot (``[n_robots, 5]``, higher first: a policy's
        action probabilities, say); each robot then tries its cells in that order instead of nearest first,
        equal scores nearest first, and the planner only keeps the moves from colliding (a collision shield
        over a learnt policy: give the action it chose a score of one and the others zero)."""
        here = self.cell_ids(cells)
        for i, (c, g) in enumerate(zip(here, self.goals)):
            self.priority[i] = self.priority[i] + 1 if c != g else self.priority[i] % 1
        rank = None if preferences is None else self._ranks(here, preferences)
        step = _Step(here, self._dist, self._moves, self.rng, self.goals if self.swap else None, rank)
        for i in sorted(range(len(here)), key=self.priority.__getitem__, reverse=True):
            if step.to[i] < 0:
                step.plan(i)
        return [self._action_to[c][t] for c, t in zip(here, step.to)]

    def cell_ids(self, cells: Sequence[tuple[int, int]], name: str = "cells") -> list[int]:
        """The level's cell ids of one (x, y) per robot, checked to be one per robot (``name``: the argument)."""
        if len(cells) != len(self.goals):
            raise ValueError(f"{name}: one (x, y) per robot, {len(self.goals)} robots; got {len(cells)}")
        return [self.table.cell_id(tuple(c)) for c in cells]

    def _ranks(self, here: list[int], preferences: Any) -> list[dict[int, float]]:
        """Per robot: each cell it can reach, keyed by minus the best score of the actions that reach it."""
        scores = np.asarray(preferences, dtype=np.float64)
        if scores.shape != (len(self.goals), N_ACTIONS):
            raise ValueError(f"preferences: one score per action ({N_ACTIONS}) for each of the {len(self.goals)} "
                             f"robots, shape ({len(self.goals)}, {N_ACTIONS}); got shape {scores.shape}")
        targets = self.table.target[here]  # [n, 5]: the cell each action reaches
        rank: list[dict[int, float]] = []
        for row, to in zip(scores.tolist(), targets.tolist()):
            best: dict[int, float] = {}
            for score, cell in zip(row, to):
                best[cell] = min(best.get(cell, -score), -score)
            rank.append(best)
        return rank


class _Step:
    """One step's reservations: where each robot stands, where it goes (-1: not planned yet)."""

    def __init__(self, here: list[int], dist: list[list[int]], moves: list[list[int]], rng: np.random.Generator,
                 goals: list[int] | None = None, rank: list[dict[int, float]] | None = None):
        self.here, self.dist, self.moves, self.rng, self.goals = here, dist, moves, rng, goals
        self.rank = rank  # per robot, cell -> its place in the robot's own order (lower first); None: nearest first
        self.standing = {c: i for i, c in enumerate(here)}
        self.taken: dict[int, int] = {}  # cell -> the robot that goes there
        self.to = [-1] * len(here)

    def pin(self, i: int, cell: int) -> bool:
        """Send robot ``i`` to ``cell`` before anyone plans (LaCAM's constraints); False if another robot
        already goes there or comes into ``i``'s cell from it."""
        j = self.standing.get(cell)
        if cell in self.taken or (j is not None and j != i and self.to[j] == self.here[i]):
            return False
        self.to[i], self.taken[cell] = cell, i
        return True

    def plan(self, i: int) -> bool:
        """Give robot ``i`` a cell, asking whoever stands there to move first; False if it must stay."""
        here = self.here[i]
        dist, rank = self.dist[i], None if self.rank is None else self.rank[i]
        options = self.moves[here]
        order = self.rng.permutation(len(options)).tolist()  # ties drawn, then nearest first (preferred first)
        if rank is None:
            options = [options[k] for k in sorted(order, key=lambda k: dist[options[k]])]
        else:
            options = [options[k] for k in sorted(order, key=lambda k: (rank[options[k]], dist[options[k]]))]
        partner = self._swap_partner(i, options[0]) if self.goals is not None else None
        if partner is not None:  # a head-on meeting in a corridor: back off, pulling the other robot along
            options.reverse()
        for k, cell in enumerate(options):
            if cell in self.taken:
                continue
            j = self.standing.get(cell)
            if j is not None and self.to[j] == here:  # it comes into this robot's cell: a swap
                continue
            self.to[i], self.taken[cell] = cell, i
            if j is not None and j != i and self.to[j] < 0 and not self.plan(j):
                continue  # it could not make way: the next cell
            if partner is not None and k == 0 and self.to[partner] < 0 and here not in self.taken:
                self.to[partner], self.taken[here] = here, partner
            return True
        self.to[i], self.taken[here] = here, i
        return False

    # The swap technique of LaCAM* (Okumura, AAMAS 2024): two robots meeting head-on in a corridor cannot
    # pass by pushing, so the one in front walks backwards until a junction lets them trade places.

    def _swap_partner(self, i: int, best: int) -> int | None:
        """The robot ``i`` should pull behind it instead of pushing, if any."""
        here, standing = self.here[i], self.standing
        j = standing.get(best)
        if (j is not None and j != i and self.to[j] < 0 and self._swap_required(i, j, here, self.here[j])
                and self._swap_possible(self.here[j], here)):
            return j
        if best != here:  # clearing the way: a robot behind that would have to pass through this one
            for cell in self.moves[here]:
                k = standing.get(cell)
                if (k is not None and k != i and self.here[k] != best and self._swap_required(k, i, here, best)
                        and self._swap_possible(best, here)):
                    return k
        return None

    def _exits(self, cell: int, came_from: int) -> tuple[int, int]:
        """How many ways lead on from ``cell`` (not back, not into a dead end held by its robot's target),
        and one of them."""
        n, last = 0, -1
        for u in self.moves[cell]:
            if u in (cell, came_from):
                continue
            k = self.standing.get(u)
            if k is not None and self.goals[k] == u and len(self.moves[u]) == 2:
                continue
            n, last = n + 1, u
        return n, last

    def _swap_required(self, pusher: int, puller: int, at_pusher: int, at_puller: int) -> bool:
        dist = self.dist[pusher]
        while dist[at_puller] < dist[at_pusher]:
            n, ahead = self._exits(at_puller, at_pusher)
            if n >= 2:
                return False  # a junction ahead: the puller can step aside there
            if n == 0:
                break
            at_pusher, at_puller = at_puller, ahead
        back = self.dist[puller]
        return back[at_pusher] < back[at_puller] and (dist[at_pusher] == 0 or dist[at_puller] < dist[at_pusher])

    def _swap_possible(self, at_pusher: int, at_puller: int) -> bool:
        start = at_pusher
        while at_puller != start:
            n, ahead = self._exits(at_puller, at_pusher)
            if n >= 2:
                return True
            if n == 0:
                return False
            at_pusher, at_puller = at_puller, ahead
        return False
