"""Own goals (``goals="own"``): every robot has its own target cell, as in POGEMA.

With own goals a level's exits are ordinary floor (``own_goal_table``): a robot finishes when it
stands on its own target, and another robot's target is floor too. What lives here:

- ``own_goal_table``: the compiled level with its exits as floor (the floor reward, no finishing).
- ``Reach``: which cells a robot can reach from where (the one-robot moves, other robots ignored),
  and the free cells goals and random starts are drawn from (not blocked, no puddle).
- ``draw_goals``: one goal per robot from a generator: free, distinct, reachable from the robot's
  start and not that start.
- ``GoalDistances``: moves to a goal cell from every cell (breadth-first, one search per goal
  cell, kept), for the goal hint.
- ``GoalColumns``: what observations add for own goals (the goal's ``[x, y]``, or a local
  window's target channel, then the hint).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Collection, Sequence
from dataclasses import dataclass, fields
from functools import cached_property, lru_cache

import numpy as np

from .actions import N_ACTIONS
from .table import COMPILED_CACHE, Table

GOAL_MODES = ("exit", "own")
HINT_BITS = N_ACTIONS  # the goal hint: one bit per action


@dataclass(frozen=True, eq=False)
class OwnGoalTable(Table):
    """A level compiled for own goals: no exits (they are floor), random starts from ``Reach.free``."""

    @cached_property
    def free_cells(self) -> tuple[int, ...]:
        return reach(self).free


@lru_cache(maxsize=COMPILED_CACHE)
def own_goal_table(table: Table) -> OwnGoalTable:
    """``table`` with its exits as floor cells: the floor reward (or the level's own reward there), never finishing."""
    if isinstance(table, OwnGoalTable):
        return table
    reward = table.reward.copy()
    custom = {table.cell_id(cell) for cell, _ in table.level.rewards}
    for c in np.flatnonzero(table.is_exit).tolist():
        if c not in custom:
            reward[c] = table.rules.floor_reward
    is_exit = np.zeros_like(table.is_exit)
    for arr in (reward, is_exit):
        arr.setflags(write=False)
    parts = {f.name: getattr(table, f.name) for f in fields(table)}
    return OwnGoalTable(**{**parts, "reward": reward, "is_exit": is_exit})


@dataclass(frozen=True, eq=False)
class Reach:
    """The cells connected by one robot's moves (walls, blocked cells and never-passing glass cut them).

    ``component[c]``: cell ``c``'s part of the level (-1 blocked); ``members[k]``: the free cells
    (not blocked, no puddle) of part ``k``, ascending; ``free``: the free cells of parts holding
    two or more, where a robot can start and still have a goal to go to.
    """

    component: np.ndarray
    members: tuple[tuple[int, ...], ...]
    member_arrays: tuple[np.ndarray, ...]  # ``members`` as arrays: a shuffled part is one gather
    free: tuple[int, ...]
    neighbours: tuple[tuple[int, ...], ...]  # the cells one move leads to from each cell
    part_of: tuple[int, ...]  # ``component`` as Python ints: read once per robot when goals are drawn


@lru_cache(maxsize=COMPILED_CACHE)
def reach(table: Table) -> Reach:
    """``table``'s ``Reach`` (cached per table)."""
    n = table.n_cells
    passes = table.rules.glass_pass_prob > 0
    target, glass = table.target.tolist(), table.glass.tolist()
    neighbours = tuple(
        tuple(d for d, g in zip(target[c][1:], glass[c][1:]) if d != c and (passes or not g)) for c in range(n)
    )
    blocked = table.blocked.tolist()
    component = [-1] * n
    parts: list[list[int]] = []
    for c in range(n):
        if blocked[c] or component[c] >= 0:
            continue
        k, todo, part = len(parts), [c], [c]
        component[c] = k
        while todo:
            for d in neighbours[todo.pop()]:
                if component[d] < 0:
                    component[d] = k
                    todo.append(d)
                    part.append(d)
        parts.append(part)
    puddle = (table.move_prob < 1.0).tolist()
    members = tuple(tuple(sorted(c for c in part if not puddle[c])) for part in parts)
    free = tuple(sorted(c for m in members if len(m) > 1 for c in m))
    comp = np.array(component, dtype=np.int64)
    comp.setflags(write=False)
    arrays = tuple(np.array(m, dtype=np.int64) for m in members)
    for a in arrays:
        a.setflags(write=False)
    return Reach(comp, members, arrays, free, neighbours, tuple(component))


def draw_goals(rng: np.random.Generator, table: Table, starts: Sequence[int]) -> list[int]:
    """One goal cell per robot (robot ``i`` starts at ``starts[i]``): free, distinct, reachable from its start
    and not its start, drawn from ``rng`` (same generator state, same goals).

    Each part of the level is shuffled once (``rng.permutation``, in the order robots first need it)
    and robots take its cells in turn, skipping their own start. A ``ValueError`` naming ``goals`` when
    a part has no cell left for a robot.
    """
    r = reach(table)
    part_of, member_arrays = r.part_of, r.member_arrays
    # part -> [the first of its cells shuffled, its size, cells handed out, robots given a goal there]; robots
    # take at most one more cell than there are robots, so only those are listed
    parts: dict[int, list] = {}
    goals, most = [0] * len(starts), len(starts) + 1
    for i, s in enumerate(starts):
        k = part_of[s]
        part = parts.get(k)
        if part is None:
            cells = member_arrays[k]
            part = parts[k] = [cells.take(rng.permutation(len(cells))[:most]).tolist(), len(cells), 0, []]
        cells, size, p, owner = part
        if p < size and cells[p] == s:  # its own start: take the next, leaving the start for others
            if p + 1 < size:
                cells[p], cells[p + 1] = cells[p + 1], cells[p]
            elif owner:  # the last cell left is its start: trade with a robot served before
                j = owner[0]
                cells[p], goals[j] = goals[j], s
        if p >= size or cells[p] == s:
            x, y = table.cell_xy(s)
            raise ValueError(
                f"goals: no free cell is left for the robot starting at ({x}, {y}): its part of the level has "
                f"{size} free cells for {len(owner) + 1} robots' goals"
            )
        goals[i] = cells[p]
        part[2] = p + 1
        owner.append(i)
    return goals


def next_goal(rng: np.random.Generator, table: Table, cell: int, taken: Collection[int]) -> int:
    """A new goal for a robot on ``cell`` that reached its goal (``lifelong=True``): a free cell reachable
    from ``cell``, not ``cell`` and none of ``taken`` (the other robots' goals), drawn from ``rng``.

    Uniform over those cells: a few draws from the whole part of the level, else one from what is
    left; a part with no other free cell left gives the robot any other free cell of it (shared).
    """
    r = reach(table)
    members = r.members[int(r.component[cell])]
    for _ in range(_TRIES):
        c = members[int(rng.integers(len(members)))]
        if c != cell and c not in taken:
            return c
    left = [c for c in members if c != cell and c not in taken] or [c for c in members if c != cell]
    return left[int(rng.integers(len(left)))]


_TRIES = 8  # draws from the whole part before listing the cells left (a crowded part)


def goal_step(table: Table, cell: int, goal: int) -> int:
    """The first action of a shortest path from ``cell`` to ``goal`` (the lowest-numbered of ties); STAY on
    the goal or when it is out of reach: the shortest-path robot of own goals."""
    bits = goal_hints(table, np.array(cell), np.array(goal))
    return int(np.argmax(bits)) if bits.any() else 0


class GoalDistances:
    """Moves from every cell to a goal cell (-1 where the goal is out of reach), one breadth-first search
    per goal cell the first time it is asked for, kept for the table's lifetime (``rows``, one per goal)."""

    def __init__(self, table: Table):
        self.table = table
        self.row_of = np.full(table.n_cells, -1, dtype=np.int64)  # goal cell -> its row in ``rows``
        self.rows = self._store = np.zeros((0, table.n_cells), dtype=np.int32)  # rows: the filled part of the store
        self._neighbours = reach(table).neighbours

    def rows_for(self, goals: np.ndarray) -> np.ndarray:
        """The rows of ``goals`` (any shape), searching the goal cells not seen before."""
        rows = self.row_of[goals]
        if np.count_nonzero(rows < 0):
            new = np.unique(np.asarray(goals)[rows < 0]).tolist()
            n, store = len(self.rows), self._store
            if n + len(new) > len(store):  # grown by doubling: goals added a few at a time cost linear time, not quadratic
                store = np.zeros((max(2 * len(store), n + len(new), 8), store.shape[1]), dtype=np.int32)
                store[:n] = self.rows
                self._store = store
            store[n : n + len(new)] = [self._search(g) for g in new]
            self.rows = store[: n + len(new)]
            self.row_of[new] = np.arange(n, n + len(new))
            rows = self.row_of[goals]
        return rows

    def _search(self, goal: int) -> list[int]:
        # moves are symmetric (walls and glass block both ways), so the search from the goal outwards
        dist = [-1] * self.table.n_cells
        dist[goal] = 0
        todo, nb = deque([goal]), self._neighbours
        while todo:
            c = todo.popleft()
            d = dist[c] + 1
            for e in nb[c]:
                if dist[e] < 0:
                    dist[e] = d
                    todo.append(e)
        return dist


@lru_cache(maxsize=COMPILED_CACHE)
def goal_distances(table: Table) -> GoalDistances:
    """The shared ``GoalDistances`` of ``table`` (every env on it adds to the same rows)."""
    return GoalDistances(table)


def goal_hints(table: Table, cells: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """``(..., HINT_BITS)`` 0/1: the actions that shorten the way to each robot's goal by one move
    (shortest paths in moves; none on the goal itself or where the goal is out of reach)."""
    dist = goal_distances(table)
    rows = dist.rows_for(goals)
    here = dist.rows[rows, cells][..., None]
    ahead = dist.rows[rows[..., None], table.target[cells]]  # STAY's target is the cell itself: never shorter
    return ((ahead == here - 1) & (here > 0)).astype(np.int64)


def target_channel(
    table: Table, cells: np.ndarray, goals: np.ndarray, radius: int, out: np.ndarray | None = None, column: int = 0
) -> np.ndarray:
    """``(..., (2r+1)^2)`` 0/1: the local window's target channel, as POGEMA's: 1 on the goal's cell when
    it lies in the window, else on the window's border cell its offset projects to (each of ``dx``,
    ``dy`` clamped to ``-r..r``); rows north to south, west to east, as the window's cells.
    ``out``: C-contiguous int64 rows ``(..., m)`` to write the channel into, at columns ``column`` on."""
    key, where, one_hot = channel_tables(table.width, table.height, radius)
    at = where.take(key.take(goals) - key.take(cells))  # the goal's clamped offset, by two look-ups
    if out is None:
        return one_hot.take(at, axis=0)
    out[..., column : column + one_hot.shape[0]] = one_hot.take(at, axis=0)
    return out


def mark_targets(
    out: np.ndarray, cells: np.ndarray, goals: np.ndarray, width: int, height: int, radius: int, column: int
) -> None:
    """``target_channel`` written into rows whose channel columns (``column`` on) are 0 already: one
    number per row (a local observer's pass). ``out``: C-contiguous rows ``(..., m)``."""
    key = cell_keys(width, height)
    mark_offsets(out, goal_offsets(key, cells, key.take(goals)), channel_where(width, height, radius), column)


def goal_offsets(cell_key: np.ndarray, cells: np.ndarray, goal_keys: np.ndarray) -> np.ndarray:
    """Each goal's offset from its robot's cell, as a key difference (``cell_key``: ``cell_keys`` of the
    grid; ``goal_keys``: of the goals, kept while they stay): 0 exactly where a robot stands on its goal,
    and what ``channel_marks`` reads the target channel from."""
    return goal_keys - cell_key.take(cells)


def channel_marks(offsets: np.ndarray, where: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Where the target channel's 1 goes in each row, as flat indices into C-contiguous rows, from the
    goals' offsets (``goal_offsets``), ``where`` (``channel_where`` of the grid and radius) and ``starts``
    (``row_starts``: the flat index of each row's channel): a local observer puts 1 there."""
    at = where.take(offsets)  # intp offsets into an intp table: no casts
    at += starts
    return at


def mark_offsets(out: np.ndarray, offsets: np.ndarray, where: np.ndarray, column: int) -> None:
    """``mark_targets`` from the goals' offsets (``goal_offsets``), when the caller has them already."""
    starts = row_starts(offsets.size, out.shape[-1], column)
    out.put(channel_marks(offsets, where, starts if offsets.ndim == 1 else starts.reshape(offsets.shape)), 1)


@lru_cache(maxsize=COMPILED_CACHE)
def cell_keys(w: int, h: int) -> np.ndarray:
    """Each cell's key ``y * (2W - 1) + x`` on a ``w x h`` grid (``channel_tables``'s) as ``intp``: goal minus
    cell is one number per offset, 0 only on the goal itself, and indexes ``channel_where`` without a cast."""
    keys = channel_tables(w, h, 0)[0].astype(np.intp)
    keys.setflags(write=False)
    return keys


@lru_cache(maxsize=COMPILED_CACHE)
def channel_where(w: int, h: int, radius: int) -> np.ndarray:
    """``channel_tables``'s channel cell of each key difference as ``intp``: flat indices add to it without a cast."""
    where = channel_tables(w, h, radius)[1].astype(np.intp)
    where.setflags(write=False)
    return where


@lru_cache(maxsize=16)
def row_starts(n: int, m: int, column: int) -> np.ndarray:
    """``column`` of each of ``n`` rows of ``m`` numbers, as flat indices (kept: asked for every step)."""
    starts = np.arange(column, n * m, m)
    starts.setflags(write=False)
    return starts


@lru_cache(maxsize=COMPILED_CACHE)
def channel_tables(w: int, h: int, radius: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """On a ``w x h`` grid: each cell's key ``y * (2W - 1) + x``; the channel's cell of each key difference
    ``dy * (2W - 1) + dx`` (``(2H - 1) * (2W - 1)`` of them, one per offset: negative ones read from the
    end); and one-hot rows."""
    side = 2 * radius + 1
    ids = np.arange(w * h, dtype=np.int64)
    key = (ids // w * (2 * w - 1) + ids % w).astype(_small_int((2 * h - 1) * (2 * w - 1)))
    dx, dy = np.r_[0:w, -w + 1 : 0], np.r_[0:h, -h + 1 : 0]  # index k holds offset d (k - len for the tail)
    clamp_x, clamp_y = np.clip(dx, -radius, radius) + radius, np.clip(dy, -radius, radius) + radius
    where = np.empty((2 * h - 1) * (2 * w - 1), dtype=_small_int(side * side))  # small: read every step
    where[(dy[:, None] * (2 * w - 1) + dx[None, :]).ravel()] = (clamp_y[:, None] * side + clamp_x[None, :]).ravel()
    one_hot = np.eye(side * side, dtype=np.int64)
    for a in (key, where, one_hot):
        a.setflags(write=False)
    return key, where, one_hot


def _small_int(n: int) -> type:
    """The smallest signed int type holding ``-n .. n``."""
    return next(t for t in (np.int16, np.int32, np.int64) if n <= np.iinfo(t).max)


@dataclass(frozen=True, eq=False)
class GoalColumns:
    """The columns own goals add to each robot's observation row: "global" and "nearest" the goal's
    ``[x, y]``; "local" the target channel (``target_channel``), then with ``hint`` the goal hint."""

    radius: int | None  # "local": the window's radius; None: the goal's [x, y]
    hint: bool
    width: int  # of the observation space (a family of levels: the largest)
    height: int

    @property
    def nvec(self) -> list[int]:
        part = [self.width, self.height] if self.radius is None else [2] * (2 * self.radius + 1) ** 2
        return part + [2] * (HINT_BITS if self.hint else 0)

    @property
    def size(self) -> int:  # len(nvec), without building it (read every step)
        return (2 if self.radius is None else (2 * self.radius + 1) ** 2) + (HINT_BITS if self.hint else 0)

    def __call__(
        self, table: Table, cells: np.ndarray, goals: np.ndarray, out: np.ndarray | None = None, written: bool = False
    ) -> np.ndarray:
        """``(..., n, size)`` int64 from each robot's cell and goal cell, ``(..., n)``, on ``table``; ``out``:
        rows ``(..., n, m)`` whose last ``size`` columns to fill instead (returned); ``written``: the goal's
        columns of ``out`` are filled already (an observer given the goals), only the hint is left."""
        cells, goals = np.asarray(cells, dtype=np.int64), np.asarray(goals, dtype=np.int64)
        if out is None:
            out = np.empty((*cells.shape, self.size), dtype=np.int64)
        size = self.size
        first = out.shape[-1] - size  # the goal's columns, then the hint's
        hint = first + size - (HINT_BITS if self.hint else 0)
        if written:  # the observer's pass wrote them
            pass
        elif self.radius is None:
            out[..., first:hint] = cell_xy(table)[goals]
        else:
            target_channel(table, cells, goals, self.radius, out, first)
        if self.hint:
            out[..., hint:] = goal_hints(table, cells, goals)
        return out


@lru_cache(maxsize=COMPILED_CACHE)
def cell_xy(table: Table) -> np.ndarray:
    """``(cells, 2)`` int64: each cell's ``[x, y]``."""
    ids = np.arange(table.n_cells, dtype=np.int64)
    xy = np.stack([ids % table.width, ids // table.width], axis=1)
    xy.setflags(write=False)
    return xy
