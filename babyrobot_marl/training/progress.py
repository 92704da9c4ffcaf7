"""A Stable-Baselines3 callback that evaluates every so often and records when the agent first
reaches a target return (timesteps and wall time): the figures of the learning benchmark."""

from __future__ import annotations

import time
from typing import Any

from .deps import require_train


def target_callback(evaluate: Any, target: float, every: int = 5000, stop: bool = True) -> Any:
    """An SB3 ``BaseCallback``: every ``every`` timesteps calls ``evaluate(model) -> mean return``;
    records ``history`` ``[(timesteps, seconds, mean)]`` and ``reached`` (the first
    ``(timesteps, seconds)`` with ``mean >= target``, or None); stops training then if ``stop``."""
    require_train("stable_baselines3")
    from stable_baselines3.common.callbacks import BaseCallback

    class TargetCallback(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.history: list[tuple[int, float, float]] = []
            self.reached: tuple[int, float] | None = None
            self._next = every
            self._t0 = time.perf_counter()
            self._eval_seconds = 0.0  # evaluation time is not training time

        def _on_step(self) -> bool:
            if self.num_timesteps < self._next:
                return True
            self._next += every
            t = time.perf_counter()
            seconds = t - self._t0 - self._eval_seconds
            mean = float(evaluate(self.model))
            self._eval_seconds += time.perf_counter() - t
            self.history.append((self.num_timesteps, seconds, mean))
            if mean >= target and self.reached is None:
                self.reached = (self.num_timesteps, seconds)
                return not stop
            return True

    return TargetCallback()
