"""Dynamic programming on a ``Model``: policy evaluation, policy iteration, value iteration.

All three are synchronous (Jacobi) sweeps over the sparse arrays, a few numpy calls per sweep.
With ``gamma == 1`` (the default: episodes end at an exit) values are finite only where an exit
can be reached: cells from which no policy reaches one get NaN values and no action, and an
action that may lead into such a cell gets ``q = -inf`` (never chosen).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..core.actions import N_ACTIONS
from .checks import check_dp_args, check_policy, check_proper
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
    gamma, theta, max_iterations, tie_tol = check_dp_args(gamma, theta, max_iterations, tie_tol)
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
    gamma, theta, max_iterations, tie_tol = check_dp_args(gamma, theta, max_iterations, tie_tol)
    pi = check_policy(m, policy)
    sweep = _Sweep(m, gamma)
    if gamma == 1.0:
        check_proper(m, pi, sweep.live)
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
    gamma, theta, max_iterations, tie_tol = check_dp_args(gamma, theta, max_iterations, tie_tol)
    current = (m.proper_policy if policy is None else check_policy(m, policy).argmax(axis=1)).astype(np.int64)
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
