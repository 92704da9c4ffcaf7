"""Where the robots of a race start (the level's numbered starts, random free cells, or cells given), drawn
from the race's generator."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core.table import Table


def new_generator(seed: int | None) -> np.random.Generator:
    """A generator as Gymnasium's ``Env`` seeds its own (``seeding.np_random``); None: unseeded."""
    from gymnasium.utils import seeding

    return seeding.np_random(seed)[0]


def placement(table: Table, start: str, n: int) -> tuple[list[int], list[int]]:
    """Level starts used as they are, and the free cells random starts are drawn from (``start``:
    ``"level"``, ``"fill"`` or ``"random"``); a ``ValueError`` naming ``n_robots`` if they do not fit."""
    level = table.level
    starts = [table.cell_id(c) for c in level.starts]
    if start == "level":
        if len(starts) < n:
            raise ValueError(
                f"n_robots: level {level.name or ''!r} has {len(starts)} numbered starts for {n} robots; "
                "pass start='fill' (level starts, then random free cells) or start='random'"
            )
        return starts[:n], []
    fixed = starts[:n] if start == "fill" else []
    free = [c for c in table.free_cells if c not in fixed]
    if len(fixed) + len(free) < n:
        fits = len(fixed) + len(free)
        raise ValueError(f"n_robots: {n} robots do not fit on level {level.name or ''!r}, which has {fits} free cells")
    return fixed, free


def draw_starts(rng: np.random.Generator, fixed: Sequence[int], free: Sequence[int], n: int) -> list[int]:
    """The fixed starts, then random distinct free cells for the other robots (drawn from ``rng``)."""
    need = n - len(fixed)
    if need == 0:
        return list(fixed)
    picks = rng.choice(len(free), size=need, replace=False)
    return list(fixed) + [free[int(k)] for k in picks]
