"""The envs' argument checks: render modes, reset options, encodings, start cells, and the vector
envs' counts, actions, seeds and reset masks.

The rules for integers, seeds, actions and enums are the core's (``core.checks``); the sentences
here are the envs' own. Pure functions, so every env shell (single, race, vector, SB3) shares them.
"""

from __future__ import annotations

import warnings
from collections.abc import Collection, Mapping, Sequence
from functools import lru_cache
from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.checks import ACTION_HELP, check_batch, check_choice, check_int, check_seed
from ..core.goals import reach
from ..core.level import as_cell
from ..core.table import Table
from .autoreset import SAME_STEP, resolve_autoreset_mode
from .encodings import ENCODINGS


def check_render_mode(render_mode: str | None, modes: list[str]) -> str | None:
    return check_choice(render_mode, "render_mode", modes, none=True)


def check_options(options: object, known: Collection[str] = ()) -> Mapping[str, Any]:
    """``reset(options=...)``: None or a dict; only the ``known`` keys are returned.

    An unknown key is a ``UserWarning`` naming the known ones, not an error: PettingZoo's and
    Gymnasium's own tests reset with arbitrary options (``{"options": 1}``). A known key's value
    is checked by the env.
    """
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise ValueError(f"options: expected a dict or None, got {type(options).__name__}")
    unknown = [k for k in options if k not in known]
    if not unknown:
        return options
    allowed = ", ".join(map(repr, known)) if known else "none"
    names = ", ".join(map(repr, unknown))
    # stacklevel 3: the line that called reset()
    warnings.warn(f"options: unknown option {names} ignored; known options are {allowed}", UserWarning, stacklevel=3)
    return {k: v for k, v in options.items() if k in known}


def check_encoding(encoding: object, what: str = "obs_encoding") -> str:
    return check_choice(encoding, what, ENCODINGS)


def _open_cell(table: Table, cell: object, what: str, not_a_cell: str, outside: str, closed: str) -> int:
    """``cell`` as the id of an open cell of ``table`` (inside the grid, neither blocked nor an exit); else a
    ``ValueError`` from the caller's wording (``{cell}``: the value given, ``{xy}``: the cell, ``{size}``: the grid)."""
    try:
        x, y = as_cell(cell, what)  # integers only: (1.5, 0) is not a cell
    except ValueError:
        raise ValueError(not_a_cell.format(cell=repr(cell))) from None
    if not (0 <= x < table.width and 0 <= y < table.height):
        raise ValueError(outside.format(xy=(x, y), size=f"{table.width}x{table.height}"))
    c = table.cell_id((x, y))
    if table.blocked[c] or table.is_exit[c]:
        raise ValueError(closed.format(xy=(x, y)))
    return c


def check_start(table: Table, start: object) -> int:
    """The single-robot env's ``options["start"]``: an open cell ``(x, y)`` of ``table``, as its id."""
    what = "options['start']"
    return _open_cell(table, start, what, f"{what}: expected a cell (x, y) of integers, got {{cell}}",
                      f"{what}: cell {{xy}} is outside the {{size}} grid",
                      f"{what}: cell {{xy}} is blocked or an exit; start on an open cell")


def check_envs(n_envs: object, what: str, n_robots: object = 1, observe: object = "global") -> int:
    """A vector env's env count, checked against the batch limits (``checks.check_batch``) before
    any env exists: the "global" rows' size follows from ``n_robots`` alone (the batch engine
    checks the other modes' once their observer is built)."""
    n = check_int(n_envs, what, lo=1)
    try:
        robots = check_int(n_robots, "n_robots", lo=1)
    except ValueError:
        robots = 1  # the race env names a bad n_robots itself
    check_batch(n, robots, 3 * robots - 1 if observe == "global" and robots > 1 else 2, what)
    return n


_INT64, _INTP = np.dtype(np.int64), np.dtype(np.intp)


@lru_cache(maxsize=16)
def _action_limit(size: int) -> np.ndarray:
    """``N_ACTIONS`` as a ``(size,)`` uint64 array: comparing with an array skips numpy's scalar handling
    (half the cost of a comparison at 64 envs, where a vector step takes microseconds)."""
    limit = np.full(size, N_ACTIONS, dtype=np.uint64)
    limit.setflags(write=False)
    return limit


