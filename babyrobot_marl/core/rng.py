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


_U64 = {
    name: np.uint64(v)
    for name, v in {"gamma": _GAMMA, "c1": _C1, "c2": _C2, "one": 1, "s30": 30, "s27": 27, "s31": 31, "s11": 11}.items()
}


def uniform_array(keys: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """``uniform`` over arrays (broadcast), bit for bit the same numbers."""
    keys = np.asarray(keys, dtype=np.uint64)
    counts = np.asarray(counts, dtype=np.uint64)
    u = _U64
    if keys.ndim == 0 and counts.ndim == 0:  # numpy scalars warn on the wrap-around that is intended
        keys, counts = keys.reshape(1), counts.reshape(1)
        return uniform_array(keys, counts)[0]
    # in place where possible: every numpy call counts on small batches
    z = keys + (counts + u["one"]) * u["gamma"]
    z ^= z >> u["s30"]
    z *= u["c1"]
    z ^= z >> u["s27"]
    z *= u["c2"]
    z ^= z >> u["s31"]
    z >>= u["s11"]
    return z.astype(np.float64) * _TO_UNIT


def new_key(generator: np.random.Generator) -> int:
    """A fresh episode key drawn from the env's seeded generator."""
    return int(generator.integers(0, 1 << 64, dtype=np.uint64))
