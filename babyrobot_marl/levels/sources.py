"""Levels drawn per reset: ``level=`` a maze family (``"maze-16x16-*"``) or a callable, seeded by the env.
``LevelPicker`` is the race's part that draws them.

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

from ..core.level import Level
from . import builtin, mazes
from .resolve import resolve_level

LevelSource = Callable[[np.random.Generator], Level]
_FAMILY = re.compile(r"maze-(\d+)x(\d+)-\*")
FAMILY_SEEDS = 2**31  # "maze-WxH-*" draws its maze seed from 0 .. FAMILY_SEEDS - 1


def maze_family(width: int, height: int, seeds: Sequence[int] | range | None = None) -> LevelSource:
    """Mazes of one size, the maze seed drawn uniformly from ``seeds`` (default: 0 .. 2**31 - 1)."""
    pool = range(FAMILY_SEEDS) if seeds is None else seeds
    if len(pool) == 0:
        raise ValueError("seeds: an empty set of maze seeds")
    mazes.maze(width, height, int(pool[0]))  # a bad size fails here, not at the first reset

    def draw(rng: np.random.Generator) -> Level:
        return builtin.get(f"maze-{width}x{height}-s{int(pool[int(rng.integers(len(pool)))])}")

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
    def draw(rng: np.random.Generator) -> Level:
        got = level(rng)
        if not isinstance(got, (str, Level)):
            raise TypeError(f"level: the level callable returned {type(got).__name__}; expected a Level, a name or a text")
        return resolve_level(got)

    return draw


class LevelPicker:
    """The race's levels, a part the env holds: one fixed level, or a source drawn from at each reset.

    ``first`` is the level the env is built on (for a source: drawn from a generator of its own,
    seed 0, only to learn the size); ``fixed`` says whether there is nothing to draw.
    """

    def __init__(self, level: Any) -> None:
        self.source = level_source(level)
        self.first: Level = resolve_level(level if self.fixed else self.source(np.random.default_rng(0)))

    @property
    def fixed(self) -> bool:
        return self.source is None

    def check_one_level(self, what: str) -> None:
        """A ``ValueError`` naming ``what`` (which runs one level in all its envs) if levels are drawn."""
        if not self.fixed:
            raise ValueError(f"level: {what} runs one level in all its envs; drawn levels are for parallel_env and env")

    def draw(self, rng: np.random.Generator, current: Level) -> Level | None:
        """A new level from ``rng`` (the env's generator), the size of ``current``; None for a fixed level."""
        if self.fixed:
            return None
        level = self.source(rng)
        if (level.width, level.height) != (current.width, current.height):
            raise ValueError(
                f"level: drawn levels must all be {current.width}x{current.height} (the observation spaces hold the size), "
                f"got {level.width}x{level.height}"
            )
        return level