def check_actions(actions: Any, n_envs: int, n_robots: int) -> np.ndarray:
    """``(n_envs, n_robots)`` actions, or a ``ValueError`` naming ``actions`` (nothing changes)."""
    a = np.asarray(actions)
    if a.shape != (n_envs * n_robots,):
        raise ValueError(f"actions: expected an array of shape ({n_envs * n_robots},), one action per env, got shape {a.shape}")
    if a.dtype.kind not in "iu":
        raise ValueError(f"actions: expected integer actions ({ACTION_HELP}), got dtype {a.dtype}")
    # one comparison: as unsigned, negative actions are huge
    if np.count_nonzero(a.view(np.uint64) >= _action_limit(a.size) if a.dtype is _INT64 else (a < 0) | (a >= N_ACTIONS)):
        k = int(np.flatnonzero((a < 0) | (a >= N_ACTIONS))[0])
        raise ValueError(f"actions: must be integers in 0..{N_ACTIONS - 1} ({ACTION_HELP}), got {a[k]} at index {k}")
    return (a if a.dtype is _INTP else a.astype(np.intp)).reshape(n_envs, n_robots)


def seed_list(seed: object, n: int) -> list[int | None]:
    """One seed (or None) per env from ``reset``'s ``seed`` argument."""
    if seed is None or isinstance(seed, (bool, np.bool_, float, int, np.integer, np.floating)):
        s = check_seed(seed)
        return [None if s is None else s + i for i in range(n)]
    if isinstance(seed, (str, bytes)) or not isinstance(seed, Sequence):
        raise ValueError(f"seed: expected None, an int or a list of {n} ints, got {type(seed).__name__}")
    if len(seed) != n:
        raise ValueError(f"seed: a list of seeds needs one per env ({n}), got {len(seed)}")
    return [check_seed(s, "seed: each seed") for s in seed]


def mask_envs(reset_mask: object, n_envs: int, n_robots: int) -> np.ndarray:
    """The envs to reset: all, or those of ``options["reset_mask"]`` (checked as ``SyncVectorEnv`` does)."""
    if reset_mask is None:
        return np.arange(n_envs)
    if not isinstance(reset_mask, np.ndarray):
        raise TypeError(f"options['reset_mask']: must be a numpy array, got {type(reset_mask).__name__}")
    if reset_mask.shape != (n_envs * n_robots,):
        raise ValueError(f"options['reset_mask']: must have shape ({n_envs * n_robots},), got {reset_mask.shape}")
    if reset_mask.dtype != np.bool_:
        raise TypeError(f"options['reset_mask']: must have dtype bool, got {reset_mask.dtype}")
    if not reset_mask.any():
        raise ValueError("options['reset_mask']: must contain at least one True value")
    per_env = reset_mask.reshape(n_envs, n_robots)
    if not (per_env == per_env[:, :1]).all():
        raise ValueError("options['reset_mask']: the slots of one race are reset together; mask all or none of them")
    return np.flatnonzero(per_env[:, 0])


def check_cells(table: Table, cells: object, n: int, what: str, distinct: bool = True) -> list[int]:
    """``n`` cells ``(x, y)`` as cell ids: each inside the grid, neither blocked nor an exit, and
    (``distinct``) no two the same; else a ``ValueError`` naming ``what`` and what is allowed."""
    allowed = f"{n} distinct open cells (x, y), one per robot, not blocked and not an exit"
    return _cell_list(table, cells, n, what, allowed, "blocked or an exit", "share a cell" if distinct else None)


def _cell_list(table: Table, cells: object, n: int, what: str, allowed: str, closed: str, shared: str | None) -> list[int]:
    """``n`` open cells as ids (``shared``: the words for two the same, ``None`` if they may be); else a
    ``ValueError`` naming ``what`` and saying ``allowed``."""
    if not isinstance(cells, Sequence) or isinstance(cells, (str, bytes)):
        raise ValueError(f"{what}: expected a list of {allowed}, got {cells!r}")
    if len(cells) != n:
        raise ValueError(f"{what}: expected {allowed}; got {len(cells)} cells")
    ids = [_open_cell(table, cell, what, f"{what}: expected {allowed}; {{cell}} is not a cell (x, y) of integers",
                      f"{what}: {{xy}} is outside the {{size}} grid; expected {allowed}",
                      f"{what}: {{xy}} is {closed}; expected {allowed}") for cell in cells]
    if shared is not None and len(set(ids)) < len(ids):
        raise ValueError(f"{what}: two robots {shared}; expected {allowed}")
    return ids


