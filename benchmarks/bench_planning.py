"""Value iteration speed: the sparse model (``babyrobot_marl.planning``) against the textbook
dense form ``V <- max_a (R + P @ V)`` on ``P[s, a, s']``, in one run, as ratios.

    python benchmarks/bench_planning.py            # mazes 8x8 .. 64x64 (dense up to 32x32: 64x64 needs 670 MB)
    python benchmarks/bench_planning.py --quick    # CI: small sizes, one repeat
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from babyrobot_marl import levels
from babyrobot_marl.planning import model, value_iteration


def dense_value_iteration(P: np.ndarray, R: np.ndarray, terminal: np.ndarray, theta: float = 1e-9) -> tuple[np.ndarray, int]:
    v = np.zeros(P.shape[0])
    for it in range(1, 100_000):
        new = np.where(terminal, 0.0, (R + P @ v).max(axis=1))
        if np.max(np.abs(new - v)) < theta:
            return new, it
        v = new
    raise RuntimeError("no convergence")


def best_of(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    a = p.parse_args()
    sizes, dense_max, repeats = ([8, 16], 16, 1) if a.quick else ([8, 16, 32, 64], 32, 3)
    print(f"{'level':12s} {'sweeps':>6s} {'sparse s':>9s} {'dense s':>9s} {'dense/sparse':>12s}")
    for n in sizes:
        name = f"maze-{n}x{n}"
        m = model(levels.get(name))
        sol = value_iteration(m)
        sparse = best_of(lambda m=m: value_iteration(m), repeats)
        if n <= dense_max:
            P, R = m.dense
            v, _ = dense_value_iteration(P, R, m.terminal)
            assert np.allclose(v, sol.values)
            dense = best_of(lambda P=P, R=R, m=m: dense_value_iteration(P, R, m.terminal), repeats)
            print(f"{name:12s} {sol.iterations:6d} {sparse:9.4f} {dense:9.4f} {dense / sparse:11.1f}x")
        else:
            print(f"{name:12s} {sol.iterations:6d} {sparse:9.4f} {'-':>9s} {'(dense P too large)':>12s}")


if __name__ == "__main__":
    main()
