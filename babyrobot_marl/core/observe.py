"""What a race robot observes: pure functions from the robots' cells to ``MultiDiscrete`` rows.

Three modes (``OBSERVE_MODES``), each a row per robot beginning with the robot's own ``[x, y]``:

- ``"global"``: then ``[x, y, finished]`` of every other robot, robots ``i+1, ..., n-1, 0, ..., i-1``
  (``n`` robots: ``3n - 1`` numbers, so a step costs O(n^2)); ``global_observations`` builds them
  for the batch engine, ``race_v0`` gathers its own by ``global_gather``.
- ``"local"``: then a ``(2r+1) x (2r+1)`` window centred on the robot (``r = view_radius``),
  rows from north to south, west to east within a row, each cell ``LOCAL_FEATURES``:
  terrain (``TERRAIN``: floor, small puddle, large puddle, blocked or outside the grid, exit),
  another racing robot there (0/1), then the edge on each side, north, east, south, west
  (``EDGE``: open, wall, glass). Cells outside the grid are blocked with walls on every side.
- ``"nearest"``: then ``[dx + W - 1, dy + H - 1]`` of the ``k`` nearest other racing robots
  (Manhattan distance, ties to the lower robot number), nearest first; missing ones (fewer than
  ``k`` others racing) are ``[2W - 1, 2H - 1]`` (``nearest_nvec``'s last values).

Finished robots are off the board: nobody sees them in "local" or "nearest" windows; a finished
robot still observed (``finished="freeze"``) sees from the exit it took. Both modes cost O(n)
memory per step: the level's part of a local window is precomputed once per (table, radius)
(``local_view``, cached), the robots are put on a scratch grid each step; nearest robots are
found by brute force for a few robots, else by searching rings of cells around each robot.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np

from .checks import check_nearest_k, check_view_radius, shown
from .goals import channel_where, mark_targets
from .nearest import nearest_nvec, nearest_observations
from .table import Table

OBSERVE_MODES = ("global", "local", "nearest")
LOCAL_FEATURES = ("terrain", "robot", "north", "east", "south", "west")
TERRAIN = {"floor": 0, "small puddle": 1, "large puddle": 2, "blocked": 3, "exit": 4}
EDGE = {"open": 0, "wall": 1, "glass": 2}
_LOCAL_NVEC = (len(TERRAIN), 2, len(EDGE), len(EDGE), len(EDGE), len(EDGE))
_ROBOT = 1  # the column of the robot feature


def global_gather(n: int) -> np.ndarray:
    """Where the "global" rows gather from the flat state ``[x0, y0, finished0, x1, ...]``: robot
    ``i`` sees its ``[x, y]``, then ``[x, y, finished]`` of robots ``i+1, ..., i-1`` (mod ``n``)."""
    if n == 0:
        return np.zeros((0, 0), dtype=np.intp)
    i = np.arange(n, dtype=np.intp)[:, None]
    others = (i + np.arange(1, n, dtype=np.intp)) % n  # (n, n - 1)
    rows = np.concatenate([3 * i, 3 * i + 1, (3 * others[:, :, None] + np.arange(3)).reshape(n, 3 * (n - 1))], axis=1)
    return rows


@lru_cache(maxsize=64)
def _small_gather(n: int) -> np.ndarray:
    g = global_gather(n)
    g.setflags(write=False)  # shared by every caller
    return g


_WINDOWS_FROM = 24  # robots from which copying windows beats the gather (measured: even at 16-24, 1.2x at 64, 1.9x at 256)


def global_observations(xyf: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """The "global" rows, ``(..., n, 3n - 1)`` int64, from every robot's ``[x, y, finished]``, ``(..., n, 3)``
    (leading dimensions: separate races): robot ``i``'s ``[x, y]``, then ``[x, y, finished]`` of robots
    ``i+1, ..., n-1, 0, ..., i-1``. ``out``: a C-contiguous int64 array of that shape to write into.

    Few robots: one gather by a small cached index. Many: robot ``i``'s others are the state written
    twice over, from robot ``i+1`` on, so each row is one contiguous copy of a window of that
    doubled state (a zero-copy view), with no ``n x 3n`` index to read.
    """
    xyf = np.asarray(xyf, dtype=np.int64)
    *lead, n, _ = xyf.shape
    races = math.prod(lead)  # not np.prod: microseconds count at 1 env x 4 robots
    shape = (*lead, n, 3 * n - 1)
    flat = xyf.reshape(races, 3 * n)
    if out is None:
        if n < _WINDOWS_FROM:
            return flat.take(_small_gather(n), axis=1).reshape(shape)
        out = np.empty(shape, dtype=np.int64)
    elif out.shape != shape or out.dtype != np.int64 or not out.flags.c_contiguous:
        raise ValueError(f"out: expected a C-contiguous int64 array of shape {shape}, got {out.dtype} {out.shape}")
    rows = out.reshape(races, n, 3 * n - 1)  # a view: out is C-contiguous
    if n < _WINDOWS_FROM:
        np.take(flat, _small_gather(n), axis=1, out=rows, mode="clip")  # "clip": unbuffered, indices all valid
        return out
    rows[:, :, :2] = xyf.reshape(races, n, 3)[:, :, :2]
    twice = np.concatenate([flat, flat], axis=1)
    rows[:, :, 2:] = np.lib.stride_tricks.sliding_window_view(twice, 3 * (n - 1), axis=1)[:, 3 : 3 * n + 1 : 3]
    return out


class Recycler:
    """Large output arrays handed out again once nobody but this holds them (no fresh pages per step).

    Past ``RECYCLE_FROM`` bytes the allocator maps every new array afresh, and the kernel zeroes
    each page before numpy writes it: at 4 envs x 1,000 robots that doubles the cost of the 96 MB
    of "global" observations. An array is handed out again only when the reference count shows
    that the caller dropped it and every view of it (a view holds its base; so does anything
    sharing its memory through the buffer protocol): arrays a caller keeps are never written.
    The last ``keep`` arrays are held (two: a loop holds the last step's while asking for the next).
    Off where reference counts do not exist (interpreters other than CPython).
    """

    RECYCLE_FROM = 32 << 20  # glibc's largest mmap threshold: smaller freed blocks are reused by malloc

    def __init__(self, keep: int = 2):
        self.keep = keep
        self._held: list[np.ndarray] = []
        self._on = sys.implementation.name == "cpython" and hasattr(sys, "getrefcount")
        probe = [np.empty(1)]
        self._alone = sys.getrefcount(probe[0]) if self._on else -1  # the count of an array held by _held alone

    def __getstate__(self) -> dict[str, int]:
        return {"keep": self.keep}  # a pickled env carries no spare arrays (96 MB each at 4 x 1,000)

    def __setstate__(self, state: dict[str, int]) -> None:
        self.__init__(state["keep"])  # reference counts are the unpickling interpreter's

    def recycles(self, shape: tuple[int, ...], dtype: type = np.int64) -> bool:
        """Whether arrays of ``shape`` are recycled (else ``empty`` is ``np.empty``)."""
        return self._on and math.prod(shape) * np.dtype(dtype).itemsize >= self.RECYCLE_FROM

    def empty(self, shape: tuple[int, ...], dtype: type = np.int64) -> np.ndarray:
        """A C-contiguous array of ``shape``, its contents undefined: a recycled one when one is free."""
        if not self.recycles(shape, dtype):
            return np.empty(shape, dtype=dtype)
        held = self._held
        for i in range(len(held)):
            if sys.getrefcount(held[i]) == self._alone and held[i].shape == shape and held[i].dtype == dtype:
                held.append(held.pop(i))  # the newest now: recycled last
                return held[-1]
        held.append(np.empty(shape, dtype=dtype))
        if len(held) > self.keep:
            del held[0]  # the oldest, held by its caller now (or freed)
        return held[-1]


@dataclass(frozen=True, eq=False)
class LocalView:
    """The level's part of every local window of radius ``radius``, on a grid padded by it."""

    radius: int
    width: int
    height: int
    static: np.ndarray  # (padded cells, 6) features, the robot column 0
    padded: np.ndarray  # (cells,) each cell's index in the padded grid
    window: np.ndarray  # ((2r+1)^2,) offsets of a window's cells from its centre, in the padded grid
    xy: np.ndarray  # (cells, 2) each cell's [x, y]

    @property
    def size(self) -> int:
        """Numbers per observation: ``[x, y]`` and six per window cell."""
        return 2 + len(LOCAL_FEATURES) * self.window.size

    @property
    def nvec(self) -> np.ndarray:
        return np.array([self.width, self.height, *(_LOCAL_NVEC * self.window.size)], dtype=np.int64)

    @cached_property
    def channel_where(self) -> np.ndarray:
        """Own goals' target channel: its cell for each goal offset (``goals.channel_where``), kept here
        because every step reads it."""
        return channel_where(self.width, self.height, self.radius)


@lru_cache(maxsize=32)
def local_view(table: Table, radius: int) -> LocalView:
    """The precomputed level part of local windows (cached: shared by every env on ``table``)."""
    level, r = table.level, radius
    w, h = level.width, level.height
    pw, ph = w + 2 * r, h + 2 * r
    grid = np.zeros((ph, pw, len(LOCAL_FEATURES)), dtype=np.int64)
    grid[:, :, 0] = TERRAIN["blocked"]  # outside: blocked, walls all round
    grid[:, :, 2:] = EDGE["wall"]
    inner = grid[r : r + h, r : r + w]
    inner[:, :, 2:] = EDGE["open"]
    inner[0, :, 2], inner[-1, :, 4], inner[:, -1, 3], inner[:, 0, 5] = (EDGE["wall"],) * 4  # the border
    inner[:, :, 0] = TERRAIN["floor"]
    for kind, cells in (("small puddle", level.small_puddles), ("large puddle", level.large_puddles)):
        for x, y in cells:
            inner[y, x, 0] = TERRAIN[kind]
    for x, y in level.blocked:
        inner[y, x, 0] = TERRAIN["blocked"]
    for c in np.flatnonzero(table.is_exit).tolist():  # the table's: with own goals the exits are floor
        inner[c // w, c % w, 0] = TERRAIN["exit"]
    for kind, edges in (("wall", level.walls), ("glass", level.glass)):
        for (ax, ay), (bx, by) in edges:  # a < b: b is east of a, or south of it
            if by == ay:
                inner[ay, ax, 3] = inner[by, bx, 5] = EDGE[kind]
            else:
                inner[ay, ax, 4] = inner[by, bx, 2] = EDGE[kind]
    ids = np.arange(w * h)
    x, y = ids % w, ids // w
    d = np.arange(-r, r + 1)
    window = (d[:, None] * pw + d[None, :]).ravel()
    static = grid.reshape(-1, len(LOCAL_FEATURES))
    for a in (static, window):
        a.setflags(write=False)
    return LocalView(r, w, h, static, (y + r) * pw + (x + r), window, np.stack([x, y], axis=1))


def local_observations(
    view: LocalView,
    cells: np.ndarray,
    racing: np.ndarray,
    extra: int = 0,
    goals: np.ndarray | None = None,
    marks: np.ndarray | None = None,
) -> np.ndarray:
    """``(..., n, view.size)`` int64 rows from cells and racing flags of shape ``(..., n)``
    (leading dimensions: separate races, e.g. the envs of a batch); ``extra`` more columns at the
    end of each row, zeros for the caller to fill (own goals' columns: no copy to append them).
    ``goals`` (own goals, each robot's target cell, ``(..., n)``): the extra columns begin with the
    target channel (``goals.target_channel``), written in this pass; ``marks``: where each row's 1 goes
    (``goals.channel_marks``), when the caller has them (own goals' steps do; one race only)."""
    cells, racing = np.asarray(cells), np.asarray(racing, dtype=bool)
    if cells.ndim == 1 and (out := _one_race(view, cells, racing, extra, goals, marks)) is not None:
        return out
    *lead, n = cells.shape
    n_races = math.prod(lead)  # not np.prod: microseconds count every step
    cells2, racing2 = cells.reshape(n_races, n), racing.reshape(n_races, n)
    size = view.size + extra
    rows = level_rows(view, extra)
    if rows is not None:  # each robot's row as the level makes it, in one gather
        out = rows.take(cells2, axis=0).astype(np.int64, copy=False)
    else:
        out = np.zeros((n_races, n, size), dtype=np.int64)
        out[:, :, :2] = view.xy.take(cells2, axis=0)
        feats = out[:, :, 2 : view.size].reshape(n_races, n, view.window.size, len(LOCAL_FEATURES))  # a view: rows split
        feats[...] = view.static.take(_window_indices(view, cells2), axis=0, mode="clip")  # "clip": no bounds checks
    if n > 1:  # a lone robot sees no other: its robot column stays 0
        _robots_seen(view, cells2, racing2, out[:, :, 2 + _ROBOT : view.size : len(LOCAL_FEATURES)])
    if marks is not None:
        out.put(marks, 1)
    elif goals is not None:
        mark_targets(out, cells2, goals, view.width, view.height, view.radius, view.size)
    return out.reshape(*lead, n, size)


def _one_race(
    view: LocalView, cells: np.ndarray, racing: np.ndarray, extra: int, goals: np.ndarray | None, marks: np.ndarray | None
) -> np.ndarray | None:
    """``local_observations`` of one race (``cells`` 1-d) from the level's tables, without reshaping; None
    when the level has no tables (wide windows on large levels)."""
    rows, around = level_rows(view, extra), window_cells(view)
    if rows is None or around is None:
        return None
    out = rows.take(cells, axis=0).astype(np.int64, copy=False)
    if len(cells) > 1:  # a lone robot sees no other: its robot column stays 0
        robot = out[:, 2 + _ROBOT : view.size : len(LOCAL_FEATURES)]
        if not _seen_alone(around, cells, racing, robot):  # robots sharing cells: counted
            _robots_counted(view, cells[None], racing[None], robot[None])
    if marks is not None:
        out.put(marks, 1)
    elif goals is not None:
        mark_targets(out, cells, goals, view.width, view.height, view.radius, view.size)
    return out


def _window_indices(view: LocalView, cells: np.ndarray) -> np.ndarray:
    """``(..., cells in a window)``: the cells of each robot's window in the padded grid (always inside it)."""
    return view.padded.take(cells)[..., None] + view.window


def _robots_seen(view: LocalView, cells: np.ndarray, racing: np.ndarray, robot: np.ndarray) -> None:
    """The robot feature of every window cell, ``robot`` ``(R, n, cells in a window)``: another racing robot there.
    The robots go on a scratch grid of a few races at a time (a bounded grid, O(n) work); only racing
    robots are on the board."""
    around = window_cells(view)
    if len(cells) == 1 and around is not None and _seen_alone(around, cells[0], racing[0], robot[0]):
        return
    _robots_counted(view, cells, racing, robot)


def _robots_counted(view: LocalView, cells: np.ndarray, racing: np.ndarray, robot: np.ndarray) -> None:
    """``_robots_seen`` by counting the racing robots of each cell of a padded grid (robots may share cells)."""
    at = view.padded.take(cells)
    idx = at[:, :, None] + view.window
    n_padded, centre = view.static.shape[0], view.window.size // 2
    step = max(1, _SCRATCH // n_padded)
    for s in range(0, len(cells), step):
        at_s, racing_s = at[s : s + step], racing[s : s + step]
        race_base = (np.arange(at_s.shape[0], dtype=np.int64) * n_padded)[:, None]
        count = np.bincount((at_s + race_base)[racing_s], minlength=at_s.shape[0] * n_padded)  # add.at's counts, faster
        seen = count.take(idx[s : s + step] + race_base[:, :, None], mode="clip")
        seen[:, :, centre] -= racing_s
        robot[s : s + step] = seen > 0


def _seen_alone(around: np.ndarray, cells: np.ndarray, racing: np.ndarray, robot: np.ndarray) -> bool:
    """``_robots_seen`` of one race whose racing robots each have a cell of their own (the rules but "pass"):
    a grid of flags read through each robot's window cells (``window_cells``: its own cell left out, as
    it holds the robot itself). False (nothing written) when two racing robots share a cell."""
    everyone = np.count_nonzero(racing) == len(cells)
    on_board = cells if everyone else cells[racing]
    taken = np.zeros(len(around) + 1, dtype=bool)  # the last: off the grid
    taken[on_board] = True
    if np.count_nonzero(taken) < len(on_board):
        return False
    robot[...] = taken.take(around.take(cells, axis=0))
    if not everyone:  # a finished robot's own cell: a racing robot there is another robot
        robot[:, around.shape[1] // 2] = taken.take(cells) & ~racing
    return True


@lru_cache(maxsize=8)
def window_cells(view: LocalView) -> np.ndarray | None:
    """``(cells, cells in a window)``: the cell of each cell's window cells, ``cells`` (one past the last) off
    the grid and at the window's centre (the observer's own cell); None when the table would pass
    ``_LEVEL_ROWS_BYTES`` (wide windows on large levels)."""
    n_cells = view.padded.size
    if n_cells * view.window.size * np.dtype(np.intp).itemsize > _LEVEL_ROWS_BYTES:
        return None
    cell_of = np.full(view.static.shape[0], n_cells, dtype=np.intp)  # padded grid -> cell
    cell_of[view.padded] = np.arange(n_cells)
    around = cell_of.take(view.padded[:, None] + view.window)
    around[:, view.window.size // 2] = n_cells
    around.setflags(write=False)  # shared by every env on the level
    return around


_LEVEL_ROWS_BYTES = 8 << 20  # the largest table of level rows kept per view (else windows are gathered per step)


@lru_cache(maxsize=8)
def level_rows(view: LocalView, extra: int = 0) -> np.ndarray | None:
    """Every cell's "local" row as the level alone makes it: ``[x, y]``, the window's features with
    the robot column 0, then ``extra`` zeros; small ints (int16 where they fit), one row per cell,
    so that a step's rows are one gather of contiguous rows. None when the table would pass
    ``_LEVEL_ROWS_BYTES`` (large levels with wide windows)."""
    dtype = np.int16 if max(view.width, view.height) <= np.iinfo(np.int16).max else np.int32
    n_cells, size = view.padded.size, view.size + extra
    if n_cells * size * np.dtype(dtype).itemsize > _LEVEL_ROWS_BYTES:
        return None
    rows = np.zeros((n_cells, size), dtype=dtype)
    rows[:, :2] = view.xy
    rows[:, 2 : view.size] = view.static.take(view.padded[:, None] + view.window, axis=0).reshape(n_cells, -1)
    rows.setflags(write=False)  # shared by every env on the level
    return rows


_SCRATCH = 1 << 20  # cells of scratch grid per pass (4 MB of counts)


@dataclass(frozen=True, eq=False)
class Observer:
    """A race's "local" or "nearest" observations (``make_observer``): ``nvec`` and the rows."""

    mode: str
    nvec: np.ndarray
    view: LocalView | None  # "local"
    k: int  # "nearest"
    xy: np.ndarray  # (cells, 2)
    width: int
    height: int

    def __call__(
        self, cells: np.ndarray, racing: np.ndarray, extra: int = 0, goals: np.ndarray | None = None,
        marks: np.ndarray | None = None,
    ) -> np.ndarray:  # fmt: skip
        """``(..., n, len(nvec))`` int64 rows from every robot's cell and racing flag, ``(..., n)``
        (``extra``: that many more columns at the end, for the caller to fill; ``goals``: own goals'
        target cells, whose columns begin the extra ones: "local" the target channel, "nearest" ``[x, y]``;
        ``marks``: "local" puts the channel's 1s there (``goals.channel_marks``) if given)."""
        if self.view is not None:
            return local_observations(self.view, cells, racing, extra, goals, marks)
        out = nearest_observations(self.xy[np.asarray(cells)], racing, self.k, self.width, self.height, extra)
        if goals is not None:
            first = len(self.nvec)
            out[..., first : first + 2] = self.xy[np.asarray(goals)]
        return out


DEFAULT_VIEW_RADIUS, DEFAULT_K = 2, 4


def make_observer(table: Table, observe: str = "global", view_radius: int | None = None, k: int | None = None) -> Observer | None:
    """The observer of ``observe`` (``None`` for "global", which the envs build themselves).

    ``view_radius`` (default 2) belongs to "local" and ``k`` (default 4) to "nearest": either
    given to another mode is a ``ValueError``, as is anything but an integer in
    ``0..max(width, height) - 1`` (``checks.check_view_radius``: that radius sees the whole level)
    or ``1..MAX_NEAREST_K`` for ``k`` (``checks.check_nearest_k``); checked before anything is allocated.
    """
    if observe not in OBSERVE_MODES:
        raise ValueError(f"observe: must be one of {', '.join(map(repr, OBSERVE_MODES))}, got {observe!r}")
    w, h = table.level.width, table.level.height
    for name, value, mode in (("view_radius", view_radius, "local"), ("k", k, "nearest")):
        if value is None:
            continue
        if observe != mode:
            raise ValueError(f"{name}: only for observe={mode!r}, got {name}={shown(value)} with observe={observe!r}")
    if view_radius is not None:
        view_radius = check_view_radius(view_radius, w, h, DEFAULT_VIEW_RADIUS)
    if k is not None:
        k = check_nearest_k(k)
    if observe == "global":
        return None
    ids = np.arange(table.n_cells)
    xy = np.stack([ids % w, ids // w], axis=1)
    if observe == "local":
        view = local_view(table, int(DEFAULT_VIEW_RADIUS if view_radius is None else view_radius))
        return Observer("local", view.nvec, view, 0, xy, w, h)
    k = int(DEFAULT_K if k is None else k)
    return Observer("nearest", nearest_nvec(w, h, k), None, k, xy, w, h)


HINT_BITS = 5  # the goal hint: one bit per action (core.actions.Action order)


def observer_for(observer: Observer, table: Table, width: int, height: int) -> Observer:
    """``observer``'s mode, radius and ``k`` on another level (``table``: a level a race drew at reset,
    its radius checked on the level the env was built on), its ``[x, y]`` sized for ``width x height``
    (the largest level the env draws: the observation space stays the same)."""
    w, h = table.level.width, table.level.height
    ids = np.arange(table.n_cells)
    xy = np.stack([ids % w, ids // w], axis=1)
    if observer.view is not None:
        view = local_view(table, observer.view.radius)
        return Observer("local", np.array([width, height, *view.nvec[2:]], dtype=np.int64), view, 0, xy, w, h)
    # "nearest": offsets [dx + width - 1, dy + height - 1] on the largest level's scale, missing ones its last values
    return Observer("nearest", nearest_nvec(width, height, observer.k), None, observer.k, xy, width, height)


@dataclass(frozen=True, eq=False)
class HintObserver(Observer):
    """An observer whose rows end with the goal hint of the robot's cell: ``hints[cell]``, one bit per action."""

    hints: np.ndarray  # (cells, HINT_BITS) 0/1

    def __call__(self, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
        rows = super().__call__(cells, racing)
        return np.concatenate([rows, self.hints.take(np.asarray(cells), axis=0).astype(np.int64)], axis=-1)


def with_hint(observer: Observer, hints: np.ndarray) -> HintObserver:
    """``observer`` with the goal hint: ``hints`` ``(cells, HINT_BITS)`` (or ``(H, W, HINT_BITS)``) of 0/1,
    appended to each robot's row (``nvec`` 2 each). A finished robot sees its exit's hint: all 0."""
    if isinstance(observer, HintObserver):
        raise ValueError("hint: this observer has a hint already")
    hints = np.asarray(hints).reshape(-1, HINT_BITS)
    nvec = np.concatenate([observer.nvec, np.full(HINT_BITS, 2, dtype=np.int64)])
    return HintObserver(observer.mode, nvec, observer.view, observer.k, observer.xy, observer.width, observer.height, hints)
