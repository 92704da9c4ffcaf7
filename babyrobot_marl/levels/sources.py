"""Levels drawn per reset: ``level=`` a maze family (``"maze:8..16"``, ``"maze-16x16-*"``) or a callable,
seeded by the env. ``LevelPicker`` is the race's part that draws them.

    race_v0.parallel_env(level="maze:8..16", n_robots=4, start="random", observe="local")  # sides 8..16
    race_v0.parallel_env(level="maze-16x16-*", n_robots=8, start="random", observe="local")
    race_v0.parallel_env(level=maze_family(16, 16, seeds=range(1000)), ...)   # a fixed training set
    race_v0.parallel_env(level=lambda rng: my_generator(rng), ...)           # any Level, name or text

At every reset the env draws its level from its own seeded generator (``np_random``), after the
seed and before the starts: same seed, same level, same race. A family of sizes (``"maze:A..B"``,
``maze_range_family``) draws the side, then the maze seed; the env is built on its largest level
(observation spaces, step limit, picture size: every level it draws fits). Other sources must draw
levels of one size (the observation spaces hold ``W`` and ``H``); their first level is drawn at
construction from a generator of its own (seed 0) only to learn that size. The batch engine and
the vector envs run one level for all their envs and refuse drawn levels.

Training and evaluation draw their mazes from disjoint seeds: ``TRAIN_MAZE_SEEDS`` and
``EVAL_MAZE_SEEDS`` (the fast trainer and ``babyrobot-marl evaluate``), so evaluation mazes are unseen.
Small mazes repeat across seeds (a 5x5 maze of one seed often equals one of another), so those of
16 to 49 cells are also split by content (``maze_part``): a family drawing from either set redraws a
maze of the other's part, and no evaluation maze equals a training maze. Mazes of fewer cells are too
few to split (a 2x2 maze is one of two); larger ones practically never repeat.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..core.level import Level
from . import builtin, mazes
from .checks import bad_family, check_family_sides
from .gridmazes import grid_maze
from .resolve import resolve_level

LevelSource = Callable[[np.random.Generator], Level]
_FAMILY = re.compile(r"maze-(\d+)x(\d+)-\*")
_RANGE = re.compile(r"(grid)?maze:(\d{1,9})\.\.(\d{1,9})")  # "maze:A..B", "gridmaze:A..B"
FAMILY_SEEDS = 2**31  # "maze-WxH-*" and "maze:A..B" draw their maze seed from 0 .. FAMILY_SEEDS - 1
TRAIN_MAZE_SEEDS = range(0, 2**30)  # the fast trainer's mazes
EVAL_MAZE_SEEDS = range(2**30, 2**31)  # evaluation's mazes: never trained on
SPLIT_CELLS = range(16, 50)  # mazes of this many cells are split between training and evaluation by content
_PARTS = ((TRAIN_MAZE_SEEDS, 0), (EVAL_MAZE_SEEDS, 1))
MAX_REDRAWS = 1000  # a part is about half of a size's mazes: a draw needs two tries on average


def maze_part(level: Level) -> int:
    """0 (a training maze) or 1 (an evaluation maze): one bit of a hash of the maze's walls, the same
    for equal mazes of any seed."""
    text = f"{level.width}x{level.height}:{sorted(level.walls)}".encode()
    return hashlib.blake2b(text, digest_size=1).digest()[0] & 1


def _draw_maze(width: int, height: int, pool: Sequence[int] | range, rng: np.random.Generator) -> Level:
    """A maze of a seed drawn from ``pool``; from the training or evaluation seeds, a small maze of that part."""
    part = next((p for seeds, p in _PARTS if pool == seeds), None)
    for _ in range(MAX_REDRAWS):
        level = builtin.get(f"maze-{width}x{height}-s{int(pool[int(rng.integers(len(pool)))])}")
        if part is None or width * height not in SPLIT_CELLS or min(width, height) < 2 or maze_part(level) == part:
            return level
    raise RuntimeError(f"no {width}x{height} maze of part {part} in {MAX_REDRAWS} draws")  # about 2**-1000


def maze_family(width: int, height: int, seeds: Sequence[int] | range | None = None) -> LevelSource:
    """Mazes of one size, the maze seed drawn uniformly from ``seeds`` (default: 0 .. 2**31 - 1)."""
    pool = range(FAMILY_SEEDS) if seeds is None else seeds
    if len(pool) == 0:
        raise ValueError("seeds: an empty set of maze seeds")
    mazes.maze(width, height, int(pool[0]))  # a bad size fails here, not at the first reset

    def draw(rng: np.random.Generator) -> Level:
        return _draw_maze(width, height, pool, rng)

    draw.family = f"maze-{width}x{height}-*"  # type: ignore[attr-defined]
    return draw


def maze_range_family(low: int, high: int, seeds: Sequence[int] | range | None = None) -> LevelSource:
    """Square mazes of side ``low..high`` (``"maze:A..B"``): each draw takes the side, then the maze seed
    from ``seeds`` (default: 0 .. 2**31 - 1), both from the generator it is given (the env's).

    Its attributes: ``family`` (the spec, ``"maze:8..16"``), ``largest`` (``(W, H)`` of the largest
    level it draws) and ``first()`` (a level of that size: what an env is built on).
    """
    return _square_family("maze", low, high, seeds, lambda side, pool, rng: _draw_maze(side, side, pool, rng),
                          lambda side, seed: builtin.get(f"maze-{side}x{side}-s{seed}"))


def grid_maze_family(low: int, high: int, seeds: Sequence[int] | range | None = None) -> LevelSource:
    """Square grid mazes (``gridmaze``: blocked cells, loops, no exit) of side ``low..high``
    (``"gridmaze:A..B"``): each draw takes the side, then the maze seed from ``seeds``, both from the
    generator it is given. Its attributes are ``maze_range_family``'s."""
    return _square_family("gridmaze", low, high, seeds,
                          lambda side, pool, rng: grid_maze(side, int(pool[int(rng.integers(len(pool)))])), grid_maze)


def _square_family(kind: str, low: int, high: int, seeds: Sequence[int] | range | None,
                   draw_level: Callable[[int, Sequence[int] | range, np.random.Generator], Level],
                   level_of: Callable[[int, int], Level]) -> LevelSource:
    """A family of square levels ``kind:low..high``: ``draw_level(side, pool, rng)`` after the side is drawn;
    ``level_of(side, seed)`` makes its first (largest) level."""
    low, high = check_family_sides(low, high)
    pool = range(FAMILY_SEEDS) if seeds is None else seeds
    if len(pool) == 0:
        raise ValueError("seeds: an empty set of maze seeds")

    def draw(rng: np.random.Generator) -> Level:
        return draw_level(int(rng.integers(low, high + 1)), pool, rng)

    draw.family = f"{kind}:{low}..{high}"  # type: ignore[attr-defined]
    draw.largest = (high, high)  # type: ignore[attr-defined]
    draw.first = lambda: level_of(high, int(pool[0]))  # type: ignore[attr-defined]
    return draw


def parse_level_family(spec: str, seeds: Sequence[int] | range | None = None) -> LevelSource | None:
    """The family of ``spec`` if it is ``"maze:A..B"`` or ``"gridmaze:A..B"`` (``None`` if ``spec`` is
    not a family spec); a ``ValueError`` naming ``level`` and the allowed forms for a malformed one."""
    if not isinstance(spec, str) or not spec.startswith(("maze:", "gridmaze:")):
        return None
    m = _RANGE.fullmatch(spec)
    if m is None:
        raise ValueError(bad_family(spec))
    family = grid_maze_family if m[1] else maze_range_family
    return family(int(m[2]), int(m[3]), seeds)


def family_of(spec: str, seeds: Sequence[int] | range | None = None) -> LevelSource | None:
    """The family of a spec of either form, ``"maze:A..B"`` or ``"maze-WxH-*"``, its maze seeds drawn from
    ``seeds`` (``None`` if ``spec`` names no family)."""
    family = parse_level_family(spec, seeds)
    m = _FAMILY.fullmatch(spec) if family is None and isinstance(spec, str) else None
    return maze_family(int(m[1]), int(m[2]), seeds) if m else family


def level_source(level: Any, need_exit: bool = True) -> LevelSource | None:
    """The drawing function of ``level=`` (``None`` for one fixed level: a name, a text or a ``Level``);
    ``need_exit``: the levels it draws must have an exit."""
    if isinstance(level, str):
        family = parse_level_family(level)
        if family is not None:
            return family
        if "\n" in level or not level.endswith("*"):
            return None
        m = _FAMILY.fullmatch(level)
        if m is None:
            raise ValueError(f"level: a level family is 'maze-WxH-*' (e.g. 'maze-16x16-*'), got {level!r}")
        return maze_family(int(m[1]), int(m[2]))
    if isinstance(level, Level) or not callable(level):
        return None
    if getattr(level, "family", None) is not None:  # maze_family, maze_range_family: returns Levels, keeps its attributes
        return level
    def draw(rng: np.random.Generator) -> Level:
        got = level(rng)
        if not isinstance(got, (str, Level)):
            raise TypeError(f"level: the level callable returned {type(got).__name__}; expected a Level, a name or a text")
        return resolve_level(got, need_exit)

    return draw


class LevelPicker:
    """The race's levels, a part the env holds: one fixed level, or a source drawn from at each reset.

    ``first`` is the level the env is built on (a family of sizes: one of its largest size; another
    source: drawn from a generator of its own, seed 0, only to learn the size); ``fixed`` says
    whether there is nothing to draw; ``largest`` is ``(W, H)`` of the largest level it draws.
    """

    def __init__(self, level: Any, need_exit: bool = True) -> None:
        self.source = level_source(level, need_exit)
        first = getattr(self.source, "first", None)  # a family of sizes: built on its largest
        self.first: Level = resolve_level(
            level if self.fixed else first() if first is not None else self.source(np.random.default_rng(0)), need_exit
        )
        self.largest: tuple[int, int] = getattr(self.source, "largest", (self.first.width, self.first.height))

    @property
    def fixed(self) -> bool:
        return self.source is None

    def check_one_level(self, what: str) -> None:
        """A ``ValueError`` naming ``what`` (which runs one level in all its envs) if levels are drawn."""
        if not self.fixed:
            raise ValueError(f"level: {what} runs one level in all its envs; drawn levels are for parallel_env and env")

    def draw(self, rng: np.random.Generator, current: Level) -> Level | None:
        """A new level from ``rng`` (the env's generator), the size of ``current`` (a family of sizes: at
        most ``largest``); None for a fixed level."""
        if self.fixed:
            return None
        level = self.source(rng)
        if hasattr(self.source, "largest"):
            w, h = self.largest
            if level.width > w or level.height > h:
                raise ValueError(f"level: drawn levels must fit in {w}x{h}, got {level.width}x{level.height}")
            return level
        if (level.width, level.height) != (current.width, current.height):
            raise ValueError(
                f"level: drawn levels must all be {current.width}x{current.height} (the observation spaces hold the size), "
                f"got {level.width}x{level.height}"
            )
        return level
