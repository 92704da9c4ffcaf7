"""Progress of training: a Stable-Baselines3 callback that evaluates every so often and records when
the agent first reaches a target return (timesteps and wall time), and ``TrainProgress``, the bar or
the plain lines a run prints."""

from __future__ import annotations

import sys
import time
from typing import Any

from .deps import require_train


def target_callback(evaluate: Any, target: float, every: int = 5000, stop: bool = True, on_eval: Any = None) -> Any:
    """An SB3 ``BaseCallback``: every ``every`` timesteps calls ``evaluate(model) -> mean return``;
    records ``history`` ``[(timesteps, seconds, mean)]`` and ``reached`` (the first
    ``(timesteps, seconds)`` with ``mean >= target``, or None); stops training then if ``stop``.
    ``on_eval(timesteps, seconds, mean)`` after each evaluation (e.g. ``TrainProgress.evaluation``)."""
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
            self._eval_cpu_seconds = 0.0  # nor its CPU time
            self.train_return = float("nan")  # mean return of SB3's recent training episodes, at the last evaluation

        def _on_step(self) -> bool:
            if self.num_timesteps < self._next:
                return True
            self._next += every
            t, c = time.perf_counter(), time.process_time()
            seconds = t - self._t0 - self._eval_seconds
            mean = float(evaluate(self.model))
            episodes = self.model.ep_info_buffer
            self.train_return = float(sum(e["r"] for e in episodes) / len(episodes)) if episodes else float("nan")
            self._eval_seconds += time.perf_counter() - t
            self._eval_cpu_seconds += time.process_time() - c
            self.history.append((self.num_timesteps, seconds, mean))
            if on_eval is not None:
                on_eval(self.num_timesteps, seconds, mean)
            if mean >= target and self.reached is None:
                self.reached = (self.num_timesteps, seconds)
                return not stop
            return True

    return TargetCallback()


class TrainProgress:
    """What a training run shows: a bar with steps/s and mean return on a terminal, otherwise one
    plain line per evaluation (a log, a pipe, CI), so progress is visible everywhere.

    ``bar``: True for a tqdm bar on ``sys.stderr`` (the ``train`` extra brings tqdm); ``out``: the
    stream of the plain lines. ``score_name``: what an evaluation measures ("return", "win rate").
    """

    def __init__(self, total: int, bar: bool, out: Any, score_name: str = "return", enabled: bool = True):
        self.total, self.out, self.score_name, self.enabled = total, out, score_name, enabled
        self.bar = None
        if enabled and bar:
            from tqdm import tqdm

            self.bar = tqdm(total=total, unit="step", unit_scale=True, dynamic_ncols=True, file=sys.stderr)
        self._done = 0

    def update(self, timesteps: int, seconds: float, mean_return: float) -> None:
        if self.bar is not None:
            self.bar.update(min(timesteps, self.total) - self._done)
            self.bar.set_postfix_str(f"{timesteps / max(seconds, 1e-9):,.0f} steps/s  return {mean_return:.3g}", refresh=False)
        self._done = min(timesteps, self.total)

    def evaluation(self, timesteps: int, seconds: float, train_return: float, score: float) -> None:
        if not self.enabled or self.bar is not None:
            return
        rate = timesteps / seconds if seconds > 0 else float("nan")
        self.out.write(f"{timesteps:>9} steps  {seconds:7.1f} s  {rate:9,.0f} steps/s  training return {train_return:9.3g}  "
                       f"eval {self.score_name} {score:.3g}\n")
        self.out.flush()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
