"""What a robot's neighbours intend (``PPOConfig.intents``): for each robot within ``near_radius`` steps, the
moves that shorten its way to its own target and whether it stands on it.

Where robots have targets of their own and stay on them (POGEMA's task), a robot decides well only if it
knows what the robots beside it are about: one on its target that another wants to pass must step aside,
two heading for one cell must not both press on. A window shows where the robots are, not where they go.
MAPF-GPT's robots read their neighbours' next shortest-path moves for the same reason; here each near cell
a racing robot stands on adds five units: its hint's four moves (north, east, south, west) and "on its
target". The units sit after every other part of a row (``WindowForm.n_in``); the near bits still say
where robots stand. An imitation policy (``imitation.py``) reads them: what PIBT decides for a robot hangs
on what the robots around it want.

With ``ranks`` a sixth unit says whether the robot there goes before this one: PIBT's priority, which
the robots keep as PIBT does (``Ranks``: steps since each last stood on its target, ties to the higher
robot number) and tell their neighbours, one number each. Who yields where two meet is PIBT's priority.

The parts are the same, to the index, whether built from the batch engine's arrays (the trainer's
judge, ``evaluate``) or from one env's robots (``WindowPolicy``, the maze benchmark): ``intent_rows``
takes cells, targets and hint bits as arrays of ``(envs, robots)`` either way, and the robots near each one
(``near_robots``), which its callers compute once for the intents and the turns.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from ...core.actions import N_ACTIONS
from ...core.goals import goal_hints
from .inputs import Inputs

INTENT_UNITS = 5  # per near cell: the hint's four moves, then "on its own target" (then, with ranks, "goes first")
_RANKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # each race env's robots' priorities (env_intents)
_STEPS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # each race env's intents at its step (step_intents)


class Ranks:
    """The robots' PIBT priorities as they keep them (Okumura et al. 2022): a robot's grows by one at each step
    it stands off its own target and is zero on it; ties go to the higher robot number (a fraction below one).
    ``values`` reads them at an env's step ``t``: once per step, whoever asks; ``t == 0`` (or a step before the
    last read) starts an episode."""

    def __init__(self, n_robots: int):
        self.ties = np.arange(n_robots) / max(n_robots, 1)
        self.elapsed = np.zeros((0, n_robots), dtype=np.int64)  # per env and robot: steps off its target
        self.t = np.zeros(0, dtype=np.int64)  # the step each env was read at last

    def values(self, cells: np.ndarray, goals: np.ndarray, t: np.ndarray) -> np.ndarray:
        """``(E, R)`` priorities of the robots on ``cells`` with targets ``goals`` (``(E, R)``) at steps ``t`` (``(E,)``)."""
        off = np.asarray(cells) != np.asarray(goals)
        t = np.asarray(t, dtype=np.int64).reshape(-1)
        if len(self.t) != len(t):
            self.elapsed, self.t = np.zeros(off.shape, dtype=np.int64), np.full_like(t, -1)  # read before step 0
        new = ((t == 0) | (t < self.t))[:, None]  # a new episode (unread steps before this one count as off)
        moved = ((t != self.t) | new[:, 0])[:, None]  # a step on from the last read (a missed step counts as off)
        grown = np.where(off, np.where(new, t[:, None] + 1, self.elapsed + (t - self.t)[:, None]), 0)
        self.elapsed = np.where(moved, grown, self.elapsed)
        self.t = t.copy()  # not the caller's array: the batch engine counts its steps in place
        return self.elapsed + self.ties


def near_robots(neighbours: np.ndarray, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
    """``(E, R, m)``: the racing robot on each of each robot's ``m`` near cells, -1 for none (``neighbours``:
    ``(n_cells + 1, m)``, the cell at each offset, ``n_cells`` off the grid; ``cells``, ``racing``: ``(E, R)``)."""
    cells = np.asarray(cells, dtype=np.int64)
    e, r = cells.shape
    stride = neighbours.shape[0]
    base = np.arange(e, dtype=np.int64)[:, None] * stride
    who = np.full(e * stride, -1, dtype=np.int64)  # the robot on each cell of each env (-1: none; cell n: never)
    robots = np.broadcast_to(np.arange(r, dtype=np.int64), (e, r))
    who[(cells + base)[racing]] = robots[racing]
    return who[neighbours[cells] + base[:, :, None]]


def goes_first(there: np.ndarray, ranks: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which near robots (``there``, ``near_robots``) go before each robot by ``ranks`` ``(E, R, m)``, their robot
    numbers (0 where none) and the envs' index, to look their parts up."""
    seen = there >= 0
    at = np.where(seen, there, 0)
    env = np.arange(there.shape[0])[:, None, None]
    ranks = np.asarray(ranks)
    return seen & (ranks[env, at] > ranks[..., None]), at, env


