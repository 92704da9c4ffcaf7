"""Dynamic programming on a ``Model``: policy evaluation, policy iteration, value iteration.

All three are synchronous (Jacobi) sweeps over the sparse arrays, a few numpy calls per sweep.
With ``gamma == 1`` (the default: episodes end at an exit) values are finite only where an exit
can be reached: cells from which no policy reaches one get NaN values and no action, and an
action that may lead into such a cell gets ``q = -inf`` (never chosen).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.checks import check_int
from .mdp import Model

DEFAULT_MAX_SWEEPS = 100_000


@dataclass(frozen=True, eq=False)
class Solution:
    """Values, action values and the greedy policy of a ``Model`` (states ``s = y * width + x``).

    ``values`` ``float64[S]``, ``q`` ``float64[S, 5]`` (indexed by ``Action``), ``policy``
    ``int64[S]`` (the greedy action; the lowest-numbered of tied best actions; STAY where there is
    nothing to choose). ``value_grid``, ``policy_grid``, ``best_actions`` are the same on the grid,
    ready for ``env.unwrapped.set_overlay(values=..., arrows=...)``. ``iterations`` counts sweeps
    (value iteration, policy evaluation) or improvement rounds (policy iteration).
    """

    values: np.ndarray
    q: np.ndarray
    policy: np.ndarray
    width: int
    height: int
    is_exit: np.ndarray
    blocked: np.ndarray
    gamma: float
    iterations: int
    tie_tol: float

    @cached_property
    def active(self) -> np.ndarray:
        """``bool[S]``: cells with a choice to make (not exits, not blocked, a finite value)."""
        return ~self.is_exit & ~self.blocked & np.isfinite(self.values)

    @cached_property
    def value_grid(self) -> np.ndarray:
        """``float64[H, W]``, NaN on blocked cells (and on cells with no finite value)."""
        v = np.where(self.blocked, np.nan, self.values)
        return v.reshape(self.height, self.width)

    @cached_property
    def policy_grid(self) -> np.ndarray:
        """``int64[H, W]``: the greedy action, -1 on exits, blocked cells and cells with no value."""
        return np.where(self.active, self.policy, -1).reshape(self.height, self.width)

    @cached_property
    def best_actions(self) -> np.ndarray:
        """``bool[H, W, 5]``: every action whose ``q`` is within ``tie_tol`` of the best."""
        q = np.where(np.isnan(self.q), -np.inf, self.q)
        best = (q >= q.max(axis=1, keepdims=True) - self.tie_tol) & self.active[:, None]
        return best.reshape(self.height, self.width, N_ACTIONS)


def q_values(m: Model, values: np.ndarray, gamma: float = 1.0) -> np.ndarray:
    """``q[s, a] = sum_k prob * (reward + gamma * values[next])``; 0 on terminal cells."""
    v = np.where(m.terminal, 0.0, values)
    return np.einsum("sak,sak->sa", m.prob, m.reward + gamma * v[m.next])


def value_iteration(
    m: Model, gamma: float = 1.0, theta: float = 1e-9, max_iterations: int = DEFAULT_MAX_SWEEPS, tie_tol: float = 1e-6
) -> Solution:
    """Optimal values by synchronous sweeps ``V <- max_a q(V)`` until no value moves by ``theta``.

    ``gamma`` in (0, 1]; ``theta`` > 0; ``max_iterations`` sweeps at most (a ``RuntimeError``
    beyond: e.g. positive custom rewards with ``gamma == 1``). ``tie_tol``: actions whose ``q``
    lies within it of the best count as best in ``Solution.best_actions``.
    """
    gamma, theta, max_iterations, tie_tol = _check(gamma, theta, max_iterations, tie_tol)
    sweep = _Sweep(m, gamma)
    u = np.zeros(sweep.n_live + 1)
    v = u[:-1]  # a view: the last entry stays 0
    for it in range(1, max_iterations + 1):
        new = sweep.q(u).max(axis=0)
        delta = np.max(np.abs(new - v), initial=0.0)
        v[:] = new
        if delta < theta:
            return sweep.solution(u, it, tie_tol)
    raise RuntimeError(f"value_iteration: no convergence in max_iterations={max_iterations} sweeps ({theta=}, {gamma=})")


def policy_evaluation(
    m: Model,
    policy: np.ndarray,
    gamma: float = 1.0,
    theta: float = 1e-9,
    max_iterations: int = DEFAULT_MAX_SWEEPS,
    tie_tol: float = 1e-6,
    initial: np.ndarray | None = None,
) -> Solution:
    """The values ``v_pi`` of ``policy`` by iterative (synchronous) policy evaluation.

    ``policy``: ``int[S]`` one action per state, or ``float[S, 5]`` action probabilities (rows
    summing to 1). Returns a ``Solution`` whose ``values``/``q`` are ``v_pi``/``q_pi`` and whose
    ``policy`` is greedy with respect to ``q_pi`` (one step of policy improvement). With
    ``gamma == 1`` the policy must reach an exit from every cell that can reach one
    (``ValueError`` otherwise: its values would be infinite).
    """
    gamma, theta, max_iterations, tie_tol = _check(gamma, theta, max_iterations, tie_tol)
    pi = _policy_matrix(m, policy)
    sweep = _Sweep(m, gamma)
    if gamma == 1.0:
        _check_proper(m, pi, sweep)
    u = sweep.compact(np.zeros(m.n_states) if initial is None else np.asarray(initial, dtype=np.float64))
    v = u[:-1]
    p_live = np.ascontiguousarray(pi[sweep.live].T)  # [a, s]
    used = p_live > 0  # (an unused action may have q = -inf: 0 * -inf would be NaN)
    for it in range(1, max_iterations + 1):
        new = (p_live * np.where(used, sweep.q(u), 0.0)).sum(axis=0)
        delta = np.max(np.abs(new - v), initial=0.0)
        v[:] = new
        if delta < theta:
            return sweep.solution(u, it, tie_tol)
    raise RuntimeError(f"policy_evaluation: no convergence in max_iterations={max_iterations} sweeps ({theta=}, {gamma=})")


def policy_iteration(
    m: Model,
    gamma: float = 1.0,
    theta: float = 1e-9,
    policy: np.ndarray | None = None,
    max_iterations: int = 1000,
    tie_tol: float = 1e-6,
) -> Solution:
    """Policy iteration: evaluate, improve greedily, until the policy is stable.

    Starts from ``policy`` (``int[S]``) or, by default, ``Model.proper_policy`` (one that
    reaches an exit, as ``gamma == 1`` needs). An action changes only when another is better by
    more than ``tie_tol``, so ties cannot make it cycle. ``max_iterations`` improvement rounds.
    """
    gamma, theta, max_iterations, tie_tol = _check(gamma, theta, max_iterations, tie_tol)
    current = (m.proper_policy if policy is None else _policy_matrix(m, policy).argmax(axis=1)).astype(np.int64)
    sol = None
    for it in range(1, max_iterations + 1):
        sol = policy_evaluation(m, current, gamma, theta, tie_tol=tie_tol, initial=None if sol is None else sol.values)
        q = np.where(np.isnan(sol.q), -np.inf, sol.q)
        keep = q[np.arange(m.n_states), current] >= q.max(axis=1) - tie_tol
        improved = np.where(keep | ~sol.active, current, sol.policy)
        if np.array_equal(improved, current):
            return Solution(sol.values, sol.q, current, m.width, m.height, m.is_exit, m.blocked, gamma, it, tie_tol)
        current = improved
    raise RuntimeError(f"policy_iteration: the policy still changed after max_iterations={max_iterations} rounds")


class _Sweep:
    """The rows of the model that sweeps update: non-terminal cells with a finite value.

    Sweeps work on ``u``, the values of the live cells followed by one 0 (for every terminal
    cell), in an action-major layout ``[a, s, k]`` so the max over actions reduces contiguous rows.
    """

    def __init__(self, m: Model, gamma: float):
        self.m, self.gamma = m, gamma
        dead = (m.exit_steps < 0) & ~m.terminal if gamma == 1.0 else np.zeros(m.n_states, dtype=bool)
        self.dead = dead
        self.live = ~m.terminal & ~dead
        self.n_live = int(self.live.sum())
        compact = np.full(m.n_states, self.n_live, dtype=np.int64)  # terminal and dead cells -> the 0 slot
        compact[self.live] = np.arange(self.n_live)
        nxt, prob, reward = m.next[self.live], m.prob[self.live], m.reward[self.live]
        risky = ((prob > 0) & dead[nxt]).any(axis=2)  # may fall where no exit is reachable
        self.next = np.ascontiguousarray(compact[nxt].transpose(1, 0, 2))
        self.gprob = np.ascontiguousarray((gamma * prob).transpose(1, 0, 2))
        self.expected = np.ascontiguousarray((prob * reward).sum(axis=2).T)  # R[a, s]
        self.expected[risky.T] = -np.inf
        self.single = self.next.shape[2] == 1  # no puddles or glass: one next cell, probability 1
        if self.single:
            self.next = self.next[:, :, 0]

    def compact(self, v: np.ndarray) -> np.ndarray:
        u = np.zeros(self.n_live + 1)
        u[:-1] = v[self.live]
        return u

    def q(self, u: np.ndarray) -> np.ndarray:
        """``q[a, s]`` of the live cells from their values ``u`` (compact form)."""
        if self.single:
            return self.expected + self.gamma * u.take(self.next)
        return self.expected + (self.gprob * u.take(self.next)).sum(axis=2)

    def solution(self, u: np.ndarray, iterations: int, tie_tol: float) -> Solution:
        m = self.m
        values = np.zeros(m.n_states)
        values[self.live] = u[:-1]
        values[self.dead] = np.nan
        q = np.zeros((m.n_states, N_ACTIONS))
        q[self.live] = self.q(u).T
        q[self.dead] = np.nan
        best = np.where(self.live[:, None], q, -np.inf)
        policy = np.argmax(best >= best.max(axis=1, keepdims=True) - tie_tol, axis=1).astype(np.int64)
        policy[~self.live] = 0
        return Solution(values, q, policy, m.width, m.height, m.is_exit, m.blocked, self.gamma, iterations, tie_tol)


def _is_real(x: object) -> bool:
    return not isinstance(x, bool) and isinstance(x, (int, float, np.floating, np.integer))


def _check(gamma: object, theta: object, max_iterations: object, tie_tol: object) -> tuple[float, float, int, float]:
    if not _is_real(gamma) or not 0.0 < gamma <= 1.0:
        raise ValueError(f"gamma: must be a number in (0, 1], got {gamma!r}")
    if not _is_real(theta) or not 0.0 < theta < math.inf:
        raise ValueError(f"theta: must be a number > 0, got {theta!r}")
    if not _is_real(tie_tol) or not 0.0 <= tie_tol < math.inf:
        raise ValueError(f"tie_tol: must be a number >= 0, got {tie_tol!r}")
    n = check_int(max_iterations, "max_iterations", lo=1)
    return float(gamma), float(theta), n, float(tie_tol)


def _policy_matrix(m: Model, policy: object) -> np.ndarray:
    """``float[S, 5]`` action probabilities from ``int[S]`` actions or ``float[S, 5]`` probabilities."""
    arr = np.asarray(policy)
    s = m.n_states
    if arr.shape == (s,) and arr.dtype.kind in "iu":
        if arr.size and (arr.min() < 0 or arr.max() >= N_ACTIONS):
            raise ValueError(f"policy: actions must lie in 0..{N_ACTIONS - 1}, got values from {arr.min()} to {arr.max()}")
        return np.eye(N_ACTIONS)[arr]
    if arr.shape == (s, N_ACTIONS) and arr.dtype.kind == "f":
        live = ~m.terminal
        if not np.all(np.isfinite(arr)) or np.any(arr < 0) or not np.allclose(arr[live].sum(axis=1), 1.0, atol=1e-9):
            raise ValueError("policy: action probabilities must be finite, >= 0 and sum to 1 in every non-terminal state")
        return arr.astype(np.float64)
    raise ValueError(
        f"policy: expected int[{s}] (one action per state) or float[{s}, {N_ACTIONS}] (action probabilities), "
        f"got {arr.dtype} array of shape {arr.shape}"
    )


def _check_proper(m: Model, pi: np.ndarray, sweep: _Sweep) -> None:
    """With gamma == 1 every live cell must reach an exit with positive probability under ``pi``."""
    n = m.n_states
    into: list[list[int]] = [[] for _ in range(n)]
    step = (m.prob > 0) & (pi[:, :, None] > 0) & sweep.live[:, None, None]
    for s, a, k in zip(*np.nonzero(step)):
        into[int(m.next[s, a, k])].append(int(s))
    reached = m.is_exit.copy()
    todo = deque(np.flatnonzero(reached).tolist())
    while todo:
        c = todo.popleft()
        for p in into[c]:
            if not reached[p]:
                reached[p] = True
                todo.append(p)
    stuck = np.flatnonzero(sweep.live & ~reached)
    if stuck.size:
        cells = ", ".join(str(m.table.cell_xy(int(c))) for c in stuck[:5])
        raise ValueError(
            f"policy: with gamma=1 it must reach an exit from every cell that can reach one; it never does from {cells}"
            f"{' ...' if stuck.size > 5 else ''} (its values would be infinite; use gamma < 1 or another policy)"
        )
