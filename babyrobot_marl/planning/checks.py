"""Planning's argument checks: the dynamic programming settings and the policies it evaluates.

The rules for integers and reals are the core's (``core.checks``); the sentences are planning's own.
"""

from __future__ import annotations

from collections import deque
from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.checks import check_int, check_real
from .mdp import Model


def check_dp_args(gamma: object, theta: object, max_iterations: object, tie_tol: object) -> tuple[float, float, int, float]:
    """``gamma`` in (0, 1], ``theta`` > 0, ``tie_tol`` >= 0 (finite numbers) and ``max_iterations`` >= 1."""
    g = check_real(gamma, "gamma", 0.0, 1.0, open_lo=True, message="{name}: must be a number in (0, 1], got {value}")
    t = check_real(theta, "theta", 0.0, open_lo=True, message="{name}: must be a number > 0, got {value}")
    tol = check_real(tie_tol, "tie_tol", 0.0, message="{name}: must be a number >= 0, got {value}")
    n = check_int(max_iterations, "max_iterations", lo=1)
    return g, t, n, tol


def check_policy(m: Model, policy: object) -> np.ndarray:
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


def check_proper(m: Model, pi: np.ndarray, live: np.ndarray) -> None:
    """With gamma == 1 every ``live`` cell (the cells sweeps update) must reach an exit with positive
    probability under ``pi``."""
    n = m.n_states
    into: list[list[int]] = [[] for _ in range(n)]
    step = (m.prob > 0) & (pi[:, :, None] > 0) & live[:, None, None]
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
    stuck = np.flatnonzero(live & ~reached)
    if stuck.size:
        cells = ", ".join(str(m.table.cell_xy(int(c))) for c in stuck[:5])
        raise ValueError(
            f"policy: with gamma=1 it must reach an exit from every cell that can reach one; it never does from {cells}"
            f"{' ...' if stuck.size > 5 else ''} (its values would be infinite; use gamma < 1 or another policy)"
        )


def check_hint_rules(level: Any, rules: Any) -> None:
    """The goal hint plans without discount: a cell kind of ``level`` whose reward is > 0 would let a robot
    collect it forever (no finite optimum), so it is refused by the rule's name before any planning."""
    kinds = {
        "floor_reward": level.n_cells - len(level.blocked) - len(level.small_puddles) - len(level.large_puddles)
        - len(level.exits) > 0,
        "small_puddle_reward": bool(level.small_puddles),
        "large_puddle_reward": bool(level.large_puddles),
    }
    for name, present in kinds.items():
        if present and getattr(rules, name) > 0:
            raise ValueError(f"{name}: the goal hint (hint=True) needs a level with a finite optimum, a reward <= 0 for "
                             f"every cell a robot can stay in, got {getattr(rules, name)!r}")
