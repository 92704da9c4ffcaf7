"""Text views of a ``Solution``: the value grid and the greedy policy as arrows."""

from __future__ import annotations

import numpy as np

from .dp import Solution

ARROWS = {0: "o", 1: "↑", 2: "→", 3: "↓", 4: "←"}  # STAY as 'o'


def value_text(sol: Solution, decimals: int = 1) -> str:
    """The value grid, one row per line, right-aligned; ``#`` on blocked cells, ``-`` where no value."""
    cells = [
        ["#" if sol.blocked.reshape(sol.height, sol.width)[y, x] else ("-" if np.isnan(v) else f"{v:.{decimals}f}")
         for x, v in enumerate(row)]
        for y, row in enumerate(sol.value_grid)
    ]
    width = max(len(c) for row in cells for c in row)
    return "\n".join(" ".join(c.rjust(width) for c in row) for row in cells)


def policy_text(sol: Solution) -> str:
    """The greedy policy as arrows: ``E`` exits, ``#`` blocked, ``o`` STAY, ``.`` no value."""
    exits = sol.is_exit.reshape(sol.height, sol.width)
    blocked = sol.blocked.reshape(sol.height, sol.width)
    lines = []
    for y, row in enumerate(sol.policy_grid):
        chars = []
        for x, a in enumerate(row):
            chars.append("E" if exits[y, x] else "#" if blocked[y, x] else "." if a < 0 else ARROWS[int(a)])
        lines.append(" ".join(chars))
    return "\n".join(lines)