def intent_rows(there: np.ndarray, cells: np.ndarray, hints: np.ndarray, goals: np.ndarray, first: int, off: int,
                ranks: np.ndarray | None = None) -> np.ndarray:
    """``(E * R, m * u)`` indices (``u``: 5, 6 with ``ranks``): for each robot and each of its ``m`` near cells, the
    units of the racing robot standing there (``there``: ``near_robots``, ``(E, R, m)``), if any: ``first + u k + d - 1``
    for each move ``d`` (1-4) its ``hints`` bits (one number per robot, bit ``a``: action ``a`` shortens its way)
    allow, ``first + u k + 4`` if it stands on its ``goals`` cell, ``first + u k + 5`` if its ``ranks`` value is
    above the robot's; ``off`` (the net's padding index) for the rest. ``cells``, ``hints``, ``goals``, ``ranks``:
    ``(E, R)``."""
    cells = np.asarray(cells, dtype=np.int64)
    e, r, m = there.shape
    seen = there >= 0
    at = np.where(seen, there, 0)
    env = np.arange(e)[:, None, None]
    bits = np.asarray(hints, dtype=np.int64)[env, at]  # each neighbour's hint as one number
    on = (cells[env, at] == np.asarray(goals, dtype=np.int64)[env, at]) & seen
    moves = (bits[..., None] >> np.arange(1, N_ACTIONS)) & 1  # (E, R, m, 4)
    u = INTENT_UNITS + (ranks is not None)
    unit = first + np.arange(m)[:, None] * u + np.arange(u)
    out = np.full((e, r, m, u), off, dtype=np.int64)
    out[..., :4] = np.where((moves > 0) & seen[..., None], unit[:, :4], off)
    out[..., 4] = np.where(on, unit[:, 4], off)
    if ranks is not None:
        out[..., 5] = np.where(goes_first(there, ranks)[0], unit[:, 5], off)
    return out.reshape(e * r, m * u)


@lru_cache(maxsize=16)
def _neighbours(width: int, height: int, near: tuple[tuple[int, int], ...]) -> np.ndarray:
    return Inputs(width, height, near).neighbours


def env_ranks(race: Any) -> Ranks:
    """The priorities the robots of ``race`` (a ``RaceEnv``) keep: one ``Ranks`` per env, read once per step."""
    ranks = _RANKS.get(race)
    if ranks is None or len(ranks.ties) != race.n_robots:
        ranks = _RANKS[race] = Ranks(race.n_robots)
    return ranks


