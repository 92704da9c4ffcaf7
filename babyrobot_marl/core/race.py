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

Finished robots are off the board: they neither move nor block, so the functions here take
the racing robots only, with their robot numbers to address the random draws.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from operator import getitem

from .engine import MOVED, SKIDDED, move
from .rng import SLOT_PRIORITY, SLOTS, uniform
from .table import TableLists


def resolve_collisions(
    mode: str, cells: Sequence[int], desired: Sequence[int], key: int, step: int, robots: Sequence[int] | None = None, n: int = 0
) -> Sequence[int]:
    """Final cells after the collision rules of ``mode``, from the current and desired cells.

    ``cells`` and ``desired`` list the racing robots only (finished robots are off the board);
    ``robots`` are their numbers (default ``0, 1, ...``) and ``n`` the robots in the race
    (default ``len(cells)``): they address the uniform draws of "block". Returns ``desired``
    itself (not a copy) when no robot is stopped by another.
    """
    if mode == "pass":
        return desired
    m = len(cells)
    # The common case, returned as is: no two robots head for one cell, and no robot heads for
    # a cell occupied now. Then the cells now and the cells ahead together hold each robot's
    # cell once and each mover's new cell once more.
    if len({*cells, *desired}) == m + sum(map(operator.ne, cells, desired)):
        return desired
    if len(set(desired)) == m:
        # No two robots head for one cell: only a staying occupant or a swap can stop a robot,
        # and if neither happens every chain of followers ends at a free cell or goes round.
        going = dict(zip(cells, desired))  # cell -> where its robot is heading
        for c, d in zip(cells, desired):
            if c != d and d in going and going[d] in (c, d):  # its occupant stays, or a swap
                break
        else:
            return desired
    robots = range(m) if robots is None else robots
    n = n or m
    occupant = {c: k for k, c in enumerate(cells)}
    final = list(desired)
    changed = True
    while changed:
        changed = False
        contests: dict[int, list[int]] = {}
        for k in range(m):
            dest = final[k]
            if dest == cells[k]:
                continue
            j = occupant.get(dest)
            if j is not None and (final[j] == cells[j] or final[j] == cells[k]):
                # its occupant stays, or the two would swap: both cases leave k in place
                final[k] = cells[k]
                if final[j] == cells[k]:
                    final[j] = cells[j]
                changed = True
            else:
                contests.setdefault(dest, []).append(k)
        for group in contests.values():
            if len(group) < 2 or any(final[k] == cells[k] for k in group):
                continue  # no contest, or found stale: the next round looks again
            keep = -1 if mode == "bounce" else max(group, key=lambda k: _priority(key, step, n, robots[k]))
            for k in group:
                if k != keep:
                    final[k] = cells[k]
            changed = True
    return final


def _priority(key: int, step: int, n: int, robot: int) -> float:
    """The uniform that ranks a robot in a contest for a cell under "block"."""
    return uniform(key, (step * n + robot) * SLOTS + SLOT_PRIORITY)


def race_step(
    t: TableLists,
    mode: str,
    cells: Sequence[int],
    actions: Sequence[int],
    key: int,
    step: int,
    robots: Sequence[int] | None = None,
    n: int = 0,
) -> tuple[Sequence[int], Sequence[int], list[bool], list[bool]]:
    """One race step of the racing robots: ``(new cells, outcome codes, blocked by a robot, finished now)``.

    ``cells`` and ``actions`` list the racing robots only, ``robots`` their numbers and ``n``
    the robots in the race, as for ``resolve_collisions``. Rewards are the caller's: the cell
    reward ``t.reward[new cell]`` of every robot, plus any finishing bonus.
    """
    m = len(cells)
    if not m:
        return [], [], [], []
    # Table look-ups in C (map): the `sure` table holds the outcome of every cell and action
    # that needs no random draw; only puddles and glass walls go through `move`.
    moves = list(map(getitem, map(t.sure.__getitem__, cells), actions))
    if None in moves:
        robots = range(m) if robots is None else robots
        base = step * (n or m) * SLOTS
        for k in range(m):
            if moves[k] is None:
                moves[k] = move(t, cells[k], actions[k], key, base + robots[k] * SLOTS)
    desired, outcome = zip(*moves)
    if mode == "pass":
        final = desired
    # resolve_collisions' own first test, inlined; without skids the robots that move are the MOVED ones
    elif len({*cells, *desired}) == m + (
        outcome.count(MOVED) if SKIDDED not in outcome else sum(map(operator.ne, cells, desired))
    ):
        final = desired  # nobody in anybody's way
    else:
        final = resolve_collisions(mode, cells, desired, key, step, robots, n)
    blocked = [False] * m if final is desired else list(map(operator.ne, final, desired))
    finished = [False] * m if t.exits.isdisjoint(final) else list(map(t.is_exit.__getitem__, final))
    return final, outcome, blocked, finished
