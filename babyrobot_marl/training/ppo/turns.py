"""Robots that decide in turns (``WindowForm.turns``): at each step the robots of an imitation crowd choose in
the order of their priorities (``intents.Ranks``), each telling the robots near it what it chose, and each
reads, for every near robot that goes before it, the action that robot chose this step.

PIBT plans a step the same way: the robot longest off its target chooses first and the others make room.
A robot that only knows where its neighbours want to go cannot tell whether the one that goes first will
press on into its cell or step aside; told what it chose, it can. Robots far apart do not wait for each
other: a robot's turn (``waves``) comes one after the latest turn among the near robots that go before it,
so a crowd decides in a few turns, each one pass of the net for every robot whose turn it is.

In the steps PIBT labels, a robot reads the actions PIBT chose for the robots before it; driving, the ones
the net chose. A bound policy (``WindowPolicy``) plans its env's whole crowd at the first robot's call of a
step and answers every robot's call from that plan (``env_turn``).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...core.actions import N_ACTIONS
from .form import NO_ACTION, WindowForm
from .intents import env_crowd, env_state, goes_first

TURN_UNITS = N_ACTIONS  # per near cell: the action (0-4) the robot there chose this step, if it goes first
_TURNS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # each race env's plan of its step (env_turn)


def turn_rows(there: np.ndarray, ranks: np.ndarray, chosen: np.ndarray, first: int, off: int) -> np.ndarray:
    """``(E * R, m)`` indices: for each robot and near cell, ``first + 5 k + a`` if the robot there (``there``,
    ``intents.near_robots``) goes before it (``ranks``, ``(E, R)``) and chose action ``a`` (``chosen``, ``(E, R)``,
    -1: not yet); ``off`` (the net's padding index) for the rest."""
    e, r, m = there.shape
    before, at, env = goes_first(there, ranks)
    a = np.asarray(chosen, dtype=np.int64)[env, at]
    return np.where(before & (a >= 0), first + np.arange(m) * TURN_UNITS + a, off).reshape(e * r, m)


def waves(there: np.ndarray, ranks: np.ndarray) -> np.ndarray:
    """``(E, R)``: each robot's turn, 0 if no near robot goes before it, else one after the latest of theirs."""
    before, at, env = goes_first(there, ranks)
    turn = np.zeros(ranks.shape, dtype=np.int64)
    for _ in range(ranks.shape[1]):  # priorities are a strict order: each pass settles one more turn at least
        later = np.where(before, turn[env, at] + 1, 0).max(axis=2, initial=0)
        if np.array_equal(later, turn):
            break
        turn = later
    return turn


def decide_in_turns(base: np.ndarray, there: np.ndarray, ranks: np.ndarray, racing: np.ndarray,
                    probs: Callable[[np.ndarray], np.ndarray], pick: Callable[[np.ndarray], np.ndarray],
                    first: int, off: int) -> tuple[np.ndarray, np.ndarray]:
    """Every racing robot's action ``(E, R)`` (-1 for the rest) and probabilities ``(E * R, 5)``, turn by turn
    (``waves``): the rows of the robots whose turn it is (``base``, ``(E * R, K)``, then ``turn_rows`` of the
    actions chosen so far) through ``probs`` (rows to probabilities) and ``pick`` (probabilities to actions)."""
    e, r = ranks.shape
    turn = np.where(racing, waves(there, ranks), -1).reshape(-1)
    chosen = np.full(e * r, -1, dtype=np.int64)
    p = np.zeros((e * r, N_ACTIONS))
    for w in range(int(turn.max(initial=-1)) + 1):
        now = turn == w
        rows = np.concatenate([base[now], turn_rows(there, ranks, chosen.reshape(e, r), first, off)[now]], axis=1)
        p[now] = probs(rows)
        chosen[now] = pick(p[now])
    return chosen.reshape(e, r), p


@dataclass(frozen=True)
class Turn:
    """One step's plan of a race env's crowd: the state it was planned at (``env_state``, its level's table), each
    robot's action and probabilities."""

    key: tuple
    table: Any
    actions: np.ndarray
    probs: np.ndarray


def env_turn(env: Any, form: WindowForm, decode: Callable[[np.ndarray], np.ndarray],
             probs: Callable[[np.ndarray], np.ndarray], pick: Callable[[np.ndarray], np.ndarray]) -> Turn:
    """The actions the racing robots of a ``race_v0`` env choose at this step, in turns (``decide_in_turns``), each
    robot's row from the env's observations (``decode``: an observation to its integers) and its last action (the
    one planned at the step before, none at an episode's start): planned at the step's first call, the same plan
    for every other call of the step."""
    race = getattr(env, "race", env)
    key = env_state(race)
    plan = _TURNS.get(race)
    if plan is not None and plan.key == key and plan.table is race.table:
        return plan
    r = race.n_robots
    last = plan.actions if plan is not None and plan.key[0] == key[0] - 1 else np.full(r, NO_ACTION)
    intents, there, ranks, racing = env_crowd(race, form)
    live = np.flatnonzero(racing[0])
    seen = race.observations()
    obs = np.stack([decode(seen[race.possible_agents[i]]) for i in live])
    rows = form.rows_of_observations(obs, np.where(last[live] < 0, NO_ACTION, last[live]), None, intents[live])
    base = np.full((r, rows.shape[1]), form.n_in, dtype=np.int64)
    base[live] = rows
    actions, p = decide_in_turns(base, there, ranks, racing, probs, pick, form.turns_first, form.n_in)
    plan = _TURNS[race] = Turn(key, race.table, actions[0], p)
    return plan