def check_no_goals(options: object, goals_mode: str) -> None:
    """A race to the exits takes no ``"goals"`` option: an error naming it (not the unknown-option warning)."""
    if goals_mode != "own" and isinstance(options, Mapping) and "goals" in options:
        raise ValueError(
            f"options[\"goals\"]: own goals need goals='own'; this race's robots go to the exits (goals={goals_mode!r})"
        )


def _switch(value: object, name: str) -> bool:
    """``value`` as a bool; a ``ValueError`` naming ``name`` unless it is True or False."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name}: must be True or False, got {value!r}")
    return bool(value)


def check_lifelong(lifelong: object, goals_mode: str) -> bool:
    """``lifelong``: a bool, ``True`` only with own goals (a robot's next target needs one to replace)."""
    if _switch(lifelong, "lifelong") and goals_mode != "own":
        raise ValueError(f"lifelong: new targets are for own goals (goals='own'), got goals={goals_mode!r}")
    return bool(lifelong)


def check_finished(finished: object, modes: tuple[str, ...], goals_mode: str, lifelong: bool) -> str:
    """``finished``: one of ``modes``; ``"stay"`` (robots stay on their targets, racing on) only with own goals and
    without ``lifelong`` (where a robot on its target gets a new one)."""
    check_choice(finished, "finished", modes)
    if finished == "stay" and (goals_mode != "own" or lifelong):
        got = f"goals={goals_mode!r}" if goals_mode != "own" else "lifelong=True"
        raise ValueError(f"finished: 'stay' keeps robots on their own targets (goals='own', lifelong=False), got {got}")
    return str(finished)


def check_goal_cells(table: Table, cells: object, n: int, goals_mode: str, what: str = 'options["goals"]') -> list[int]:
    """``reset``'s own goals: ``n`` distinct cells ``(x, y)``, one per robot, not blocked (exits are floor with own
    goals), as cell ids; else a ``ValueError`` naming ``what``. Only with ``goals="own"``."""
    check_no_goals({"goals": cells}, goals_mode)
    allowed = f"{n} distinct cells (x, y), one goal per robot, not blocked"
    return _cell_list(table, cells, n, what, allowed, "blocked", "share a goal")


def check_goals_reach(table: Table, goals: Sequence[int], starts: Sequence[int], what: str = 'options["goals"]') -> None:
    """Each robot's goal is reachable from its start (one robot's moves) and is not that start; else a ``ValueError``."""
    part = reach(table).component
    for i, (g, s) in enumerate(zip(goals, starts)):
        if g == s or part[g] != part[s]:
            why = "is its start" if g == s else f"cannot be reached from its start {table.cell_xy(s)}"
            raise ValueError(
                f"{what}: robot_{i}'s goal {table.cell_xy(g)} {why}; each goal must be reachable from its robot's start"
            )


def check_sb3_autoreset(mode: object) -> None:
    """``mode`` is Gymnasium's same-step auto-reset, the only one an SB3 ``VecEnv`` has; else a ``ValueError``."""
    _, name = resolve_autoreset_mode(mode)
    if name != SAME_STEP:
        raise ValueError(
            f"autoreset_mode: a Stable-Baselines3 VecEnv always resets an env in the step it ends (its last "
            f"observation in infos[k]['terminal_observation']), which is 'same-step'; got {mode!r}"
        )


def check_hint(hint: object, observe: object) -> bool:
    """``hint``: a bool, ``True`` only with ``observe="local"`` (the goal hint follows the local window)."""
    if _switch(hint, "hint") and observe != "local":
        raise ValueError(f"hint: the goal hint is for observe='local' (it follows the local window), got observe={observe!r}")
    return bool(hint)
