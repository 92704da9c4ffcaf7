"""The model ``p(s', r | s, a)`` of one robot, read from the same tables the simulator steps with.

``outcomes`` lists what ``engine.move`` can do from a cell and with what probability;
``transition_arrays`` stacks that into ``P[s, a, s']`` and ``R[s, a]``; ``frozenlake_P`` gives
the dict-of-lists form of Gymnasium's toy_text envs. Exits are terminal (absorbing, reward 0
from then on); blocked cells are unreachable and kept as absorbing placeholders.
"""

from __future__ import annotations

import numpy as np

from .actions import N_ACTIONS
from .table import Table

Transition = tuple[float, int, float, bool]  # (probability, next cell, reward, terminated)


def outcomes(t: Table, c: int, a: int) -> dict[int, float]:
    """Next cell -> probability, for one robot at cell ``c`` taking action ``a``."""
    dist: dict[int, float] = {}

    def add(cell: int, p: float) -> None:
        if p > 0.0:
            dist[int(cell)] = dist.get(int(cell), 0.0) + p

    if a == 0 or t.blocked[c]:
        add(c, 1.0)
        return dist
    p_move = float(t.move_prob[c])
    n = int(t.n_skid[c, a])
    if n:
        for k in range(n):
            add(t.skid[c, a, k], (1.0 - p_move) / n)
    else:
        add(c, 1.0 - p_move)
    dest = int(t.target[c, a])
    p_pass = t.rules.glass_pass_prob if t.glass[c, a] else 1.0
    add(dest, p_move * p_pass)
    add(c, p_move * (1.0 - p_pass))
    return dist


def transition_arrays(t: Table) -> tuple[np.ndarray, np.ndarray]:
    """``P[s, a, s']`` and expected ``R[s, a]``; exits and blocked cells absorb with reward 0."""
    n = t.n_cells
    P = np.zeros((n, N_ACTIONS, n))
    R = np.zeros((n, N_ACTIONS))
    for c in range(n):
        for a in range(N_ACTIONS):
            if t.is_exit[c] or t.blocked[c]:
                P[c, a, c] = 1.0
                continue
            for nxt, p in outcomes(t, c, a).items():
                P[c, a, nxt] += p
                R[c, a] += p * t.reward[nxt]
    return P, R


def frozenlake_P(t: Table) -> dict[int, dict[int, list[Transition]]]:
    """``P[s][a] == [(probability, next state, reward, terminated), ...]`` as in FrozenLake."""
    P: dict[int, dict[int, list[Transition]]] = {}
    for c in range(t.n_cells):
        P[c] = {}
        for a in range(N_ACTIONS):
            if t.is_exit[c] or t.blocked[c]:
                P[c][a] = [(1.0, c, 0.0, bool(t.is_exit[c]))]
                continue
            P[c][a] = [(p, nxt, float(t.reward[nxt]), bool(t.is_exit[nxt])) for nxt, p in sorted(outcomes(t, c, a).items())]
    return P
