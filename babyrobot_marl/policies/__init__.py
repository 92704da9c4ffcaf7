"""Scripted robots: ``random`` and ``shortest``; ``make(name, table, seed)`` builds one by name."""

from __future__ import annotations

import numpy as np

from ..core.checks import check_int
from ..core.table import Table
from .random import RandomPolicy
from .shortest import ShortestPathPolicy, distances, shortest_path_actions

POLICY_NAMES = ("random", "shortest")


def make(name: str, table: Table, seed: int | np.random.Generator | None = None) -> RandomPolicy | ShortestPathPolicy:
    """A scripted policy by name: ``"random"`` (seeded) or ``"shortest"``."""
    if not isinstance(table, Table):
        raise TypeError(f"table: expected a compiled Table (babyrobot_marl.compile_level(level)), got {type(table).__name__}")
    if name == "random":
        if not (seed is None or isinstance(seed, np.random.Generator)):
            try:
                seed = check_int(seed, "seed", lo=0)  # Python and numpy integers, not bools or floats
            except ValueError:
                raise ValueError(f"seed: a policy seed is None, an integer >= 0 or a numpy Generator, got {seed!r}") from None
        return RandomPolicy(seed)
    if name == "shortest":
        return ShortestPathPolicy(table)
    raise ValueError(f"policy: unknown policy {name!r}; known policies: {', '.join(POLICY_NAMES)}")


__all__ = ["POLICY_NAMES", "RandomPolicy", "ShortestPathPolicy", "distances", "make", "shortest_path_actions"]
