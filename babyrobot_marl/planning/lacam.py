"""LaCAM, lazy constraints addition search (Okumura, AAAI 2023; LaCAM2, IJCAI 2023): a planner for robots
with targets of their own (``goals="own"``) that plans the whole episode before the first step, searching
over PIBT's steps.

>>> planner = LaCAM(level, goals, seed=0)        # goals: one (x, y) per robot
>>> plan = planner.solve(starts)                 # every robot's cell at every step, starts first; or None
>>> moves = planner.actions(env.robot_cells)     # or step by step, as with PIBT

Each node of the search is a configuration (one cell per robot). PIBT's step from it gives the next
one; when that leads nowhere new, the search comes back and tries the step again with one more robot
held to a cell of its choosing (first the robot of highest priority, each of its cells in turn, then the
next robot as well, ...), so in the end every combination of moves can be tried. Depth first: the
newest configuration is searched next, and one already seen is searched again rather than added twice
(or, one time in ten, the search starts over from the first, as LaCAM3 does: it gets out of a crowded
corner sooner). The search stops at the first configuration with every robot on its target; the plan is
the way there. With ``horizon=`` a plan longer than that many steps is searched on (LaCAM*: the
shortest known way to each configuration is kept up to date) until one is short enough.

PIBT alone can circle for ever (two robots taking turns on a cell one of them needs to pass); LaCAM
finds a plan whenever one exists, given enough search. The search is capped by ``max_nodes``, the
number of PIBT steps it may try, not by time: the same seed gives the same plan on any machine. On
POGEMA's 128 maze episodes (``benchmarks/bench_pogema_mazes.py --lacam``) it finds a plan within the 128
steps for every one, at 8 to 64 robots (PIBT alone: all robots arrive in 80% of them at 64 robots).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.level import Level
from ..core.rules import Rules
from .pibt import FAR, PIBT, _Step

Cell = tuple[int, int]
RESTART = 0.1  # LaCAM3: a search that comes back to a configuration it knows starts over this often


class _Node:
    """One configuration of the search: the robots' priorities there, the constraints still to try from it
    (a queue of ``((robot, cell), ...)``, each one robot longer than the one it came from), its steps from
    the start by the shortest way known (``g``, through ``parent``), the fewest steps left (``h``) and the
    configurations one step on (``next``)."""

    __slots__ = ("config", "parent", "priority", "order", "tree", "g", "h", "next")

    def __init__(self, config: tuple[int, ...], parent: _Node | None, priority: list[float], h: int):
        self.config, self.parent, self.priority, self.h = config, parent, priority, h
        self.g = 0 if parent is None else parent.g + 1
        self.order = sorted(range(len(config)), key=priority.__getitem__, reverse=True)
        self.tree: deque[tuple[tuple[int, int], ...]] = deque([()])
        self.next: dict[_Node, None] = {}  # in the order found (a set's order would change from run to run)


class LaCAM:
    """The planner of one episode: the level, each robot's target, the search's budget and its seed.

    ``max_nodes``: how many PIBT steps one search may try before it gives up (``solve`` returns None);
    ``horizon``: search on, within ``max_nodes``, while the plan found is longer than this many steps (the
    episode's length, say; None: the first plan found); ``swap``: PIBT's swap technique in those steps
    (see ``PIBT``)."""

    def __init__(self, level: str | Level, goals: Sequence[tuple[int, int]], seed: int | None = None,
                 max_nodes: int = 20_000, horizon: int | None = None, rules: Rules | dict[str, Any] | None = None,
                 swap: bool = True):
        if isinstance(max_nodes, bool) or not isinstance(max_nodes, int) or max_nodes < 1:
            raise ValueError(f"max_nodes: a whole number of PIBT steps, at least 1; got {max_nodes!r}")
        if horizon is not None and (isinstance(horizon, bool) or not isinstance(horizon, int) or horizon < 0):
            raise ValueError(f"horizon: None or a whole number of steps, at least 0; got {horizon!r}")
        self._pibt = pibt = PIBT(level, goals, seed=seed, rules=rules, swap=swap)  # its tables, and the fallback
        if len(set(pibt.goals)) != len(pibt.goals):
            raise ValueError("goals: one (x, y) per robot, no two the same")
        self.table, self.goals, self.swap = pibt.table, pibt.goals, swap
        self.max_nodes, self.horizon = max_nodes, horizon
        self.rng = np.random.default_rng(seed)
        self.nodes = 0  # the PIBT steps the last search tried
        self.fell_back = False  # no plan within the budget: actions() gives PIBT's steps
        self._plan: list[list[Cell]] | None = None
        self._t = 0

    def solve(self, starts: Sequence[tuple[int, int]]) -> list[list[Cell]] | None:
        """The robots' cells at every step from ``starts`` until each stands on its target (the first
        configuration is ``starts``, the last the goals; one robot moves at most one cell a step, no two
        share a cell or trade places), or None if the search tries ``max_nodes`` PIBT steps without one
        (or none exists). With ``horizon``, a plan longer than that is searched on for a shorter one, and
        the shortest found within ``max_nodes`` comes back."""
        here = self._pibt.cell_ids(starts, "starts")
        if len(set(here)) != len(here):
            raise ValueError("starts: one (x, y) per robot, no two the same")
        goal, dist, moves = tuple(self.goals), self._pibt._dist, self._pibt._moves
        n = len(here)
        far = max(max(d[c] for d, c in zip(dist, here)), 1) + 1  # scales the first priorities below one
        first = (self.rng.permutation(n) / max(n, 1)).tolist()  # ties drawn
        root = _Node(tuple(here), None, [(d[c] + f) / far for d, c, f in zip(dist, here, first)], self._h(here))
        open_, seen = [root], {root.config: root}
        best = root if root.config == goal else None
        horizon = FAR if self.horizon is None else self.horizon
        self.nodes = 0
        while open_ and (best is None or best.g > horizon) and self.nodes < self.max_nodes:
            if best is not None and self.rng.random() < 0.01:  # LaCAM3: refine from elsewhere now and then
                open_.append(open_[int(self.rng.integers(len(open_)))])
            node = open_[-1]
            if best is not None and node.g + node.h >= best.g:  # no shorter plan through it
                open_.pop()
                continue
            if not node.tree:
                open_.pop()
                continue
            self.nodes += 1
            config = self._successor(node, self._next_constraints(node, moves))
            if config is None:
                continue
            known = seen.get(config)
            if known is None:
                priority = [p + 1 if c != g else p % 1 for p, c, g in zip(node.priority, config, goal)]
                seen[config] = known = _Node(config, node, priority, self._h(config))
                node.next[known] = None
                if config == goal:
                    best = known
            else:  # seen before: search it again from there (LaCAM2), not a second node
                node.next[known] = None
                if node.g + 1 < known.g:
                    self._shorten(node, best, open_)
                if self.rng.random() < RESTART:
                    known = root
            open_.append(known)
        return None if best is None else self._path(best)

    def _h(self, config: Sequence[int]) -> int:
        return max(d[c] for d, c in zip(self._pibt._dist, config))

    @staticmethod
    def _shorten(node: _Node, best: _Node | None, open_: list[_Node]) -> None:
        """``node`` leads somewhere in fewer steps than known (LaCAM*'s rewiring): pass the shorter way on
        to every configuration reached from there; those that may now lead to a shorter plan are searched
        again."""
        todo = deque([node])
        while todo:
            u = todo.popleft()
            for v in u.next:
                if u.g + 1 < v.g:
                    v.g, v.parent = u.g + 1, u
                    todo.append(v)
                    if best is not None and v.g + v.h < best.g:
                        open_.append(v)

    def actions(self, cells: Sequence[tuple[int, int]]) -> list[int]:
        """One action per robot (``Action`` values) that takes it to its planned cell this step.

        The first call plans the whole episode from ``cells`` (``solve``), the next ones replay the plan
        (STAY once every robot is on its target). If the robots stand anywhere else than the plan says, it
        plans again from there. If a search finds no plan within ``max_nodes``, this and every later step
        are PIBT's (``fell_back`` turns True)."""
        ids = self._pibt.cell_ids(cells)
        here = [tuple(c) for c in cells]
        if self.fell_back:
            return self._pibt.actions(here)
        plan = self._plan
        if plan is None or plan[self._t] != here:
            plan, self._t = self.solve(here), 0
            if plan is None:
                self.fell_back = True
                return self._pibt.actions(here)
            self._plan = plan
        self._t = min(self._t + 1, len(plan) - 1)
        to, cell_id, action_to = plan[self._t], self.table.cell_id, self._pibt._action_to
        return [action_to[c][cell_id(b)] for c, b in zip(ids, to)]

    def _next_constraints(self, node: _Node, moves: list[list[int]]) -> tuple[tuple[int, int], ...]:
        """The next constraints to try from ``node``, after queueing each one-robot-longer set behind it."""
        pins = node.tree.popleft()
        if len(pins) < len(node.config):
            i = node.order[len(pins)]
            options = moves[node.config[i]]
            for k in self.rng.permutation(len(options)).tolist():
                node.tree.append((*pins, (i, options[k])))
        return pins

    def _successor(self, node: _Node, pins: tuple[tuple[int, int], ...]) -> tuple[int, ...] | None:
        """PIBT's step from ``node`` with the pinned robots' cells fixed first, None if they collide."""
        step = _Step(list(node.config), self._pibt._dist, self._pibt._moves, self.rng,
                     self.goals if self.swap else None)
        for i, cell in pins:
            if not step.pin(i, cell):
                return None
        for i in node.order:
            if step.to[i] < 0:
                step.plan(i)
        to, here, standing = step.to, step.here, step.standing
        if len(set(to)) != len(to):  # a robot that found no cell stays where a pinned one goes
            return None
        for i, cell in enumerate(to):  # two robots trading places
            j = standing.get(cell)
            if j is not None and j != i and to[j] == here[i]:
                return None
        return tuple(to)

    def _path(self, node: _Node | None) -> list[list[Cell]]:
        out = []
        while node is not None:
            out.append([self.table.cell_xy(c) for c in node.config])
            node = node.parent
        return out[::-1]
