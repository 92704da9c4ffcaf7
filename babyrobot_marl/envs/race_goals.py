"""The race env's own goals (``goals="own"``, ``lifelong=True``), as a part of ``RaceEnv`` (a mixin over the
env's own fields): the reset options' cells, each robot's target, the goal's columns of its observation,
and lifelong's new targets. The rules live in ``core.goals``."""

from __future__ import annotations

import operator
from collections.abc import Mapping, Sequence
from itertools import compress, repeat
from typing import Any

import numpy as np

from ..core.goals import cell_keys, draw_goals, goal_step, next_goal
from .checks import check_cells, check_goal_cells, check_goals_reach
from .race_outputs import racing_outputs


def towards_own_goal(race: Any, k: int, obs: Any = None) -> int:
    """Robot ``k``'s first action on a shortest path to its own target in ``race`` (STAY on it or when it is out
    of reach): the shortest-path robot of own goals (``obs`` unused: it reads the race)."""
    table = race.table
    return goal_step(table, table.cell_id(race.robot_cells[k]), table.cell_id(race.goals[race.possible_agents[k]]))


def next_goals(rng: np.random.Generator, table: Any, goal_of: list[int], live: list[int], cells: Sequence[int],
               reached: list[bool]) -> np.ndarray:  # fmt: skip
    """Lifelong: each racing robot that ``reached`` its target gets a new one in ``goal_of`` (robot order, drawn
    from ``rng``: ``core.goals.next_goal``); every robot's target as an array."""
    taken = set(goal_of)
    for i, c, r in zip(live, cells, reached):
        if r:
            taken.discard(goal_of[i])
            goal_of[i] = g = next_goal(rng, table, c, taken)
            taken.add(g)
    return np.array(goal_of, dtype=np.int64)


def staying_outputs(race: Any, cells: Sequence[int], here: np.ndarray | None, outcome: Sequence[int], blocked: list[bool],
                    on: list[bool], marks: np.ndarray | None) -> tuple[tuple, list[float], bool]:  # fmt: skip
    """A step of ``finished="stay"`` in ``race`` after which some robots stand on their targets (``on``): the five
    dicts, the racing robots' returns and whether the race is over. Robots on their targets earn the exit reward
    (0 by default) and race on; when all of them stand on theirs at once the race ends, each robot terminated
    (POGEMA's ``on_target="nothing"``), else at ``max_cycles`` each robot is truncated. Infos' ``"finished"``:
    on its target now."""
    reported, rewards, reward_on = race.agents, list(map(race._reward_at.__getitem__, cells)), race.rules.exit_reward
    for k in compress(range(len(on)), on):
        rewards[k] = reward_on
    returns = list(map(operator.add, race._live_returns, rewards))
    xy, rows = race._cell_xy.take(cells if here is None else here, axis=0), race._observations(here, marks)
    solved = False not in on
    if solved or race._t >= race.max_cycles:  # the race's end
        out = racing_outputs(reported, rows, rewards, outcome, blocked, on if solved else [False] * len(on), xy,
                             repeat(0), True, solved, finished=on)  # fmt: skip
        return out, returns, True
    infos = {  # as the common step's, each robot's "finished" its own
        a: {"cell": c, "outcome": o, "blocked": b, "finished": f, "rank": 0}
        for a, c, o, b, f in zip(reported, xy, outcome, blocked, on)
    }
    no = race._none_done
    return (dict(zip(reported, rows)), dict(zip(reported, rewards)), no.copy(), no.copy(), infos), returns, False


class OwnGoalShortest:
    """The shortest-path robot of own goals acting on its observation row: a ``"global"`` or ``"nearest"`` row
    of an own-goal race (no hint, ``"multidiscrete"``) starts with the robot's ``[x, y]`` and ends with its
    target's ``[x, y]``. The first action of a shortest path, STAY on the target or when it is out of reach."""

    name = "shortest"

    def __init__(self, table: Any):
        self.table = table

    def __call__(self, obs: Any) -> int:
        t = self.table
        return goal_step(t, t.cell_id((int(obs[0]), int(obs[1]))), t.cell_id((int(obs[-2]), int(obs[-1]))))


