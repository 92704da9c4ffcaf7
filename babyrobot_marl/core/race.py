"""One step of a race: every robot's own move (``engine.move``), then collisions, then finishing.

Collision rules (DESIGN.md), applied after every racing robot's outcome, skids included:

- ``"block"``: when several robots would end in the same cell, one of them, drawn uniformly,
  gets it and the others stay; two robots may not swap cells (both stay); a robot may follow
  into a cell that its occupant leaves in the same step, but not into a cell whose occupant
  stays. Resolved until nothing changes.
- ``"bounce"``: like block, but when several robots would end in the same cell, all stay.
- ``"pass"``: robots do not interact and may share cells.
- ``"soft"``: POGEMA's soft rule (``collision_system="soft"``): like block, but a contest for
  a cell goes to the lowest-numbered robot, with no draw. POGEMA reverts moves one robot at a
  time (highest number first, each revert cascading back along the robots heading for the
  reverted robot's cell); the result is the same closure as block's with that winner.

The uniform draw of "block" gives each robot a priority ``rng.uniform`` at its
``SLOT_PRIORITY`` address; the highest priority among the contenders wins. Robots only ever
go from moving to staying, so the result is the smallest set of staying robots closed under
the rules: it does not depend on the order in which conflicts are found, and one pass that
spreads each stop to the robots behind finds it in time linear in the robots.

Finished robots are off the board: they neither move nor block, so the functions here take
the racing robots only, with their robot numbers to address the random draws.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from itertools import compress
from operator import getitem

import numpy as np

from .actions import N_ACTIONS
from .engine import move
from .rng import SLOT_PRIORITY, SLOTS, uniform, uniform_array
from .table import TableLists


def resolve_collisions(
    mode: str, cells: Sequence[int], desired: Sequence[int], key: int, step: int, robots: Sequence[int] | None = None, n: int = 0
) -> Sequence[int]:
    """Final cells after the collision rules of ``mode``, from the current and desired cells.

    ``cells`` and ``desired`` list the racing robots only (finished robots are off the board);
    ``robots`` are their numbers (default ``0, 1, ...``) and ``n`` the robots in the race
    (default ``len(cells)``): they address the uniform draws of "block". Returns ``desired``
    itself (not a copy) when no robot is stopped by another.

    The rules only ever turn movers into stayers, so the result is the smallest set of stayers
    closed under them: a mover in a swap or losing a contest stays (both read off ``desired``
    alone), and a mover heading for the cell of a robot that stays stays too. So stopping
    spreads backwards along "heads for the cell of" from the robots that do not move and the
    swaps and contest losers. Only movers heading for a cell held now or contesting a cell can
    be stopped at all: they are found by passes in C over every robot (sets of cells), and
    looked at one by one; O(n) whatever the numbering (O(n log n) in C when cells are contested:
    a sort). From ``_ARRAYS_FROM`` racing robots on, those passes are numpy's, and past
    ``_ONE_BY_ONE_UP_TO`` such movers the closure too, by pointer doubling as in the batch
    engine (``_resolve_on_arrays``).
    """
    if mode == "pass":
        return desired
    return _stop_movers(mode, cells, desired, key, step, robots, n)


def _stop_movers(
    mode: str, cells: Sequence[int], desired: Sequence[int], key: int, step: int, robots: Sequence[int] | None, n: int
) -> Sequence[int]:
    """``resolve_collisions`` under an exclusive rule ("block", "bounce", "soft")."""
    m = len(cells)
    if m and m >= _ARRAYS_FROM:
        c, d = np.asarray(cells, dtype=np.int64), np.asarray(desired, dtype=np.int64)
        final = _stop_movers_arrays(mode, cells, c, d, key, step, robots, n, int(max(c.max(), d.max())) + 1)
        return desired if final is d else final.tolist()
    ahead = list(compress(desired, map(operator.ne, cells, desired)))  # the movers' destinations
    occupied = set(cells)
    held = occupied.intersection(ahead)  # destinations a robot holds now
    n_ahead = len(set(ahead))
    if not held and n_ahead == len(ahead):  # the common case: nobody in anybody's way
        return desired
    if n_ahead < len(ahead):  # and destinations two movers or more head for (equal neighbours once sorted)
        ahead.sort()
        held.update(compress(ahead, map(operator.eq, ahead, ahead[1:])))
    # cell -> the movers heading for it, ascending: for those few cells only (their robots found in C)
    heading: dict[int, list[int]] = {}
    for k in compress(range(m), map(held.__contains__, desired)):
        d = desired[k]
        if cells[k] != d:  # not the robot staying there
            heading.setdefault(d, []).append(k)
    holder = {cells[j]: j for j in compress(range(m), map(held.__contains__, cells))}  # held cell -> its robot
    stopped = _stopped_movers(mode, heading, holder, cells, desired, key, step, robots, n or m)
    if not stopped:
        return desired
    final = list(desired)
    for k in stopped:
        final[k] = cells[k]
    return final


def _stopped_movers(
    mode: str, heading: dict[int, list[int]], holder: dict[int, int], cells: Sequence[int], desired: Sequence[int],
    key: int, step: int, robots: Sequence[int] | None, n: int,
) -> set[int]:
    """The movers that stay: ``heading`` maps each cell that can stop a mover to its movers (ascending),
    ``holder`` the held ones among them to the robot holding it."""
    stopped: set[int] = set()
    for d, group in heading.items():
        j = holder.get(d)
        if j is not None:
            dj = desired[j]
            if dj == d:  # its robot stays: nobody gets in
                stopped.update(group)
                continue
            for k in group:
                if cells[k] == dj:  # k and j would swap
                    stopped.add(k)
        if len(group) > 1:  # a contest: block lets the highest priority in, soft the lowest number, bounce nobody
            if mode == "bounce":
                stopped.update(group)
            else:
                keep = _contest_winner(mode, group, key, step, n, robots)
                stopped.update(k for k in group if k != keep)
    todo = list(stopped)  # a robot that stays stops the movers heading for its cell, and so on back
    while todo:
        for k in heading.get(cells[todo.pop()], ()):
            if k not in stopped:
                stopped.add(k)
                todo.append(k)
    return stopped


_LOOP_UP_TO = 8  # racing robots up to which race_step looks moves up in a plain loop
_ARRAYS_FROM = 128  # racing robots from which moves are looked up and conflicts found with numpy
# (on random maps of density 0.3: Python 1.3x faster at 64 robots, even at about 128, numpy 1.2-1.5x
# faster at 256 and 3.5x at 1,024)


def _stop_movers_arrays(
    mode: str, cells: Sequence[int], c: np.ndarray, d: np.ndarray, key: int, step: int, robots: Sequence[int] | None,
    n: int, size: int,
) -> np.ndarray:
    """``_stop_movers`` on arrays: ``c``, ``d`` the racing robots' cells and destinations (``cells``: ``c`` as
    a list), all below ``size``. The movers that can be stopped (heading for a held or contested cell)
    are found by array passes; a few are then resolved one by one as ``_stop_movers`` does, many on
    arrays (``_resolve_on_arrays``). Returns ``d`` itself when nobody is stopped, else a new array."""
    m = len(c)
    moving = d != c
    holder = np.full(size, -1, dtype=np.int64)  # cell -> the robot on it
    holder[c] = np.arange(m)
    held_by = holder.take(d)  # the robot on each robot's destination (itself for a robot that stays), -1: free
    hit = moving & (held_by >= 0)
    rival = moving & (np.bincount(d[moving], minlength=size).take(d) > 1)  # contesting a cell
    ks = np.flatnonzero(hit | rival)
    if len(ks) > _ONE_BY_ONE_UP_TO:
        return _resolve_on_arrays(mode, c, d, moving, held_by, hit, rival, key, step, robots, n)
    if not len(ks):
        return d
    heading: dict[int, list[int]] = {}  # cell -> the movers heading for it, ascending
    holder: dict[int, int] = {}  # a held destination -> its robot
    for k, dk, j in zip(ks.tolist(), d[ks].tolist(), held_by[ks].tolist()):
        group = heading.get(dk)
        if group is None:
            heading[dk] = [k]
            if j >= 0:
                holder[dk] = j
        else:
            group.append(k)
    stopped = _stopped_movers(mode, heading, holder, cells, d, key, step, robots, n or m)
    if not stopped:
        return d
    final = d.copy()
    back = np.fromiter(stopped, np.int64, len(stopped))
    final[back] = c[back]
    return final


_ONE_BY_ONE_UP_TO = 96  # movers that can be stopped up to which they are resolved in a Python loop


def _resolve_on_arrays(
    mode: str, c: np.ndarray, d: np.ndarray, moving: np.ndarray, held_by: np.ndarray, hit: np.ndarray,
    rival: np.ndarray, key: int, step: int, robots: Sequence[int] | None, n: int,
) -> np.ndarray:
    """``_stop_movers_arrays`` past its passes, on arrays (as the batch engine's ``resolve_collisions_array``):
    stayers, swaps and contest losers stop, then stopping spreads back along "heads for the cell of"
    by pointer doubling (``log2`` of the robots passes at most)."""
    m = len(c)
    stopped = ~moving
    k = np.flatnonzero(hit)
    stopped[k[d.take(held_by.take(k)) == c.take(k)]] = True  # swaps (a robot that stays is stopped already)
    r = np.flatnonzero(rival)
    if len(r) and mode == "bounce":
        stopped[r] = True
    elif len(r):  # each cell's contenders in order, the winner first: all but the first stop
        numbers = r if robots is None else np.fromiter(map(robots.__getitem__, r.tolist()), np.int64, len(r))
        if mode == "soft":  # the lowest robot number
            order = np.lexsort((numbers, d.take(r)))
        else:  # the highest priority, the first contender on a tie (as max() picks)
            counts = (np.uint64(step * (n or m)) + numbers.astype(np.uint64)) * np.uint64(SLOTS) + np.uint64(SLOT_PRIORITY)
            order = np.lexsort((r, -uniform_array(np.uint64(key), counts), d.take(r)))
        r = r.take(order)
        dr = d.take(r)
        stopped[r[1:][dr[1:] == dr[:-1]]] = True
    back = spread_stops(stopped, hit & ~stopped, held_by, m.bit_length()) & moving
    if not back.any():
        return d
    final = d.copy()
    final[back] = c[back]
    return final


def spread_stops(stopped: np.ndarray, follows: np.ndarray, occupant: np.ndarray, passes: int) -> np.ndarray:
    """Every robot that stays: the ``stopped`` ones, and each follower (``follows``: heading for the cell
    of robot ``occupant[i]``) with a stopped robot ahead on its chain, by pointer doubling in ``passes``
    passes (the chains double each pass: ``log2`` of the longest chain covers any cycle). Followers still
    open after them go round a cycle with nobody stopped: they move."""
    size = len(stopped)
    open_ = np.flatnonzero(follows)
    ahead = np.full(size + 1, size, dtype=np.int64)  # size: the end of a chain, never stopped
    ahead[open_] = occupant.take(open_)
    stop = np.append(stopped, False)
    for _ in range(passes):
        if not len(open_):
            break
        nxt = ahead.take(open_)
        stop[open_] |= stop.take(nxt)
        ahead[open_] = ahead.take(nxt)
        open_ = open_[~stop.take(open_) & (ahead.take(open_) != size)]  # the rest go round a cycle, or not yet known
    return stop[:size]


def _step_arrays(
    t: TableLists, flat: tuple[np.ndarray, np.ndarray], mode: str, cells: Sequence[int], actions: Sequence[int], key: int,
    step: int, robots: Sequence[int] | None, n: int,
) -> tuple[list[int], list[int], list[bool], list[bool]]:
    """``race_step`` of many robots: the look-ups in ``flat`` (``Table.sure_flat``) and the collision rules on arrays."""
    m = len(cells)
    nxt, code = flat
    c = np.fromiter(cells, np.int64, m)
    at = c * N_ACTIONS
    at += np.fromiter(actions, np.int64, m)
    d, o = nxt.take(at), code.take(at)
    if d.min() < 0:  # puddles and glass walls: their draws, as move makes them
        numbers = range(m) if robots is None else robots
        base = step * (n or m) * SLOTS
        for k in np.flatnonzero(d < 0).tolist():
            d[k], o[k] = move(t, cells[k], actions[k], key, base + numbers[k] * SLOTS)
    final = d if mode == "pass" else _stop_movers_arrays(mode, cells, c, d, key, step, robots, n, len(t.sure))
    out = final.tolist()
    blocked = [False] * m if final is d else (final != d).tolist()
    finished = [False] * m if t.exits.isdisjoint(out) else list(map(t.is_exit.__getitem__, out))
    return out, o.tolist(), blocked, finished


def _contest_winner(mode: str, group: list[int], key: int, step: int, n: int, robots: Sequence[int] | None) -> int:
    """Which of the movers ``group`` (indices into the racing robots) gets their cell: under "soft"
    the lowest robot number (POGEMA's order), under "block" the highest uniform priority."""
    numbers = range(n) if robots is None else robots
    if mode == "soft":
        return min(group, key=numbers.__getitem__)
    return max(group, key=lambda k: _priority(key, step, n, numbers[k]))


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
    flat: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[Sequence[int], Sequence[int], list[bool], list[bool]]:
    """One race step of the racing robots: ``(new cells, outcome codes, blocked by a robot, finished now)``.

    ``cells`` and ``actions`` list the racing robots only, ``robots`` their numbers and ``n``
    the robots in the race, as for ``resolve_collisions``. Rewards are the caller's: the cell
    reward ``t.reward[new cell]`` of every robot, plus any finishing bonus. ``flat``: the table's
    ``sure_flat``, for crowds of ``_ARRAYS_FROM`` robots or more (their steps on arrays).
    """
    m = len(cells)
    if m >= _ARRAYS_FROM and flat is not None:
        return _step_arrays(t, flat, mode, cells, actions, key, step, robots, n)
    if m == 1:  # a lone robot (the last one racing) meets nobody: one look-up, no collision rules
        cell, action = cells[0], actions[0]
        sure = t.sure[cell][action]
        robot = 0 if robots is None else robots[0]
        d, o = sure if sure is not None else move(t, cell, action, key, (step * (n or 1) + robot) * SLOTS)
        return (d,), (o,), [False], [t.is_exit[d]]
    if m == 2:  # two robots: their look-ups, and the collision rules in two comparisons
        (c0, c1), (a0, a1), sure = cells, actions, t.sure
        m0, m1 = sure[c0][a0], sure[c1][a1]
        if m0 is not None and m1 is not None:  # else (puddles, glass walls) the general way below
            (d0, o0), (d1, o1) = m0, m1
            # nobody stopped: no contest for a cell (nor a move into the cell of a robot that stays,
            # whose cell is its destination too) and no swap; following a robot that leaves is allowed
            if mode == "pass" or (d0 != d1 and (d0 != c1 or d1 != c0)):
                return (d0, d1), (o0, o1), [False, False], [t.is_exit[d0], t.is_exit[d1]]
    if not m:
        return [], [], [], []
    # The `sure` table holds the outcome of every cell and action that needs no random draw; only
    # puddles and glass walls go through `move`. Few robots: a plain loop (map's and zip's set-up
    # cost more than the look-ups); many: the look-ups in C (map).
    if m <= _LOOP_UP_TO:
        sure, desired, outcome = t.sure, [], []
        for k in range(m):
            cell, action = cells[k], actions[k]
            one = sure[cell][action]
            if one is None:
                robot = k if robots is None else robots[k]
                one = move(t, cell, action, key, (step * (n or m) + robot) * SLOTS)
            desired.append(one[0])
            outcome.append(one[1])
    else:
        moves = list(map(getitem, map(t.sure.__getitem__, cells), actions))
        if None in moves:
            robots = range(m) if robots is None else robots
            base = step * (n or m) * SLOTS
            for k in range(m):
                if moves[k] is None:
                    moves[k] = move(t, cells[k], actions[k], key, base + robots[k] * SLOTS)
        desired, outcome = zip(*moves)
    final = desired if mode == "pass" else _stop_movers(mode, cells, desired, key, step, robots, n)
    blocked = [False] * m if final is desired else list(map(operator.ne, final, desired))
    finished = [False] * m if t.exits.isdisjoint(final) else list(map(t.is_exit.__getitem__, final))
    return final, outcome, blocked, finished
