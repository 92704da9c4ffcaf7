"""The race env's read-outs: its state, its pictures and its per-robot tallies, as a part of ``RaceEnv``
(a mixin reading the env's own fields; ``race.py`` holds the steps)."""

from __future__ import annotations

import numpy as np

from ..core.level import Cell
from ..render.ansi import frame, robot_glyph
from ..render.scene import Scene
from .scenes import own_goals, race_scene


class RaceReadouts:
    """``RaceEnv``'s read-only views: ``state()``, ``render()``, ``render_text()``, ``robot_cells``, ``ranks``, ..."""

    def state(self) -> np.ndarray:
        """Every robot's ``[x, y, finished]`` in robot order (a global view for critics), encoded as observations are."""
        self._check_started("state")
        rows = [0] * self.n_robots
        for i, row in zip(self._live + self._done, [*self._live_cells, *self._parked]):
            rows[i] = row
        return self._encode_state(self._xyf.take(rows, axis=0).ravel())

    def render(self) -> str | None:
        if self.render_mode is None:
            import gymnasium

            gymnasium.logger.warn("render() called with render_mode=None; pass render_mode='ansi' or 'human'")
            return None
        if self.render_mode == "rgb_array":
            return self.drawing.frame(self._scene())
        if self.render_mode == "ansi":
            return self.render_text()
        self.drawing.show(self._scene, self.render_text, self._t > 0, self.metadata["render_fps"])
        return None

    def _scene(self) -> Scene:
        return race_scene(self)

    def render_text(self, colour: bool = False) -> str:
        """The text frame: the level, racing robots as letters A, B, ..., and a status line."""
        robots: list[Cell | None] = [self._xy[c] if r else None for c, r in zip(self._cells, self._racing)]
        done = [f"{robot_glyph(i, self.n_robots)}#{r}" for i, r in enumerate(self._rank) if r]  # [] before reset
        status = f"step {self._t}/{self.max_cycles}" + (f"  finished: {' '.join(done)}" if done else "")
        return frame(self.level, robots, status, colour=colour, goals=own_goals(self))

    @property
    def robot_cells(self) -> list[Cell]:
        """Each robot's ``(x, y)`` (a finished robot: the exit it took, or its own target)."""
        return [self._xy[c] for c in self._cells]

    @property
    def elapsed_steps(self) -> int:
        return self._t

    def observations(self) -> dict[str, np.ndarray]:
        """Each agent's observation now: what the last ``reset`` or ``step`` returned (fresh arrays)."""
        self._check_started("observations")
        return dict(zip(self.agents, self._observations()))

    @property
    def ranks(self) -> list[int]:
        """Each robot's finishing rank (1 = first; robots finishing in one step share it), 0 if not finished."""
        return list(self._rank)

    @property
    def returns(self) -> list[float]:
        returns = list(self._returns)
        for i, r in zip(self._live, self._live_returns):
            returns[i] = r
        return returns

    @property
    def collisions_count(self) -> list[int]:
        """How many steps each robot has been blocked by another robot this episode."""
        bumps = list(self._bumps)
        for i, b in zip(self._live, self._live_bumps):
            bumps[i] = b
        return bumps

    @property
    def goals(self) -> dict[str, Cell] | None:
        """Each agent's own target ``(x, y)`` with ``goals="own"`` (empty before the first reset); None when
        the robots race to the exits (``goals="exit"``)."""
        if self.goals_mode != "own":
            return None
        return {} if self._goal_of is None else {a: self._xy[g] for a, g in zip(self.possible_agents, self._goal_of)}
