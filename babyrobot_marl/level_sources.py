"""Levels drawn per reset: ``level=`` a maze family (``"maze-16x16-*"``) or a callable, seeded by the env.

    race_v0.parallel_env(level="maze-16x16-*", n_robots=8, start="random", observe="local")
    race_v0.parallel_env(level=maze_family(16, 16, seeds=range(1000)), ...)   # a fixed training set
    race_v0.parallel_env(level=lambda rng: my_generator(rng), ...)           # any Level, name or text

At every reset the env draws its level from its own seeded generator (``np_random``), after the
seed and before the starts: same seed, same level, same race. All levels of a source must have
one size (the observation spaces hold ``W`` and ``H``); the first level is drawn at construction
from a generator of its own (seed 0) only to learn that size. The batch engine and the vector
envs run one level for all their envs and refuse drawn levels.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from . import levels
from .core.level import Level
from .core.table import compile_level

LevelSource = Callable[[np.random.Generator], Level]
_FAMILY = re.compile(r"maze-(\d+)x(\d+)-\*")
FAMILY_SEEDS = 2**31  # "maze-WxH-*" draws its maze seed from 0 .. FAMILY_SEEDS - 1


def maze_family(width: int, height: int, seeds: Sequence[int] | range | None = None) -> LevelSource:
    """Mazes of one size, the maze seed drawn uniformly from ``seeds`` (default: 0 .. 2**31 - 1)."""
    pool = range(FAMILY_SEEDS) if seeds is None else seeds
    if len(pool) == 0:
        raise ValueError("seeds: an empty set of maze seeds")
    levels.maze(width, height, int(pool[0]))  # a bad size fails here, not at the first reset

    def draw(rng: np.random.Generator) -> Level:
        return levels.get(f"maze-{width}x{height}-s{int(pool[int(rng.integers(len(pool)))])}")

    draw.family = f"maze-{width}x{height}-*"  # type: ignore[attr-defined]
    return draw


def level_source(level: Any) -> LevelSource | None:
    """The drawing function of ``level=`` (``None`` for one fixed level: a name, a text or a ``Level``)."""
    if isinstance(level, str):
        if "\n" in level or not level.endswith("*"):
            return None
        m = _FAMILY.fullmatch(level)
        if m is None:
            raise ValueError(f"level: a level family is 'maze-WxH-*' (e.g. 'maze-16x16-*'), got {level!r}")
        return maze_family(int(m[1]), int(m[2]))
    if isinstance(level, Level) or not callable(level):
        return None
    from .envs.common import resolve_level

    def draw(rng: np.random.Generator) -> Level:
        got = level(rng)
        if not isinstance(got, (str, Level)):
            raise TypeError(f"level: the level callable returned {type(got).__name__}; expected a Level, a name or a text")
        return resolve_level(got)

    return draw


class DrawnLevels:
    """Mixin for the race env: ``_init_level_source`` in ``__init__``, ``_draw_level`` at reset."""

    _level_source: LevelSource | None = None

    def _init_level_source(self, level: Any) -> Any:
        """``level`` itself for a fixed level, else a first level drawn to fix the size."""
        self._level_source = level_source(level)
        return level if self._level_source is None else self._level_source(np.random.default_rng(0))

    def _check_one_level(self, what: str) -> None:
        if self._level_source is not None:
            raise ValueError(f"level: {what} runs one level in all its envs; drawn levels are for parallel_env and env")

    def _draw_level(self) -> None:
        """A new level from the env's generator, with everything that depends on it."""
        if self._level_source is None:
            return
        level: Level = self._level_source(self.np_random)  # type: ignore[attr-defined]
        old = self.level  # type: ignore[has-type]
        if (level.width, level.height) != (old.width, old.height):
            raise ValueError(
                f"level: drawn levels must all be {old.width}x{old.height} (the observation spaces hold the size), "
                f"got {level.width}x{level.height}"
            )
        self.level, self.table = level, compile_level(level, self.rules)  # type: ignore[attr-defined]
        self._lists = self.table.lists
        self._reward_at = self._lists.reward.__getitem__
        self._observer = self._observer_of(self.table)  # type: ignore[attr-defined]
        self._fixed_starts, self._free = self._placement(self.n_robots)  # type: ignore[attr-defined]
        self.__dict__.pop("rgb_renderer", None)  # drawn again for the new walls
        if getattr(self, "canvas", None) is not None:  # a live canvas shows one level: a new one for this
            self._close_canvas()  # type: ignore[attr-defined]
            self.canvas = None
