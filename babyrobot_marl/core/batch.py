"""Many races at once: ``n_envs`` copies of one level with ``n_robots`` each, stepped in numpy.

All state lives in arrays of shape ``(n_envs,)`` or ``(n_envs, n_robots)``; a step is the same
table look-ups as ``engine.move`` and the same collision rules as ``race.resolve_collisions``,
over whole arrays, with no Python loop over envs or robots. Random numbers come from the
same counter-based stream (``rng.uniform_array``) at the same addresses, so env ``i`` of a
batch plays exactly the episode of a single env given the same seed and actions. Each env
keeps its own ``numpy.random.Generator`` only for what a reset draws (the episode key, random
starts), in the same order as the single envs do.

``BatchRace`` is the core: ``step`` without auto-reset, ``reset_envs`` to start new episodes.
The Gymnasium and Stable-Baselines3 vector envs are thin shells over it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .actions import N_ACTIONS
from .checks import check_batch, check_int
from .engine import move_array, move_drawn
from .goals import GoalColumns, draw_goals, next_goal
from .observe import Observer, Recycler, global_observations
from .race import spread_stops
from .rng import SLOT_PRIORITY, SLOTS, uniform_array
from .table import Table

START_MODES = ("level", "fill", "random", "single")  # "single": BabyRobotEnv's one random start


def resolve_collisions_array(
    mode: str, cells: np.ndarray, desired: np.ndarray, racing: np.ndarray, keys: np.ndarray, steps: np.ndarray
) -> np.ndarray:
    """``race.resolve_collisions`` over ``(n_envs, n_robots)`` arrays; ``keys``, ``steps``: ``(n_envs,)``.

    The same closure as the scalar rules: movers in a swap or losing a contest stay (block: to a
    contender of higher priority, the lower robot number on a tie; soft: to a lower robot number;
    bounce: to any contender),
    robots that do not move stay, and a mover heading for the cell of a robot that stays stays
    too. All envs are one graph here (a robot's cell keyed by its env), each mover pointing at
    the occupant of its destination; stopping spreads back along those pointers by pointer
    doubling, ``log2(n_robots)`` passes at most, so the work is O(robots log robots) with no
    Python loop over envs or robots and no ``n_robots ** 2`` array.
    """
    n_envs, n = cells.shape
    if mode == "pass" or n == 1:  # one robot meets nobody
        return desired
    moving = racing & (desired != cells)
    if n <= _PAIRWISE_UP_TO:
        # Envs where some robot heads for another robot's destination or current cell: a superset
        # of the envs with a conflict. Compared robot pair by robot pair over all envs at once:
        # long rows, fast, for a few robots.
        d_rows, c_rows = desired.T.copy(), cells.T.copy()
        near = np.zeros(n_envs, dtype=bool)
        for i in range(n):
            for j in range(n):
                if j != i:
                    near |= d_rows[i] == c_rows[j]
                    if j > i:
                        near |= d_rows[i] == d_rows[j]
        todo = np.flatnonzero(near & moving.any(axis=1))
    else:
        todo = np.flatnonzero(moving.any(axis=1))
    if todo.size == 0:
        return desired
    c, d = cells[todo].ravel(), desired[todo].ravel()
    live, mv = racing[todo].ravel(), moving[todo].ravel()
    # one key space for all envs: env row * stride + cell
    stride = int(max(c.max(), d.max())) + 1
    row_base = np.repeat(np.arange(todo.size, dtype=np.int64) * stride, n)
    ck, dk = c + row_base, d + row_base
    # the occupant of each mover's destination (a racing robot on that cell), or -1
    on_board = np.flatnonzero(live)
    by_cell = on_board[np.argsort(ck[on_board])]
    at = np.minimum(np.searchsorted(ck[by_cell], dk), by_cell.size - 1)
    occupant = by_cell[at]
    hit = mv & (ck[occupant] == dk)
    stopped = live & ~mv  # robots that do not move
    k = np.flatnonzero(hit)
    stopped[k[dk[occupant[k]] == ck[k]]] = True  # swaps: each side is stopped from its own row
    # contests: movers sharing a destination, in robot order within each destination
    movers = np.flatnonzero(mv)
    movers = movers[np.argsort(dk[movers], kind="stable")]
    same = dk[movers[1:]] == dk[movers[:-1]]
    if same.any():
        in_contest = np.zeros(movers.size, dtype=bool)
        in_contest[1:] |= same
        in_contest[:-1] |= same
        rivals = movers[in_contest]
        if mode == "bounce":
            stopped[rivals] = True
        elif mode == "soft":  # the lowest robot number of each cell gets in: rivals come by cell, then robot
            stopped[rivals[1:][dk[rivals[1:]] == dk[rivals[:-1]]]] = True
        else:
            row, robot = rivals // n, (rivals % n).astype(np.uint64)
            counts = (steps[todo][row].astype(np.uint64) * np.uint64(n) + robot) * np.uint64(SLOTS) + np.uint64(SLOT_PRIORITY)
            prio = uniform_array(keys[todo][row], counts)
            rivals = rivals[np.lexsort((rivals, -prio, dk[rivals]))]
            stopped[rivals[1:][dk[rivals[1:]] == dk[rivals[:-1]]]] = True  # all but the first of each cell
    elif not hit.any():
        return desired  # nobody heads for an occupied cell, no two for one cell
    # the rest follow their occupant: stopped if a stopped robot lies ahead on the chain (chains stay in their env)
    back = spread_stops(stopped, hit & ~stopped, occupant, n.bit_length()) & mv
    final = desired.copy()
    f = final[todo].ravel()
    f[back] = c[back]
    final[todo] = f.reshape(todo.size, n)
    return final


_PAIRWISE_UP_TO = 8  # robots per env up to which the pair-by-pair pre-check beats sorting


class BatchRace:
    """``n_envs`` races of ``n_robots`` on one compiled level, as arrays.

    ``start``: ``"level"`` / ``"fill"`` / ``"random"`` as in ``race_v0``, or ``"single"`` for
    ``BabyRobotEnv``'s random start (one robot, one draw). ``win_bonus`` is the race's bonus
    (0 for single-robot envs). Robots that finish are parked (the ``finished="freeze"`` view).
    ``goal_columns`` (own goals, on a ``goals.own_goal_table``): each robot has its own target
    (``goals``, drawn at reset after the starts, as ``race_v0`` draws them), finishes on it with the
    exit reward (no bonus), and its observation rows end with the goal's columns. ``lifelong``
    (with own goals): a robot on its target gets a new one from its env's generator instead and keeps
    going (``reached`` counts the targets); the race ends at ``max_steps``. ``stay`` (own goals, not lifelong,
    ``race_v0``'s ``finished="stay"``): a robot on its target earns the exit reward and races on (it may leave
    again and blocks others); when all of an env's robots stand on their targets at once they all finish that
    step, staying on the board, and the env's race is over (one robot: reaching its target ends it, as ever).
    """

    def __init__(
        self,
        table: Table,
        n_envs: int,
        n_robots: int,
        max_steps: int,
        fixed_starts: Sequence[int] = (),
        free: Sequence[int] = (),
        start: str = "level",
        win_bonus: float = 0.0,
        observer: Observer | None = None,
        pools: Sequence[int] | None = None,
        goal_columns: GoalColumns | None = None,
        lifelong: bool = False,
        stay: bool = False,
    ):
        if start not in START_MODES:
            raise ValueError(f"start: must be one of {START_MODES}, got {start!r}")
        n_envs, n_robots = check_int(n_envs, "n_envs", lo=1), check_int(n_robots, "n_robots", lo=1)
        obs_size = observer.nvec.size if observer is not None else 3 * n_robots - 1 if n_robots > 1 else 2
        obs_size += len(goal_columns.nvec) if goal_columns is not None else 0
        check_batch(n_envs, n_robots, obs_size)  # before anything per env or robot exists
        self.table = table
        self.n_envs, self.n_robots, self.max_steps = n_envs, n_robots, max_steps
        self.fixed = np.asarray(fixed_starts, dtype=np.int64)
        self.free = np.asarray(free, dtype=np.int64)
        # start pools: consecutive runs of ``free`` (one per level of an atlas); a reset draws a pool, then starts in it
        counts = np.asarray([len(self.free)] if pools is None else pools, dtype=np.int64)
        if counts.sum() != len(self.free) or (pools is not None and (counts < 1).any()):
            raise ValueError(f"pools: the sizes of runs of free cells, each >= 1, summing to {len(self.free)}, "
                             f"got {counts.tolist()}")
        self.pool_count, self.pool_first = counts, np.cumsum(counts) - counts
        self.pool = np.zeros(n_envs, dtype=np.int64)  # each env's pool in its current episode
        self.start = start
        self.win_bonus = 0.0 if goal_columns is not None else float(win_bonus)
        self.goal_columns = goal_columns
        # own goals: each robot's target cell; ``given_goals`` (when set) replaces the draw at resets
        self.goals = np.zeros((n_envs, n_robots), dtype=np.int64) if goal_columns is not None else None
        self.given_goals: np.ndarray | None = None
        self.lifelong = bool(lifelong) and self.goals is not None
        if stay and (self.goals is None or self.lifelong):
            raise ValueError("stay: robots stay on their own targets: it needs goal_columns (own goals), not lifelong")
        self.stay = bool(stay)
        self.reached = np.zeros((n_envs, n_robots), dtype=np.int64)  # own goals: targets reached this episode (stay: 0)
        self._drawn_rng: np.random.Generator | None = None  # reset_drawn's generator: lifelong draws for its envs
        self.mode = table.rules.collisions
        e, n = n_envs, n_robots
        self.cells = np.zeros((e, n), dtype=np.int64)
        self.racing = np.zeros((e, n), dtype=bool)
        self.rank = np.zeros((e, n), dtype=np.int32)
        self.n_finished = np.zeros(e, dtype=np.int32)
        self.t = np.zeros(e, dtype=np.int64)
        self.keys = np.zeros(e, dtype=np.uint64)
        self.over = np.ones(e, dtype=bool)  # no episode yet
        # each env's generator, made at its first unseeded reset (1,024 fresh ones cost 11 ms)
        self.generators: list[np.random.Generator | None] = [None] * e
        self._robot_counts = np.arange(n, dtype=np.uint64) * np.uint64(SLOTS)
        w = table.width
        self.observer = observer  # None: the "global" rows below
        self._obs_shape = (e, n, 3 * n - 1)
        recycler = Recycler()  # "global" observations of many robots: 96 MB a step at 4 x 1,000
        self._recycler = recycler if observer is None and n > 1 and recycler.recycles(self._obs_shape) else None
        ids = np.arange(table.n_cells)
        self._xyf = np.stack([ids % w, ids // w, np.zeros_like(ids)], axis=1).astype(np.int64)
        self._xy = np.ascontiguousarray(self._xyf[:, :2])
        # _step_one's constants: whether some move draws (puddles, glass walls), c * N_ACTIONS by cell, the step limit
        self._draws = bool(np.count_nonzero(table.sure_flat[0] < 0))
        self._cell_base = np.arange(table.n_cells, dtype=np.int64) * N_ACTIONS
        self._one_t = np.ones(e, dtype=np.int64)
        self._no_block = np.zeros((e, n), dtype=bool)
        self._no_block.setflags(write=False)  # one robot is never blocked by another

    @property
    def max_steps(self) -> int:
        return self._max_steps

    @max_steps.setter
    def max_steps(self, value: int) -> None:
        self._max_steps, self._max_t = value, np.full(self.n_envs, value, dtype=np.int64)  # _step_one compares with the array

    @property
    def nbytes(self) -> int:
        """Bytes of per-env state (not counting the shared table or the generators)."""
        return sum(a.nbytes for a in (self.cells, self.racing, self.rank, self.n_finished, self.t, self.keys, self.over))

    # ------------------------------------------------------------------ resets
    def seed(self, seeds: Sequence[int | None]) -> None:
        """Give each env a fresh generator, as ``reset(seed=...)`` gives a single env."""
        for i, s in enumerate(seeds):
            self.generators[i] = np.random.default_rng(s)

    def reset_envs(self, envs: Sequence[int] | np.ndarray) -> None:
        """Start new episodes in the given envs, each drawing from its own generator."""
        for i in np.asarray(envs, dtype=np.int64).tolist():
            g = self.generators[i]
            if g is None:
                g = self.generators[i] = np.random.default_rng()
            self.keys[i] = g.integers(0, 1 << 64, dtype=np.uint64)
            if self.pool_count.size > 1:
                self.pool[i] = g.integers(self.pool_count.size)
            self.cells[i] = self._starts(g, int(self.pool[i]))
            if self.goals is not None:  # given (a vector env's reset option), or drawn after the starts
                given = self.given_goals
                self.goals[i] = given if given is not None else draw_goals(g, self.table, self.cells[i].tolist())
        self._started(np.asarray(envs, dtype=np.int64))

    def reset_drawn(self, envs: np.ndarray, rng: np.random.Generator) -> None:
        """Start new episodes in ``envs`` drawing every key and start from one generator ``rng`` in a few
        numpy calls (a trainer's resets: no per-env generator, so no Python loop over envs; not the
        episodes ``reset_envs`` gives a seeded env)."""
        envs = np.asarray(envs, dtype=np.int64)
        k = envs.size
        if k == 0:
            return
        self._drawn_rng = rng
        self.keys[envs] = rng.integers(0, 1 << 64, size=k, dtype=np.uint64)
        pool = self.pool[envs] = rng.integers(self.pool_count.size, size=k) if self.pool_count.size > 1 else 0
        first, count = self.pool_first[pool], self.pool_count[pool]
        need = 1 if self.start == "single" else self.n_robots - len(self.fixed)
        if need > 0:
            if need == 1:  # one uniform index per env
                picks = (rng.random((k, 1)) * np.reshape(count, (-1, 1))).astype(np.int64)
            else:  # distinct cells: the ``need`` smallest of uniform keys, the pool's cells only
                u = rng.random((k, int(np.max(count))))
                if self.pool_count.size > 1:
                    u[np.arange(u.shape[1]) >= np.reshape(count, (-1, 1))] = 2.0
                picks = np.argpartition(u, need - 1, axis=1)[:, :need]
            drawn = self.free[np.reshape(first, (-1, 1)) + picks]
            self.cells[envs] = drawn if self.start == "single" or not len(self.fixed) else np.concatenate(
                [np.broadcast_to(self.fixed, (k, len(self.fixed))), drawn], axis=1)
        else:
            self.cells[envs] = self.fixed
        if self.goals is not None:
            for i in envs.tolist():
                self.goals[i] = draw_goals(rng, self.table, self.cells[i].tolist())
        self._started(envs)

    def _started(self, envs: np.ndarray) -> None:
        self.racing[envs] = True
        self.reached[envs] = 0
        self.rank[envs] = 0
        self.n_finished[envs] = 0
        self.t[envs] = 0
        self.over[envs] = False

    def _starts(self, g: np.random.Generator, pool: int = 0) -> np.ndarray:
        free = self.free[self.pool_first[pool] : self.pool_first[pool] + self.pool_count[pool]]
        if self.start == "single":
            return free[[int(g.integers(len(free)))]]
        need = self.n_robots - len(self.fixed)
        if need == 0:
            return self.fixed
        picks = g.choice(len(free), size=need, replace=False)
        return np.concatenate([self.fixed, free[picks]])

    # ------------------------------------------------------------------ the step
    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Advance every env one step (actions: ``(n_envs, n_robots)`` ints in 0..4).

        Returns ``(rewards, finishing, blocked, outcome, over)``: rewards ``(E, R)`` float64
        (0 for parked robots), robots finishing this step, robots stopped by another robot,
        ``engine`` outcome codes (-1 for parked robots), and envs whose race is over
        (everyone finished, or ``max_steps`` reached). Over envs stay as they are until
        ``reset_envs``.
        """
        if self.n_robots == 1:
            return self._step_one(actions)
        t, cells = self.table, self.cells
        racing = self.racing & ~self.over[:, None]  # an env whose race is over waits for reset_envs
        counts = (self.t[:, None].astype(np.uint64) * np.uint64(self.n_robots)) * np.uint64(SLOTS) + self._robot_counts
        desired, outcome = move_array(t, cells, actions, self.keys[:, None], counts)
        desired = np.where(racing, desired, cells)
        outcome = np.where(racing, outcome, -1)
        final = resolve_collisions_array(self.mode, cells, desired, racing, self.keys, self.t)
        blocked = final != desired
        rewards = np.where(racing, t.reward[final], 0.0)
        finishing = racing & (t.is_exit[final] if self.goals is None else final == self.goals)
        if self.goals is not None and finishing.any():  # on its own target: the exit reward, no race to win
            finishing = self._on_goals(finishing, final, rewards)
        if finishing.any():
            first = finishing.any(axis=1) & (self.n_finished == 0)
            rewards += np.where(finishing & first[:, None], self.win_bonus, 0.0)
            self.rank = np.where(finishing, (self.n_finished + 1)[:, None], self.rank)
            self.n_finished += finishing.sum(axis=1, dtype=np.int32)
            if not self.stay:  # staying robots end the race on the board, as the env shows them
                self.racing = self.racing & ~finishing
            racing = racing & ~finishing
        self.cells = final
        self.t += ~self.over
        self.over = over = (self.t >= self.max_steps) | ~racing.any(axis=1)
        return rewards, finishing, blocked, outcome, over

    def _step_one(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``step`` for one robot per env (no collisions, finishing ends the episode): fewer numpy calls."""
        t, c, a = self.table, self.cells[:, 0], actions[:, 0]
        sure_next, sure_code = t.sure_flat  # move_array's look-up, inlined: counts only where drawn
        idx = self._cell_base.take(c) + a  # c * N_ACTIONS + a: a look-up costs less than numpy's scalar handling
        nxt, code = sure_next.take(idx), sure_code.take(idx)
        draw = nxt < 0 if self._draws else None
        if draw is not None and np.count_nonzero(draw):  # puddles and glass walls
            k = np.flatnonzero(draw)
            counts = self.t[k].astype(np.uint64) * np.uint64(SLOTS)  # robot 0 of 1: (t * 1 + 0) * SLOTS
            nxt[k], code[k] = move_drawn(t, idx[k], c[k], self.keys[k], counts)
        frozen = self.over  # an env whose episode is over waits for reset_envs
        waiting = np.count_nonzero(frozen)
        if waiting:
            nxt = np.where(frozen, c, nxt)
            code = np.where(frozen, -1, code)
        rewards = t.reward.take(nxt)
        finishing = t.is_exit.take(nxt) if self.goals is None else nxt == self.goals[:, 0]
        if self.goals is not None and np.count_nonzero(finishing):
            finishing = self._on_goals(finishing[:, None] & ~self.over[:, None], nxt[:, None], rewards[:, None])[:, 0]
        if waiting:
            rewards[frozen] = 0.0
            finishing &= ~frozen
            self.t += ~frozen
        else:
            self.t += self._one_t
        if np.count_nonzero(finishing):  # a lone robot that finishes wins its race
            rewards[finishing] += self.win_bonus
            self.rank[finishing, 0] = 1
            self.n_finished[finishing] = 1
            self.racing[finishing, 0] = False
        self.cells = nxt[:, None]
        over = finishing | (self.t >= self._max_t)
        self.over = over = frozen | over if waiting else over
        return rewards[:, None], finishing[:, None], self._no_block, code[:, None], over

    def _on_goals(self, on_goal: np.ndarray, final: np.ndarray, rewards: np.ndarray) -> np.ndarray:
        """Robots standing on their own targets (``(E, R)``): the exit reward, counted; the ones that finish
        (all of them; with ``stay``, all of an env's robots when each stands on its target, else none; none with
        ``lifelong``: they get new targets, drawn env by env, in robot order)."""
        rewards[on_goal] = self.table.rules.exit_reward
        if self.stay:  # racing robots are all of a running env's robots: nobody is parked
            return on_goal & on_goal.all(axis=1)[:, None]
        self.reached += on_goal
        if not self.lifelong:
            return on_goal
        for i in np.flatnonzero(on_goal.any(axis=1)).tolist():
            g = self.generators[i] if self.generators[i] is not None else self._drawn_rng
            goals = self.goals[i]
            taken = set(goals.tolist())
            for k in np.flatnonzero(on_goal[i]).tolist():
                taken.discard(int(goals[k]))
                goals[k] = new = next_goal(g, self.table, int(final[i, k]), taken)
                taken.add(new)
        return np.zeros_like(on_goal)

    def observations(self) -> np.ndarray:
        """``(n_envs, n_robots, 2 + 3 * (n_robots - 1))`` int64, as ``race_v0`` (``[x, y]`` for one robot);
        with an ``observer``, its rows. A new array each step, or one of the last two steps' arrays
        that the caller no longer holds (``observe.Recycler``, past 32 MB): never one the caller keeps."""
        columns = self.goal_columns
        if columns is None:
            return self._rows()
        if self.observer is not None:  # rows with room for the goal's columns, filled in place
            rows = self.observer(self.cells, self.racing, columns.size, self.goals)  # with the goal's columns
            return columns(self.table, self.cells, self.goals, out=rows, written=True)
        return np.concatenate([self._rows(), columns(self.table, self.cells, self.goals)], axis=-1)

    def _rows(self) -> np.ndarray:
        if self.observer is not None:
            return self.observer(self.cells, self.racing)
        if self.n_robots == 1:  # [x, y] alone
            return self._xy.take(self.cells, axis=0)
        xyf = self._xyf.take(self.cells, axis=0)  # (E, R, 3): [x, y, 0]
        xyf[:, :, 2] = ~self.racing
        return global_observations(xyf, None if self._recycler is None else self._recycler.empty(self._obs_shape))
