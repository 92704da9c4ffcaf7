"""The model ``p(s', r | s, a)`` of one robot, read from the same tables the simulator steps with.

``outcomes`` lists what ``engine.move`` can do from one cell and action, in plain Python (the
reference); ``sparse_arrays`` gives all of them at once as ``next[s, a, k]`` and ``prob[s, a, k]``
(at most a few next cells per state and action, built with a few numpy calls; the planning
algorithms work on these); ``transition_arrays`` expands them into dense ``P[s, a, s']`` and
``R[s, a]``; ``frozenlake_P`` gives the dict-of-lists form of Gymnasium's toy_text envs. Exits are
terminal (absorbing, reward 0 from then on); blocked cells are unreachable and kept as absorbing
placeholders.
"""

from __future__ import annotations

import numpy as np

from .actions import N_ACTIONS
from .checks import check_dense_states
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


def sparse_arrays(t: Table) -> tuple[np.ndarray, np.ndarray]:
    """``next[s, a, k]`` and ``prob[s, a, k]``: the distinct next cells of every state and action.

    ``K`` is the largest number of distinct next cells of any (s, a) on this level (1 on a level
    without puddles or glass); unused slots hold ``s`` with probability 0. Exits and blocked
    cells absorb: ``next[s, a, 0] == s`` with probability 1. Same numbers as ``outcomes``.
    """
    n = t.n_cells
    f = t.flat
    cells = np.repeat(np.arange(n, dtype=np.int64), N_ACTIONS)
    pm = f.move_prob  # 1.0 for STAY
    n_skid = f.n_skid
    p_pass = np.where(f.glass, t.rules.glass_pass_prob, 1.0)
    k_skid = f.skid.shape[1]
    # slots: the skid cells, the target, the cell itself (failed glass pass, or a skid with nowhere to go)
    nxt = np.concatenate([f.skid, f.target[:, None], cells[:, None]], axis=1)
    prob = np.zeros(nxt.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        per_skid = np.where(n_skid > 0, (1.0 - pm) / n_skid, 0.0)
    prob[:, :k_skid] = np.where(np.arange(k_skid) < n_skid[:, None], per_skid[:, None], 0.0)
    prob[:, k_skid] = pm * p_pass
    prob[:, k_skid + 1] = pm * (1.0 - p_pass) + np.where(n_skid == 0, 1.0 - pm, 0.0)
    absorbing = np.repeat(t.is_exit | t.blocked, N_ACTIONS)
    prob[absorbing] = 0.0
    prob[absorbing, k_skid] = 1.0
    nxt[absorbing, k_skid] = cells[absorbing]
    nxt[prob == 0.0] = cells[:, None].repeat(nxt.shape[1], axis=1)[prob == 0.0]
    # merge slots leading to the same cell into the first of them, then move the used slots first
    same = nxt[:, :, None] == nxt[:, None, :]  # [row, i, j]
    first = ~np.triu(same, k=1).transpose(0, 2, 1).any(axis=2)  # no equal slot before this one
    merged = np.einsum("rij,rj->ri", same, prob) * first
    used = merged > 0.0
    order = np.argsort(~used, axis=1, kind="stable")
    nxt, merged, used = (np.take_along_axis(x, order, axis=1) for x in (nxt, merged, used))
    k = max(1, int(used.sum(axis=1).max()))
    nxt = np.where(used, nxt, cells[:, None])[:, :k]
    merged = merged[:, :k]
    return nxt.reshape(n, N_ACTIONS, k), merged.reshape(n, N_ACTIONS, k)


def transition_arrays(t: Table) -> tuple[np.ndarray, np.ndarray]:
    """``P[s, a, s']`` and expected ``R[s, a]``; exits and blocked cells absorb with reward 0."""
    n = t.n_cells
    check_dense_states(n, t.width, t.height, what="transition_arrays")  # before the S * 5 * S array
    nxt, prob = sparse_arrays(t)
    P = np.zeros((n, N_ACTIONS, n))
    s = np.broadcast_to(np.arange(n)[:, None, None], nxt.shape)
    a = np.broadcast_to(np.arange(N_ACTIONS)[None, :, None], nxt.shape)
    np.add.at(P, (s, a, nxt), prob)
    R = (prob * t.reward[nxt]).sum(axis=2)
    R[t.is_exit | t.blocked] = 0.0
    return P, R


def frozenlake_P(t: Table) -> dict[int, dict[int, list[Transition]]]:
    """``P[s][a] == [(probability, next state, reward, terminated), ...]`` as in FrozenLake."""
    nxt, prob = sparse_arrays(t)
    nxt_l, prob_l = nxt.tolist(), prob.tolist()
    reward, is_exit = t.reward.tolist(), t.is_exit.tolist()
    absorbing = (t.is_exit | t.blocked).tolist()
    P: dict[int, dict[int, list[Transition]]] = {}
    for c in range(t.n_cells):
        if absorbing[c]:
            P[c] = {a: [(1.0, c, 0.0, is_exit[c])] for a in range(N_ACTIONS)}
            continue
        P[c] = {
            a: [(p, s, reward[s], is_exit[s]) for s, p in sorted(zip(nxt_l[c][a], prob_l[c][a])) if p > 0.0]
            for a in range(N_ACTIONS)
        }
    return P