def env_crowd(env: Any, form: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray]:
    """What the robots of a ``race_v0`` env of own goals tell each other now: ``intent_rows`` ``(R, m * u)``, the
    robot on each one's near cells (``near_robots``, ``(1, R, m)``), with ``form.ranks`` their priorities
    (``env_ranks``, ``(1, R)``, read at every step), and which are racing (``(1, R)``); robot order, read from the
    env's public state (``robot_cells``, ``goals``, ``agents``, ``elapsed_steps``) as the batch engine's arrays give them."""
    race = getattr(env, "race", env)
    table = race.table
    agents = race.possible_agents
    live = set(race.agents)
    cells = np.array([[table.cell_id(tuple(c)) for c in race.robot_cells]], dtype=np.int64)
    goals = np.array([[table.cell_id(tuple(race.goals[a])) for a in agents]], dtype=np.int64)
    racing = np.array([[a in live for a in agents]])
    hints = goal_hints(table, cells, goals) @ (1 << np.arange(N_ACTIONS))
    near = _neighbours(table.width, table.height, tuple(form.near))
    ranks = env_ranks(race).values(cells, goals, np.array([race.elapsed_steps])) if form.ranks else None
    there = near_robots(near, cells, racing)
    return intent_rows(there, cells, hints, goals, form.intents_first, form.n_in, ranks), there, ranks, racing


def env_intents(env: Any, form: Any) -> np.ndarray:
    """``(n_robots, m * u)``: ``intent_rows`` for every robot of a ``race_v0`` env of own goals (``env_crowd``)."""
    return env_crowd(env, form)[0]


def robot_index(env: Any, xy: tuple[int, int]) -> int:
    """The number of the racing robot of ``env`` standing at ``xy`` (the one whose observation a policy reads)."""
    race = getattr(env, "race", env)
    live = set(race.agents)
    for i, (cell, agent) in enumerate(zip(race.robot_cells, race.possible_agents)):
        if agent in live and tuple(cell) == tuple(xy):
            return i
    raise ValueError(f"obs: no racing robot of this policy's env stands at {tuple(xy)}; bind the policy to the env whose "
                     "robots it acts for (policy.for_env(env))")


@dataclass(frozen=True)
class StepIntents:
    """The crowd's intents (``env_intents``) of a race env at one state (``step_intents``): the state, its level's
    table and the priorities' last read (``Ranks.t``, a new array at each read), both compared by identity, and the rows."""

    key: tuple
    table: Any
    read: Any
    rows: np.ndarray


def env_state(race: Any) -> tuple:
    """A race env's state as a key: its step first, the robots' cells and targets, the racing ones (with its level's
    table, compared by identity, it tells a step, a reset or robots placed by hand from the state it was read at)."""
    return (race.elapsed_steps, tuple(map(tuple, race.robot_cells)), tuple(map(tuple, (race.goals or {}).values())),
            tuple(race.agents))


def _ranks_read(race: Any, form: Any) -> Any:
    return env_ranks(race).t if form.ranks else None


def step_intents(env: Any, form: Any) -> np.ndarray:
    """``env_intents`` of a ``race_v0`` env of own goals, computed once per state of the env: its step, the robots'
    cells and targets, the racing ones, its level and ``form`` (a step, a reset, robots placed by hand: computed
    again). Every robot's call of a step (``robot_intents``) reads the crowd's one computation, as ``turns.env_turn``
    plans the crowd's step once. The robots' priorities (``env_ranks``) are read once at the step (a read of the
    same step gives the same); read by another since (``env_crowd``), the rows are computed again."""
    race = getattr(env, "race", env)
    key = (form, env_state(race))
    got = _STEPS.get(race)
    if got is None or got.key != key or got.table is not race.table or got.read is not _ranks_read(race, form):
        rows = env_intents(env, form)
        rows.setflags(write=False)  # every robot's call of the step reads it
        got = _STEPS[race] = StepIntents(key, race.table, _ranks_read(race, form), rows)
    return got.rows


def robot_intents(env: Any, form: Any, xy: tuple[int, int]) -> np.ndarray:
    """``(1, m * u)``: ``env_intents`` of the racing robot standing at ``xy`` (the one whose observation it is), from
    the crowd's intents at the env's step (``step_intents``: computed once per step, not once per robot)."""
    i = robot_index(env, xy)
    return step_intents(env, form)[i : i + 1].copy()
