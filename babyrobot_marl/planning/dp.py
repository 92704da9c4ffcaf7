"""Dynamic programming on a ``Model``: policy evaluation, policy iteration, value iteration.

Vectorised numpy over the sparse model: one sweep is a gather ``V[next]``, a weighted sum and
a max. ``gamma=1`` (the undiscounted episode) is allowed: every reward is negative until the
exit, so values are finite for every policy that reaches an exit; a policy that never does
has no finite value, and evaluating it stops with a clear error after ``max_iterations``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.actions import N_ACTIONS
from .model import Model

TIE = 1e-9  # actions within this (relative) of the best are all best


@dataclass(frozen=True, eq=False)
class Solution:
    """What a planning algorithm returns: values, action values and a greedy policy."""

    model: Model
    values: np.ndarray  # float64[S]
    q: np.ndarray  # float64[S, 5], by Action
    policy: np.ndarray  # int64[S]: greedy action (STAY on terminal states)
    gamma: float
    iterations: int

    @property
    def value_grid(self) -> np.ndarray:
        """``values`` as ``[H, W]``, NaN on blocked cells (no robot is ever there)."""
        grid = self.values.astype(np.float64).reshape(self.model.shape)
        grid[self.model.table.blocked.reshape(self.model.shape)] = np.nan
        return grid

    @property
    def policy_grid(self) -> np.ndarray:
        """``policy`` as ``[H, W]``, -1 on exits and blocked cells."""
        return np.where(self.model.terminal, -1, self.policy).reshape(self.model.shape)

    @property
    def best_actions(self) -> np.ndarray:
        """``bool[H, W, 5]``: every action whose value ties with the best (False on terminal states)."""
        best = self.q.max(axis=1, keepdims=True)
        ties = self.q >= best - TIE * np.maximum(1.0, np.abs(best))
        ties[self.model.terminal] = False
        return ties.reshape(*self.model.shape, N_ACTIONS)


def q_from_values(m: Model, values: np.ndarray, gamma: float) -> np.ndarray:
    """``q[s, a] = r(s, a) + gamma * sum_s' p(s' | s, a) v(s')`` (0 on terminal states)."""
    q = m.reward + gamma * (m.prob * values[m.next]).sum(axis=2)
    q[m.terminal] = 0.0
    return q


def _check(gamma: float, theta: float, max_iterations: int) -> None:
    if isinstance(gamma, bool) or not isinstance(gamma, (int, float)) or not 0.0 <= gamma <= 1.0:
        raise ValueError(f"gamma: must be a number in [0, 1], got {gamma!r}")
    if isinstance(theta, bool) or not isinstance(theta, (int, float)) or not theta > 0:
        raise ValueError(f"theta: must be a positive number, got {theta!r}")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, int) or max_iterations < 1:
        raise ValueError(f"max_iterations: must be a positive integer, got {max_iterations!r}")


def _greedy(q: np.ndarray) -> np.ndarray:
    return np.argmax(q, axis=1).astype(np.int64)  # ties: the lowest action number


def value_iteration(m: Model, gamma: float = 1.0, theta: float = 1e-9, max_iterations: int = 100_000) -> Solution:
    """Optimal values: sweep ``v <- max_a q(s, a)`` until no value moves by ``theta`` or more."""
    _check(gamma, theta, max_iterations)
    v = np.zeros(m.n_states)
    for it in range(1, max_iterations + 1):
        q = q_from_values(m, v, gamma)
        new = q.max(axis=1)
        delta = np.abs(new - v).max()
        v = new
        if delta < theta:
            return Solution(m, v, q_from_values(m, v, gamma), _greedy(q), float(gamma), it)
    raise RuntimeError(f"value_iteration: no convergence in {max_iterations} sweeps (theta={theta}); raise max_iterations")


def policy_evaluation(
    m: Model, policy: np.ndarray, gamma: float = 1.0, theta: float = 1e-9, max_iterations: int = 100_000
) -> Solution:
    """Values of ``policy``: one action per state (``int[S]`` or ``int[H, W]``) or action
    probabilities (``float[S, 5]``), by iterative sweeps. The returned ``policy`` is greedy
    with respect to these values (one step of policy improvement)."""
    _check(gamma, theta, max_iterations)
    pi = _policy_matrix(m, policy)
    v = np.zeros(m.n_states)
    for it in range(1, max_iterations + 1):
        q = q_from_values(m, v, gamma)
        new = (pi * q).sum(axis=1)
        delta = np.abs(new - v).max()
        v = new
        if delta < theta:
            q = q_from_values(m, v, gamma)
            return Solution(m, v, q, _greedy(q), float(gamma), it)
    raise RuntimeError(
        f"policy_evaluation: no convergence in {max_iterations} sweeps; with gamma=1 a policy that never "
        "reaches an exit has no finite value: use gamma < 1"
    )


def policy_iteration(
    m: Model, gamma: float = 1.0, theta: float = 1e-9, policy: np.ndarray | None = None, max_rounds: int = 1000
) -> Solution:
    """Evaluate, improve greedily, repeat until the policy is stable. The default first policy
    is the shortest-path robot's (it reaches an exit, so it has finite values even at gamma=1)."""
    from ..policies.shortest import shortest_path_actions

    current = shortest_path_actions(m.table) if policy is None else _policy_actions(m, policy)
    for _ in range(max_rounds):
        sol = policy_evaluation(m, current, gamma, theta)
        # keep the current action where it is still among the best (no flip-flopping between ties)
        best = sol.q.max(axis=1)
        keep = sol.q[np.arange(m.n_states), current] >= best - TIE * np.maximum(1.0, np.abs(best))
        improved = np.where(keep, current, sol.policy)
        if np.array_equal(improved, current):
            return Solution(m, sol.values, sol.q, current, sol.gamma, sol.iterations)
        current = improved
    raise RuntimeError(f"policy_iteration: the policy still changed after {max_rounds} rounds")


def _policy_actions(m: Model, policy: np.ndarray) -> np.ndarray:
    arr = np.asarray(policy)
    if arr.shape == m.shape:
        arr = arr.reshape(-1)
    if arr.shape != (m.n_states,) or arr.dtype.kind not in "iu":
        raise ValueError(f"policy: expected one integer action per state, shape ({m.n_states},) or {m.shape}, got {arr.shape}")
    arr = np.where(m.terminal, 0, arr)  # exits and blocked cells: any action (-1 from policy_grid) counts as STAY
    if ((arr < 0) | (arr >= N_ACTIONS)).any():
        raise ValueError(f"policy: actions must be in 0..{N_ACTIONS - 1}")
    return arr.astype(np.int64)


def _policy_matrix(m: Model, policy: np.ndarray) -> np.ndarray:
    arr = np.asarray(policy)
    if arr.dtype.kind == "f":
        if arr.shape != (m.n_states, N_ACTIONS):
            raise ValueError(f"policy: action probabilities need shape ({m.n_states}, {N_ACTIONS}), got {arr.shape}")
        if (arr < 0).any() or not np.allclose(arr.sum(axis=1), 1.0):
            raise ValueError("policy: action probabilities must be >= 0 and sum to 1 in every state")
        return arr
    actions = _policy_actions(m, arr)
    pi = np.zeros((m.n_states, N_ACTIONS))
    pi[np.arange(m.n_states), actions] = 1.0
    return pi
