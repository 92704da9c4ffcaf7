"""Compile a ``Level`` and ``Rules`` once into flat look-up tables.

Cells are numbered ``c = y * width + x``. The simulator (``engine``) and the planning model
(``model``) both read these tables and nothing else, so they cannot disagree.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import NamedTuple

import numpy as np

from .actions import DELTAS, N_ACTIONS
from .level import Cell, Level
from .outcomes import BUMPED, MOVED, STAYED
from .rules import Rules

MAX_SKIDS = N_ACTIONS - 2  # the open directions other than the intended one: at most 3


class TableLists(NamedTuple):
    """The tables as nested Python lists: one robot's step reads these faster than arrays."""

    sure: list[list[tuple[int, int] | None]]  # (next cell, outcome) where no draw is needed
    target: list[list[int]]
    glass: list[list[bool]]
    move_prob: list[float]
    skid: list[list[tuple[int, ...]]]
    reward: list[float]
    is_exit: list[bool]
    glass_pass_prob: float
    exits: frozenset[int]  # the exit cells


class FlatTable(NamedTuple):
    """``Table``'s per-(cell, action) arrays flattened to index ``c * 5 + a``."""

    target: np.ndarray
    code: np.ndarray  # the outcome when nothing is drawn: STAYED, BUMPED or MOVED
    glass: np.ndarray
    move_prob: np.ndarray  # 1.0 for STAY: it never skids
    n_skid: np.ndarray
    skid: np.ndarray  # (cells * 5, MAX_SKIDS)


