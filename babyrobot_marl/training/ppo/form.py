"""What a level family's policy reads (``WindowForm``): the net's input from a robot's local window.

A policy that plays mazes it has never seen reads what the env's ``observe="local"`` view shows it,
not its ``[x, y]``: a coordinate means a different place in every maze (and a 12x12 maze's
coordinates do not exist on an 8x8 one), so it only helps memorise the training mazes. What it
reads: each window cell's terrain and its four edges (walls), the goal hint's 5 bits when the env
gives them (``hint=True``), and one bit per cell within ``near_radius`` steps saying whether a racing
robot stands there (the robots it could bump into), and with ``memory`` the robot's own last action
(one unit of 5; none at an episode's start), and with ``trail`` the order in which it stood on the
cells next to it (``trail.py``), and a crowd that imitates a planner what the robots near it intend
(``intents.py``). Each feature is multi-hot (one unit per non-zero value), so a row of the net's
input is a short list of indices, as for the single-level trainer's one-hot.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...core.actions import N_ACTIONS
from ...core.observe import LOCAL_FEATURES, TERRAIN
from .goal_inputs import HINT_VALUES, closed_edges
from .intents import INTENT_UNITS
from .trail import KINDS, TRAIL_UNITS, trail_kinds

_NVEC = (len(TERRAIN), 3, 3, 3, 3)  # terrain, then the edges north, east, south, west (LOCAL_FEATURES without robot)
_COLUMNS = [i for i, f in enumerate(LOCAL_FEATURES) if f != "robot"]
_ROBOT = LOCAL_FEATURES.index("robot")
_OFFSETS = np.cumsum((0,) + tuple(v - 1 for v in _NVEC))[:-1]  # each feature's first unit in a window cell
_UNITS = sum(v - 1 for v in _NVEC)  # units per window cell: one per non-zero value
N_HINT = 5
NO_ACTION = N_ACTIONS  # a robot's last action at its episode's start: none


@dataclass(frozen=True)
class WindowForm:
    """The net's input read from a local window of ``radius`` (the env's ``view_radius``): every window
    cell's terrain and edges, the hint bits if ``hint``, then one bit per ``near`` offset (a racing
    robot there), then the last action's unit if ``memory``, then the trail's units if ``trail``, then what the
    robots on the near cells intend if ``intents`` (``intents.py``; with ``ranks``, who goes first), then with
    ``turns`` what the ones that go first chose this step (``turns.py``: added by the caller, who knows). ``n_in``
    units; a row is ``K`` indices, ``n_in`` for "off" (the net's padding row)."""

    radius: int
    near: tuple[tuple[int, int], ...]
    hint: bool
    memory: bool = False
    goals: str = "exit"  # "own": the target channel's unit and the hint toward its own target (goal_inputs)
    trail: bool = False
    intents: bool = False  # own goals: what the robots on the near cells intend (intents.py)
    ranks: bool = False  # with intents: whether each goes before this robot (PIBT's priority, intents.Ranks)
    turns: bool = False  # with ranks: the robots decide in turns, each reading what the ones before it chose (turns.py)

    @property
    def own(self) -> bool:
        return self.goals == "own"

    @property
    def side(self) -> int:
        return 2 * self.radius + 1

    @property
    def n_window(self) -> int:
        return self.side * self.side

    @property
    def n_static(self) -> int:
        """Units of the level's part: the window's terrain and edges, the hint (toward the exits)."""
        return self.n_window * _UNITS + (N_HINT if self.hint and not self.own else 0)

    @property
    def n_goal(self) -> int:
        """Units of the own target's part: the target channel's cell, the hint toward it."""
        return self.n_window + (N_HINT if self.hint else 0) if self.own else 0

    @property
    def goal_values(self) -> int:
        """Distinct values of the own target's part of a key (1: none)."""
        return self.n_window * (HINT_VALUES if self.hint else 1) if self.own else 1

    @property
    def n_in(self) -> int:
        return self.turns_first + (len(self.near) * N_ACTIONS if self.turns else 0)

    @property
    def turns_first(self) -> int:
        """The first unit of the actions chosen this step by the near robots that go first (``turns.py``)."""
        return self.intents_first + (len(self.near) * self.intent_units if self.intents else 0)

    @property
    def intent_units(self) -> int:
        """Units per near cell of the neighbours' intents: the hint's four moves, "on its target", "goes first"."""
        return INTENT_UNITS + self.ranks

    @property
    def intents_first(self) -> int:
        """The first unit of the neighbours' intents (after the trail's)."""
        return self._n_memory + (TRAIL_UNITS if self.trail else 0)

    @property
    def _n_memory(self) -> int:
        """Units before the trail's."""
        return self.n_static + self.n_goal + len(self.near) + (N_ACTIONS if self.memory else 0)

    def trail_rows(self, values: np.ndarray) -> np.ndarray:
        """``(N, 5)`` indices: each move's unit of what the trail says of its cell (``trail.py``), "off" for no
        move, then the unit of the steps stood still ("off" for none)."""
        kind, still = trail_kinds(values)
        at = self._n_memory + np.arange(kind.shape[1]) * (KINDS - 1) + kind - 1
        last = self._n_memory + kind.shape[1] * (KINDS - 1) + still - 1
        return np.concatenate([np.where(kind > 0, at, self.n_in), np.where(still > 0, last, self.n_in)[:, None]], axis=1)

    def memory_rows(self, last: np.ndarray) -> np.ndarray:
        """``(N, 1)`` indices: the unit of each robot's last action (``NO_ACTION``: none, at an episode's start)."""
        last = np.asarray(last, dtype=np.int64).reshape(-1, 1)
        return np.where(last < N_ACTIONS, self.n_static + self.n_goal + len(self.near) + last, self.n_in)

    def goal_rows(self, values: np.ndarray) -> np.ndarray:
        """``(N, 1 + 5?)`` indices from the own target's part of keys (``target unit * 32 + hint bits``)."""
        values = np.asarray(values, dtype=np.int64).reshape(-1)
        at = self.n_static
        unit, bits = np.divmod(values, HINT_VALUES) if self.hint else (values, None)
        parts = [(at + unit)[:, None]]
        if self.hint:
            on = (bits[:, None] >> np.arange(N_HINT)) & 1
            parts.append(np.where(on > 0, at + self.n_window + np.arange(N_HINT), self.n_in))
        return np.concatenate(parts, axis=1)

    @cached_property
    def window_at(self) -> np.ndarray:
        """The window cell of each ``near`` offset (rows north to south, west to east)."""
        return np.array([(dy + self.radius) * self.side + dx + self.radius for dx, dy in self.near], dtype=np.int64)

    def static_rows(self, feats: np.ndarray, hint: np.ndarray | None) -> np.ndarray:
        """``(N, n_window * 5 + 5?)`` indices from window features ``(N, n_window, 6)`` and hint bits ``(N, 5)``."""
        f = np.asarray(feats, dtype=np.int64)
        if self.own:  # walls and blocked cells read alike (goal_inputs.closed_edges)
            f = closed_edges(f, self.radius)
        f = f[:, :, _COLUMNS]  # (N, W, 5)
        unit = np.arange(self.n_window)[:, None] * _UNITS + _OFFSETS + f - 1
        rows = np.where(f > 0, unit, self.n_in).reshape(f.shape[0], -1)
        if self.hint and not self.own:
            h = np.asarray(hint, dtype=np.int64)
            rows = np.concatenate([rows, np.where(h > 0, self.n_window * _UNITS + np.arange(N_HINT), self.n_in)], axis=1)
        return rows

    def robot_rows(self, bits: np.ndarray) -> np.ndarray:
        """``(N, m)`` indices from the near bits ``(N, m)`` (0/1)."""
        return np.where(np.asarray(bits) > 0, self.n_static + self.n_goal + np.arange(len(self.near)), self.n_in)

    def obs_size(self) -> int:
        """Numbers of one env observation: ``[x, y]``, the window, the target channel (own goals), the hint bits."""
        return 2 + len(LOCAL_FEATURES) * self.n_window + (self.n_window if self.own else 0) + (N_HINT if self.hint else 0)

    def rows_of_observations(self, obs: np.ndarray, last: np.ndarray | None = None,
                             trail: np.ndarray | None = None, intents: np.ndarray | None = None) -> np.ndarray:
        """The net's rows from ``race_v0``'s ``observe="local"`` rows ``(N, obs_size)`` (MultiDiscrete
        integers) and, with ``memory``, each robot's ``last`` action, with ``trail`` its trail number, with
        ``intents`` its neighbours' units (``intents.env_intents``): the same rows the trainer builds from the
        batch engine's cells."""
        if self.intents and intents is None:
            raise ValueError("intents: this policy reads what the robots near each robot intend; "
                             "bind it to your env with policy.for_env(env)")
        o = np.asarray(obs, dtype=np.int64).reshape(-1, self.obs_size())
        feats = o[:, 2 : 2 + len(LOCAL_FEATURES) * self.n_window].reshape(-1, self.n_window, len(LOCAL_FEATURES))
        hint = o[:, -N_HINT:] if self.hint else None
        bits = feats[:, self.window_at, _ROBOT]
        parts = [self.static_rows(feats, hint)]
        if self.own:  # the target channel's cell, then the hint's bits as one number
            at = 2 + len(LOCAL_FEATURES) * self.n_window
            value = o[:, at : at + self.n_window].argmax(axis=1)
            if self.hint:
                value = value * HINT_VALUES + hint @ (1 << np.arange(N_HINT))
            parts.append(self.goal_rows(value))
        parts.append(self.robot_rows(bits))
        if self.memory:
            parts.append(self.memory_rows(np.full(len(o), NO_ACTION) if last is None else last))
        if self.trail:
            parts.append(self.trail_rows(np.zeros(len(o), dtype=np.int64) if trail is None else trail))
        if self.intents:
            parts.append(np.asarray(intents, dtype=np.int64).reshape(len(o), -1))
        return np.concatenate(parts, axis=1)
