"""One step of a race: every robot's own move (``engine.move``), then collisions, then finishing.

Collision rules (DESIGN.md), applied after every racing robot's outcome, skids included:

- ``"block"``: when several robots would end in the same cell, one of them, drawn uniformly,
  gets it and the others stay; two robots may not swap cells (both stay); a robot may follow
  into a cell that its occupant leaves in the same step, but not into a cell whose occupant
  stays. Resolved until nothing changes.
- ``"bounce"``: like block, but when several robots would end in the same cell, all stay.
- ``"pass"``: robots do not interact and may share cells.

The uniform draw of "block" gives each robot a priority ``rng.uniform`` at its
``SLOT_PRIORITY`` address; the highest priority among the contenders wins. Robots only ever
go from moving to staying, so the loop ends after at most ``n_robots`` rounds, and the result
does not depend on the order in which conflicts are found.

Finished robots (``racing[i]`` False) are off the board: they neither move nor block.
"""

from __future__ import annotations

import operator
from itertools import compress

from .engine import move
from .rng import SLOT_PRIORITY, SLOTS, uniform
from .table import TableLists


def resolve_collisions(
    mode: str, cells: list[int], desired: list[int], racing: list[bool], key: int, step: int
) -> list[int]:
    """Final cells after the collision rules of ``mode``, from current and desired cells.

    Returns ``desired`` itself (not a copy) when no robot is stopped by another.
    """
    if mode == "pass":
        return desired
    n = len(cells)
    # The common case, returned as is: no two racing robots head for one cell, and only the
    # robots that stay head for a cell occupied now.
    if False in racing:
        now, heading = list(compress(cells, racing)), list(compress(desired, racing))
    else:
        now, heading = cells, desired
    heads = set(heading)
    if len(heads) == len(heading) and len(heads.intersection(now)) == sum(map(operator.eq, now, heading)):
        return desired
    live = [i for i in range(n) if racing[i]]
    occupant = {cells[i]: i for i in live}
    final = list(desired)
    changed = True
    while changed:
        changed = False
        contests: dict[int, list[int]] = {}
        for i in live:
            dest = final[i]
            if dest == cells[i]:
                continue
            j = occupant.get(dest)
            if j is not None and (final[j] == cells[j] or final[j] == cells[i]):
                # its occupant stays, or the two would swap: both cases leave i in place
                final[i] = cells[i]
                if final[j] == cells[i]:
                    final[j] = cells[j]
                changed = True
            else:
                contests.setdefault(dest, []).append(i)
        for group in contests.values():
            if len(group) < 2 or any(final[i] == cells[i] for i in group):
                continue  # no contest, or found stale: the next round looks again
            keep = -1 if mode == "bounce" else max(group, key=lambda i: _priority(key, step, n, i))
            for i in group:
                if i != keep:
                    final[i] = cells[i]
            changed = True
    return final


def _priority(key: int, step: int, n: int, robot: int) -> float:
    """The uniform that ranks a robot in a contest for a cell under "block"."""
    return uniform(key, (step * n + robot) * SLOTS + SLOT_PRIORITY)


def race_step(
    t: TableLists,
    mode: str,
    cells: list[int],
    racing: list[bool],
    actions: list[int],
    key: int,
    step: int,
) -> tuple[list[int], list[int], list[bool], list[bool]]:
    """One race step: ``(new cells, outcome codes, blocked by a robot, finished now)``.

    Robots not ``racing`` keep their cell and outcome -1. Rewards are the caller's: the cell
    reward ``t.reward[new cell]`` of every racing robot, plus any finishing bonus.
    """
    n = len(cells)
    base = step * n * SLOTS
    desired, outcome = list(cells), [-1] * n
    is_exit = t.is_exit
    near_exit = False  # only a robot heading for an exit can finish
    for i in range(n):
        if racing[i]:
            d, o = move(t, cells[i], actions[i], key, base + i * SLOTS)
            desired[i] = d
            outcome[i] = o
            near_exit = near_exit or is_exit[d]
    final = resolve_collisions(mode, cells, desired, racing, key, step)
    blocked = [False] * n if final is desired else [f != d for f, d in zip(final, desired)]
    finished = [r and is_exit[f] for f, r in zip(final, racing)] if near_exit else [False] * n
    return final, outcome, blocked, finished
