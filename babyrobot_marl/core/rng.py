"""Counter-based random numbers: one uniform per (episode key, counter), no hidden state.

Why not draw from a ``numpy.random.Generator`` at every step? Because a generator's draws
depend on how many came before: a robot that skids would shift every later number, and a
batch of envs could not reproduce a single env without a Python loop. Here each random
decision has its own address ``counter`` (step, robot, slot), and the uniform there is
splitmix64's output number ``counter`` of the stream seeded by the episode ``key``. The key
itself is drawn from the env's seeded ``np_random`` at every reset, so all randomness still
comes from the env's generator: same seed, same episodes.
"""

from __future__ import annotations

import numpy as np

_M64 = (1 << 64) - 1
_GAMMA = 0x9E3779B97F4A7C15
_C1 = 0xBF58476D1CE4E5B9
_C2 = 0x94D049BB133111EB
_TO_UNIT = 2.0**-53

# Slots of one robot's step: each random decision reads its own number.
SLOT_SKID, SLOT_SKID_DIRECTION, SLOT_GLASS, SLOT_PRIORITY = 0, 1, 2, 3
SLOTS = 4


def counter(step: int, robot: int, n_robots: int, slot: int) -> int:
    """The address of one random decision: step ``step`` (from 0), robot ``robot``."""
    return ((step * n_robots) + robot) * SLOTS + slot


def uniform(key: int, count: int) -> float:
    """A float in [0, 1) at address ``count`` of the stream ``key`` (pure Python, scalar)."""
    z = (key + (count + 1) * _GAMMA) & _M64
    z = ((z ^ (z >> 30)) * _C1) & _M64
    z = ((z ^ (z >> 27)) * _C2) & _M64
    return ((z ^ (z >> 31)) >> 11) * _TO_UNIT


def uniform_array(keys: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """``uniform`` over arrays (broadcast), bit for bit the same numbers."""
    keys = np.asarray(keys, dtype=np.uint64)
    counts = np.asarray(counts, dtype=np.uint64)
    with np.errstate(over="ignore"):  # wrapping mod 2**64 is intended; 0-d inputs would warn
        z = keys + (counts + np.uint64(1)) * np.uint64(_GAMMA)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(_C1)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(_C2)
        z = (z ^ (z >> np.uint64(31))) >> np.uint64(11)
    return z.astype(np.float64) * _TO_UNIT


def new_key(generator: np.random.Generator) -> int:
    """A fresh episode key drawn from the env's seeded generator."""
    return int(generator.integers(0, 1 << 64, dtype=np.uint64))
