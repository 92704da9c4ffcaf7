"""The race env's level, as a part of ``RaceEnv`` (a mixin over the env's own fields): the compiled table,
the observer and the starts on it, and the per-cell arrays the steps read; a level drawn at reset
(``level=`` a family) replaces them all. ``race.py`` holds the steps."""

from __future__ import annotations

import numpy as np

from ..core.goals import own_goal_table
from ..core.level import Level
from ..core.observe import Observer, observer_for, with_hint
from ..core.table import Table, compile_level
from ..planning.hint import optimal_actions
from .starts import draw_starts, placement


class RaceLevels:
    """``RaceEnv``'s level-dependent parts: ``_use_level``, ``_compile``, ``_cell_arrays``, ...."""

    def _use_level(self, level: Level) -> None:
        """Race on ``level`` (drawn at reset, the size of the last): everything that depends on it."""
        self.level, self.table = level, self._compile(level)
        self._observer = self._drawn_observer(self.table)
        self._fixed_starts, self._free = self._placement(self.n_robots)
        self.drawing.new_level(level)
        self._cell_arrays()

    def _cell_arrays(self) -> None:
        """What steps read per cell: its rules' lists, its reward, its ``[x, y]`` (a family of sizes: each level
        has its own cells, inside the largest's space) as a tuple and a row, and its state rows."""
        self._lists = self.table.lists
        self._sure_flat = self.table.sure_flat  # the same as arrays, for crowds
        self._reward_at = self._lists.reward  # by cell
        self._xy = [self.table.cell_xy(c) for c in range(self.table.n_cells)]
        self._cell_xy = np.array(self._xy, dtype=np.int64).reshape(-1, 2)  # (cells, 2): infos' "cell", rows of a gather
        # [x, y, finished] of a robot: row c racing in cell c, row n_cells + c finished there
        self._xyf = np.array([(*xy, 0) for xy in self._xy] + [(*xy, 1) for xy in self._xy], dtype=np.int64)

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
