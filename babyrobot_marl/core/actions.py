"""The five actions and the cell offsets they aim at."""

from __future__ import annotations

from enum import IntEnum


class Action(IntEnum):
    """What a robot can do in one step. NORTH decreases ``y``, EAST increases ``x``."""

    STAY = 0
    NORTH = 1
    EAST = 2
    SOUTH = 3
    WEST = 4


N_ACTIONS = len(Action)

# (dx, dy) per action, indexed by the action's value.
DELTAS: tuple[tuple[int, int], ...] = ((0, 0), (0, -1), (1, 0), (0, 1), (-1, 0))

ARROWS = ("·", "↑", "→", "↓", "←")
