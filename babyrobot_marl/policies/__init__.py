"""Scripted robots: ``random`` and ``shortest``; ``make(name, table, seed)`` builds one by name."""

from __future__ import annotations

from ..core.table import Table
from .random import RandomPolicy
from .shortest import ShortestPathPolicy, distances, shortest_path_actions

POLICY_NAMES = ("random", "shortest")


def make(name: str, table: Table, seed: int | None = None) -> RandomPolicy | ShortestPathPolicy:
    """A scripted policy by name: ``"random"`` (seeded) or ``"shortest"``."""
    if name == "random":
        return RandomPolicy(seed)
    if name == "shortest":
        return ShortestPathPolicy(table)
    raise ValueError(f"policy: unknown policy {name!r}; known policies: {', '.join(POLICY_NAMES)}")


__all__ = ["POLICY_NAMES", "RandomPolicy", "ShortestPathPolicy", "distances", "make", "shortest_path_actions"]
