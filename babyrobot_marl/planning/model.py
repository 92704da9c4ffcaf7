"""The MDP of one robot, ``p(s', r | s, a)``, read from the tables the simulator steps with.

A ``Model`` is sparse: each state and action lead to at most ``K`` next states (the intended
cell, the cell itself, the skid cells), stored as ``next[s, a, k]`` and ``prob[s, a, k]``
(padding: probability 0). States are cells, ``s = y * width + x``. Exits are terminal (value
0: the episode ends on entering one); blocked cells can never be entered and are kept as
terminal placeholders. ``dense()`` gives the classic ``P[s, a, s']`` and ``R[s, a]``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.level import Level
from ..core.model import outcomes
from ..core.rules import Rules
from ..core.table import Table, compile_level


@dataclass(frozen=True, eq=False)
class Model:
    """``next[s, a, k]``, ``prob[s, a, k]``, expected reward ``reward[s, a]``, ``terminal[s]``."""

    table: Table
    next: np.ndarray  # int64[S, A, K]
    prob: np.ndarray  # float64[S, A, K]
    reward: np.ndarray  # float64[S, A]: the expected reward of the step (the reward of the cell entered)
    terminal: np.ndarray  # bool[S]: exits and blocked cells

    @property
    def n_states(self) -> int:
        return self.table.n_cells

    @property
    def shape(self) -> tuple[int, int]:
        """``(height, width)`` of the level: grids of values are this shape."""
        return self.table.height, self.table.width

    def dense(self) -> tuple[np.ndarray, np.ndarray]:
        """``P[s, a, s']`` and ``R[s, a]`` as dense arrays (``S * S * 5`` floats: small levels only)."""
        s, a = np.indices(self.next.shape[:2])
        P = np.zeros((self.n_states, N_ACTIONS, self.n_states))
        for k in range(self.next.shape[2]):
            np.add.at(P, (s, a, self.next[:, :, k]), self.prob[:, :, k])
        return P, self.reward.copy()


def model(source: Any, rules: Rules | Mapping[str, Any] | None = None) -> Model:
    """The model of ``source``: a ``Level``, a built-in level name, a level text, or an env
    (``BabyRobotEnv``, also wrapped: its level and rules; ``rules`` must then be None)."""
    from ..envs.common import resolve_level, resolve_rules

    env = getattr(source, "unwrapped", source)
    if hasattr(env, "table") and isinstance(env.table, Table):
        if rules is not None:
            raise ValueError("rules: an env brings its own rules; pass rules=None (or pass its level instead)")
        return from_table(env.table)
    if not isinstance(source, (str, Level)):
        raise ValueError(f"source: expected a Level, a level name or text, or a BabyRobot env, got {type(source).__name__}")
    level = resolve_level(source)
    return from_table(compile_level(level, resolve_rules(rules, {}, known="model(source, rules)")))


def from_table(t: Table) -> Model:
    """Build the sparse model from a compiled table (``core.model.outcomes`` per state and action)."""
    n = t.n_cells
    terminal = t.is_exit | t.blocked
    rows: list[list[dict[int, float]]] = [
        [{c: 1.0} if terminal[c] else outcomes(t, c, a) for a in range(N_ACTIONS)] for c in range(n)
    ]
    k_max = max(len(d) for row in rows for d in row)
    nxt = np.tile(np.arange(n)[:, None, None], (1, N_ACTIONS, k_max))
    prob = np.zeros((n, N_ACTIONS, k_max))
    for c, row in enumerate(rows):
        for a, dist in enumerate(row):
            for k, (s2, p) in enumerate(sorted(dist.items())):
                nxt[c, a, k], prob[c, a, k] = s2, p
    reward = (prob * t.reward[nxt]).sum(axis=2)
    reward[terminal] = 0.0
    for arr in (nxt, prob, reward, terminal):
        arr.setflags(write=False)
    return Model(t, nxt, prob, reward, terminal.copy())
