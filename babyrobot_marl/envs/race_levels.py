"""The race env's level, as a part of ``RaceEnv`` (a mixin reading the env's own fields): the compiled table,
the observer and the starts on it, and the per-cell arrays the steps read (``cell_arrays``); the env holds
them and replaces them all for a level drawn at reset (``RaceEnv._use_level``). ``race.py`` holds the steps."""

from __future__ import annotations

import numpy as np

from ..core.goals import own_goal_table
from ..core.level import Level
from ..core.observe import Observer, observer_for, with_hint
from ..core.table import Table, compile_level
from ..planning.hint import optimal_actions
from .starts import draw_starts, placement


def cell_arrays(table: Table) -> tuple:
    """What steps read per cell of ``table``: its rules' lists and flat look-ups, its reward, its ``[x, y]``
    (a family of sizes: each level has its own cells, inside the largest's space) as a tuple and as a row
    (infos' "cell", rows of a gather), and the state's ``[x, y, finished]`` rows: row c racing in cell c,
    row n_cells + c finished there."""
    lists = table.lists
    xy = [table.cell_xy(c) for c in range(table.n_cells)]
    xyf = np.array([(*c, 0) for c in xy] + [(*c, 1) for c in xy], dtype=np.int64)
    return lists, table.sure_flat, lists.reward, xy, np.array(xy, dtype=np.int64).reshape(-1, 2), xyf


class RaceLevels:
    """``RaceEnv``'s level-dependent parts, stateless (the env holds the state): ``_compile``, ``_placement``, ...."""

    def _drawn_observer(self, table: Table) -> Observer | None:
        """The observer on a level drawn at reset: the first's mode and radius, sized for the largest level, the hint if asked."""
        if self._first_observer is None:
            return None
        observer = observer_for(self._first_observer, table, *self.levels.largest)
        own = self._goal_columns is not None  # own goals: the hint is among the goal's columns
        return with_hint(observer, optimal_actions(table.level, self.rules)) if self.hint and not own else observer

    def _placement(self, n: int) -> tuple[list[int], list[int]]:
        return placement(self.table, self.start, n)

    def _draw_starts(self, goals: list[int] | None = None) -> list[int]:
        """Random starts (goals given: off those cells, so that no robot starts on its goal)."""
        free = self._free if goals is None else [c for c in self._free if c not in set(goals)]
        return draw_starts(self.np_random, self._fixed_starts, free, self.n_robots)

    def _compile(self, level: Level) -> Table:
        table = compile_level(level, self.rules)
        return own_goal_table(table) if self.goals_mode == "own" else table