class RaceGoals:
    """``RaceEnv``'s own-goal steps, stateless (the env holds the state): ``_cell_options``, ``_goals_for``, ...."""

    def _goal_tables(self) -> tuple[np.ndarray, tuple | None]:
        """Own goals' per-level tables, read every step: the cells' keys (``goal_offsets``) and, for "local"
        rows, the target channel's ``(where, row length, column)`` (``channel_marks``)."""
        view = self._observer.view if self._observer is not None else None
        keys = cell_keys(self.table.width, self.table.height)
        if self._goal_columns is None or view is None:
            return keys, None
        row = view.size + self._goal_columns.size
        return keys, (view.channel_where, row, view.size)

    def _finishing_rows(self, live: list[int], cells: Sequence[int], keep: list[bool]) -> np.ndarray | None:
        """The rows of the robots that raced this step (``live``, in order, now on ``cells``; ``keep``: still
        racing), finishers included, as ``_observations`` gives them once the finishers have left: from these
        robots alone (robots parked earlier are in nobody's view). None for "global" rows (the general way)."""
        if self._observer is None:
            return None
        here, racing, columns = np.array(cells), np.array(keep), self._goal_columns
        if columns is None:
            return self.encoder(self._observer(here, racing))
        goals = self._goal_arr[live]
        rows = self._observer(here, racing, columns.size, goals)
        return self.encoder(columns(self.table, here, goals, out=rows, written=True) if columns.hint else rows)

    def _goal_observations(self, here: np.ndarray | None = None, marks: np.ndarray | None = None) -> np.ndarray:
        """``_observations`` with own goals: each row, then its goal's columns (``core.goals.GoalColumns``;
        "local" and "nearest" observers write the goal's part in their own pass, the hint is added after).
        ``here``: the racing robots' cells as an array, if the step made one, and ``marks`` their target channel's."""
        ids, columns, goals = self._agent_ids, self._goal_columns, self._goal_arr
        if self._observer is not None and self._reported_live:  # the racing robots' rows alone (as in _observations)
            cells = np.array(self._live_cells) if here is None else here
            if marks is not None and not columns.hint:  # the common step of a "local" race: its marks are the goals' part
                return self.encoder(self._observer(cells, self._all_racing[: len(cells)], columns.size, None, marks))
            goals = self._racing_goals()
            rows = self._observer(cells, self._all_racing[: len(cells)], columns.size, goals, marks)
            return self.encoder(columns(self.table, cells, goals, out=rows, written=True) if columns.hint else rows)
        cells = np.array(self._cells)
        if self._observer is not None:  # rows with room for the goal's columns, filled in place
            rows = self._observer(cells, np.array(self._racing), columns.size, goals)
            rows = columns(self.table, cells, goals, out=rows, written=True)
            return self.encoder(rows if len(ids) == self.n_robots else rows[ids])  # all robots: already in order, fresh
        rows = self._xyf.take([*self._live_cells, *self._parked], axis=0).ravel()[self._gather_reported]
        return self.encoder(np.concatenate([rows, columns(self.table, cells[ids], goals[ids])], axis=-1))

    def _cell_options(self, options: Mapping[str, Any]) -> tuple[list[int] | None, list[int] | None]:
        """``reset``'s ``"starts"`` and ``"goals"`` as cell ids (None: not given), checked on this level."""
        starts, goals = options.get("starts"), options.get("goals")
        if starts is not None:
            starts = check_cells(self.table, starts, self.n_robots, 'options["starts"]')
        if goals is not None:
            goals = check_goal_cells(self.table, goals, self.n_robots, self.goals_mode)
        return starts, goals

    def _goals_for(self, starts: list[int], goals: list[int] | None) -> list[int] | None:
        """Each robot's target cell (own goals): given ones checked against the starts, else drawn; None: exits."""
        if self.goals_mode != "own":
            return None
        if goals is None:
            return draw_goals(self.np_random, self.table, starts)
        check_goals_reach(self.table, goals, starts)
        return goals

    @property
    def goals_reached(self) -> list[int]:
        """How many targets each robot has reached this episode (own goals; with ``lifelong=True`` it counts
        every target, else 0 or 1; with ``finished="stay"``, 1 for a robot on its target now); all 0 in the race
        to the exits."""
        if self.finished_mode == "stay" and self._started:  # every robot races, in order
            return [int(c == g) for c, g in zip(self._live_cells, self._goal_of)]
        return list(self._reached) if self._reached else [0] * self.n_robots
