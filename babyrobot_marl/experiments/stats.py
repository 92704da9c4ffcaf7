"""The statistics of experiments: 95% intervals of rates (Wilson score) and of means (normal approximation).

Intervals are truncated at the range the figure can take: a mean near a bound gets a one-sided
interval, never one that reaches past it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

Z95 = 1.959963984540054  # the two-sided 95% normal quantile

def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of a rate ``successes / n`` (``(nan, nan)`` for ``n = 0``)."""
    if n == 0:
        return (math.nan, math.nan)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    low, high = centre - half, centre + half
    return (0.0 if successes == 0 else max(0.0, low), 1.0 if successes == n else min(1.0, high))  # exact at the ends


def mean_interval(
    values: Sequence[float], z: float = Z95, lo: float = -math.inf, hi: float = math.inf
) -> tuple[float, float, float]:
    """``(mean, low, high)``: the mean +- ``z`` standard errors (``nan`` where undefined), truncated
    at ``lo`` and ``hi``, the range the values (and so their mean) can take."""
    x = np.asarray(values, dtype=np.float64)
    if x.size == 0:
        return (math.nan, math.nan, math.nan)
    m = float(x.mean())
    if x.size == 1:
        return (m, math.nan, math.nan)
    half = z * float(x.std(ddof=1)) / math.sqrt(x.size)
    return (m, max(lo, m - half), min(hi, m + half))


@dataclass(frozen=True)
class Metric:
    """A figure with its 95% interval."""

    value: float
    low: float
    high: float

    def __str__(self) -> str:
        if math.isnan(self.value):
            return "-"
        if math.isnan(self.low):
            return f"{self.value:.3g}"
        return f"{self.value:.3g} [{self.low:.3g}, {self.high:.3g}]"


def rate_metric(successes: int, n: int) -> Metric:
    """A rate with its Wilson interval (nan for no trials)."""
    low, high = wilson(successes, n)
    return Metric(successes / n if n else math.nan, low, high)


def mean_metric(values: Sequence[float], lo: float = -math.inf, hi: float = math.inf) -> Metric:
    """A mean with its interval, truncated at [lo, hi]."""
    return Metric(*mean_interval(values, lo=lo, hi=hi))
