"""``Model``: one robot's MDP as sparse arrays, built from the simulator's compiled tables."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..core.checks import check_dense_states
from ..core.level import Level
from ..core.model import Transition, frozenlake_P, sparse_arrays, transition_arrays
from ..core.rules import Rules, resolve_rules
from ..core.table import Table, compile_level
from ..levels.resolve import resolve_level


@dataclass(frozen=True, eq=False)
class Model:
    """``p(s', r | s, a)`` of one robot; states are cells ``s = y * width + x``, actions ``Action``.

    ``next[s, a, k]``, ``prob[s, a, k]``: the ``K`` possible next cells and their probabilities
    (``K`` is small: 1 without puddles or glass, at most 5). ``reward[s, a, k]``: the reward of
    that transition (the reward of the cell it ends in; 0 out of a terminal). ``terminal[s]``:
    exits and blocked cells, which absorb with reward 0. ``P`` and ``R`` are the dense
    ``P[s, a, s']`` and ``R[s, a]``; ``frozenlake_P`` the dict form of ``env.unwrapped.P``.
    """

    table: Table
    next: np.ndarray
    prob: np.ndarray
    reward: np.ndarray
    terminal: np.ndarray

    @property
    def level(self) -> Level:
        return self.table.level

    @property
    def rules(self) -> Rules:
        return self.table.rules

    @property
    def width(self) -> int:
        return self.table.width

    @property
    def height(self) -> int:
        return self.table.height

    @property
    def n_states(self) -> int:
        return self.table.n_cells

    @property
    def is_exit(self) -> np.ndarray:
        return self.table.is_exit

    @property
    def blocked(self) -> np.ndarray:
        return self.table.blocked

    @cached_property
    def dense(self) -> tuple[np.ndarray, np.ndarray]:
        """``(P[s, a, s'], R[s, a])``: S * S * 5 floats, for small levels and checks.

        At most ``MAX_DENSE_STATES`` states (the size is checked before anything is allocated);
        larger levels use the sparse ``next``/``prob``/``reward`` arrays, which all of planning reads.
        """
        check_dense_states(self.n_states, self.width, self.height)
        return transition_arrays(self.table)

    @property
    def P(self) -> np.ndarray:
        return self.dense[0]

    @property
    def R(self) -> np.ndarray:
        """Expected reward ``R[s, a]``."""
        return (self.prob * self.reward).sum(axis=2)

    @cached_property
    def frozenlake_P(self) -> dict[int, dict[int, list[Transition]]]:
        return frozenlake_P(self.table)

    @cached_property
    def exit_steps(self) -> np.ndarray:
        """Fewest steps from each cell to an exit along transitions of positive probability
        (``-1`` where no policy ever reaches one). Terminal cells: 0 on exits, -1 if blocked."""
        n = self.n_states
        into: list[list[int]] = [[] for _ in range(n)]
        live = ~self.terminal
        for s, _a, k in zip(*np.nonzero((self.prob > 0) & live[:, None, None])):
            into[int(self.next[s, _a, k])].append(int(s))
        steps = np.full(n, -1, dtype=np.int64)
        todo = deque(np.flatnonzero(self.is_exit).tolist())
        steps[todo] = 0
        while todo:
            c = todo.popleft()
            for p in into[c]:
                if steps[p] < 0:
                    steps[p] = steps[c] + 1
                    todo.append(p)
        return steps

    @cached_property
    def proper_policy(self) -> np.ndarray:
        """A policy that reaches an exit with probability 1 from every cell that can reach one:
        in each cell an action with a positive chance of a cell one step closer (STAY elsewhere)."""
        steps = self.exit_steps
        closer = (self.prob > 0) & (steps[self.next] == steps[:, None, None] - 1) & (steps[self.next] >= 0)
        good = closer.any(axis=2)
        policy = np.argmax(good, axis=1).astype(np.int64)
        policy[~good.any(axis=1)] = 0
        return policy


def model(level: Any, rules: Rules | dict | None = None) -> Model:
    """The MDP of one robot on ``level`` under ``rules``.

    ``level``: a ``Level``, a built-in name (or ``maze-WxH[-sSEED]``), a level text, or a
    ``BabyRobotEnv`` (also wrapped, e.g. from ``gymnasium.make``), whose level and rules are used;
    ``rules``: a ``Rules``, a dict of rule values or None (the defaults; not allowed with an env).
    """

    env = getattr(level, "unwrapped", level)
    if hasattr(env, "table") and isinstance(env.table, Table):
        if rules is not None:
            raise ValueError("rules: give no rules with an env; the env's own rules are used")
        table = env.table
    else:
        if not isinstance(level, (str, Level)):
            raise TypeError(f"level: expected a Level, a level name, a level text or a BabyRobotEnv, got {type(level).__name__}")
        table = compile_level(resolve_level(level), resolve_rules(rules, {}))
    nxt, prob = sparse_arrays(table)
    terminal = table.is_exit | table.blocked
    reward = np.where(terminal[:, None, None], 0.0, table.reward[nxt])
    for arr in (nxt, prob, reward, terminal):
        arr.setflags(write=False)
    return Model(table, nxt, prob, reward, terminal)