@dataclass(frozen=True, eq=False)
class Table:
    """A level compiled under some rules. Arrays are indexed by cell id and action.

    ``target[c, a]``  the cell that action ``a`` leads to from ``c`` when nothing goes wrong
                      (``c`` itself for STAY and for a move into a wall, a blocked cell or the border)
    ``glass[c, a]``   that move crosses a glass wall
    ``move_prob[c]``  probability that a move out of ``c`` is not a skid (1.0 off puddles)
    ``skid[c, a, k]`` the ``n_skid[c, a]`` cells a skid may lead to, padded with ``c``
    ``reward[c]``     reward for ending a step in ``c`` (the exit reward on exits)
    ``is_exit[c]``, ``blocked[c]``
    """

    level: Level
    rules: Rules
    target: np.ndarray
    glass: np.ndarray
    move_prob: np.ndarray
    skid: np.ndarray
    n_skid: np.ndarray
    reward: np.ndarray
    is_exit: np.ndarray
    blocked: np.ndarray

    @property
    def width(self) -> int:
        return self.level.width

    @property
    def height(self) -> int:
        return self.level.height

    @property
    def n_cells(self) -> int:
        return self.level.n_cells

    @cached_property
    def free_cells(self) -> tuple[int, ...]:
        """Ids of ``level.free_cells()``: worked out once per table, shared by the envs built on it."""
        return tuple(self.cell_id(c) for c in self.level.free_cells())

    @cached_property
    def lists(self) -> TableLists:
        skid = [[tuple(self.skid[c, a, : self.n_skid[c, a]].tolist()) for a in range(N_ACTIONS)] for c in range(self.n_cells)]
        return TableLists(
            _sure_outcomes(self),
            self.target.tolist(),
            self.glass.tolist(),
            self.move_prob.tolist(),
            skid,
            self.reward.tolist(),
            self.is_exit.tolist(),
            self.rules.glass_pass_prob,
            frozenset(np.flatnonzero(self.is_exit).tolist()),
        )

    @cached_property
    def sure_flat(self) -> tuple[np.ndarray, np.ndarray]:
        """``lists.sure`` as two flat arrays indexed by ``c * 5 + a``: the next cell (-1 where the
        step needs a random draw) and the outcome code (-1 there too). One ``take`` steps a batch."""
        f = self.flat
        actions = np.tile(np.arange(N_ACTIONS), self.n_cells)
        drawn = (actions > 0) & ((f.move_prob < 1.0) | f.glass)  # a skid or a glass wall: drawn at step time
        nxt, code = np.where(drawn, -1, f.target), np.where(drawn, -1, f.code).astype(np.int64)
        nxt.setflags(write=False)
        code.setflags(write=False)
        return nxt, code

    @cached_property
    def flat(self) -> FlatTable:
        """The per-(cell, action) tables as flat arrays indexed by ``c * 5 + a`` (for batches)."""

        n = self.n_cells
        cells = np.repeat(np.arange(n), N_ACTIONS)
        actions = np.tile(np.arange(N_ACTIONS), n)
        target = self.target.reshape(-1)
        code = np.where(actions == 0, STAYED, np.where(target == cells, BUMPED, MOVED))
        move_prob = np.where(actions == 0, 1.0, self.move_prob[cells])  # STAY never skids
        arrays = (target.copy(), code, self.glass.reshape(-1).copy(), move_prob, self.n_skid.reshape(-1).copy(),
                  self.skid.reshape(n * N_ACTIONS, -1).copy())
        for arr in arrays:
            arr.setflags(write=False)
        return FlatTable(*arrays)

    def cell_id(self, cell: Cell) -> int:
        return cell[1] * self.level.width + cell[0]

    def cell_xy(self, c: int) -> Cell:
        return (c % self.level.width, c // self.level.width)


def compile_level(level: Level, rules: Rules | None = None) -> Table:
    """Build the look-up tables of ``level`` under ``rules`` (default ``Rules()``).

    Cached: the last ``COMPILED_CACHE`` (level, rules) pairs are compiled once and their table
    shared, by every env built from them (its arrays are read-only; what a table derives on first
    use, such as ``lists``, is shared with it). ``compile_level.cache_clear()`` empties the cache.
    """
    return _compiled(level, level.name, Rules() if rules is None else rules)


COMPILED_CACHE = 16  # tables of 256x256 mazes weigh tens of megabytes each


@lru_cache(maxsize=COMPILED_CACHE)
def _compiled(level: Level, name: str, rules: Rules) -> Table:  # name: equal levels may carry other names
    return _compile(level, rules)


compile_level.cache_clear = _compiled.cache_clear  # type: ignore[attr-defined]
compile_level.cache_info = _compiled.cache_info  # type: ignore[attr-defined]


def _compile(level: Level, rules: Rules) -> Table:
    w, n = level.width, level.n_cells
    target = np.tile(np.arange(n, dtype=np.int64)[:, None], (1, N_ACTIONS))
    glass = np.zeros((n, N_ACTIONS), dtype=bool)
    skid = np.tile(np.arange(n, dtype=np.int64)[:, None, None], (1, N_ACTIONS, MAX_SKIDS))
    n_skid = np.zeros((n, N_ACTIONS), dtype=np.int64)
    move_prob = np.ones(n)
    reward = np.full(n, rules.floor_reward)
    is_exit = np.zeros(n, dtype=bool)
    blocked = np.zeros(n, dtype=bool)

    def cid(cell: Cell) -> int:
        return cell[1] * w + cell[0]

    for cell in level.blocked:
        blocked[cid(cell)] = True
    for cell in level.small_puddles:
        move_prob[cid(cell)] = rules.small_puddle_move_prob
        reward[cid(cell)] = rules.small_puddle_reward
    for cell in level.large_puddles:
        move_prob[cid(cell)] = rules.large_puddle_move_prob
        reward[cid(cell)] = rules.large_puddle_reward
    for cell in level.exits:
        is_exit[cid(cell)] = True
        reward[cid(cell)] = rules.exit_reward
    for cell, r in level.rewards:
        reward[cid(cell)] = r

    _moves(level, blocked, target, glass, skid, n_skid)
    for arr in (target, glass, move_prob, skid, n_skid, reward, is_exit, blocked):
        arr.setflags(write=False)
    return Table(level, rules, target, glass, move_prob, skid, n_skid, reward, is_exit, blocked)


def _moves(level: Level, blocked: np.ndarray, target: np.ndarray, glass: np.ndarray, skid: np.ndarray,
           n_skid: np.ndarray) -> None:
    """Fill each open cell's move targets, glass flags and skid cells (the open, glassless directions other than
    the intended one, in action order), as arrays: a Python loop per cell took most of an atlas's building."""
    w, h, n = level.width, level.height, level.n_cells
    direction = {d: a for a, d in enumerate(DELTAS) if a}
    walled = np.zeros((n, N_ACTIONS), dtype=bool)
    behind_glass = np.zeros((n, N_ACTIONS), dtype=bool)
    for edges, mark in ((level.walls, walled), (level.glass, behind_glass)):
        for a, b in edges:
            d = (b[0] - a[0], b[1] - a[1])
            mark[a[1] * w + a[0], direction[d]] = mark[b[1] * w + b[0], direction[(-d[0], -d[1])]] = True
    cells = np.arange(n)
    xs, ys = cells % w, cells // w
    open_ = np.zeros((n, N_ACTIONS), dtype=bool)
    for a in range(1, N_ACTIONS):
        x, y = xs + DELTAS[a][0], ys + DELTAS[a][1]
        inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        nxt = np.where(inside, y * w + x, cells)
        open_[:, a] = inside & ~blocked[nxt] & ~walled[:, a] & ~blocked
        target[:, a] = np.where(open_[:, a], nxt, cells)
        glass[:, a] = open_[:, a] & behind_glass[:, a]
    clear = open_ & ~glass  # where a skid may lead
    for a in range(1, N_ACTIONS):
        others = clear[:, 1:].copy()
        others[:, a - 1] = False
        order = np.argsort(~others, axis=1, kind="stable")  # the open directions first, in action order
        n_skid[:, a] = others.sum(1)
        picked = np.take_along_axis(np.where(others, target[:, 1:], cells[:, None]), order, 1)[:, :MAX_SKIDS]
        skid[:, a] = picked


def _sure_outcomes(t: Table) -> list[list[tuple[int, int] | None]]:
    """``(next cell, outcome)`` of every cell and action whose step draws no random number."""

    out: list[list[tuple[int, int] | None]] = []
    for c in range(t.n_cells):
        row: list[tuple[int, int] | None] = [(c, STAYED)]
        for a in range(1, N_ACTIONS):
            dest = int(t.target[c, a])
            if t.move_prob[c] < 1.0 or t.glass[c, a]:
                row.append(None)  # a skid or a glass wall: drawn at step time
            else:
                row.append((dest, BUMPED if dest == c else MOVED))
        out.append(row)
    return out
