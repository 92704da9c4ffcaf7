"""What training gives: the evaluations along the way (``EvalPoint``), the trained network and its totals (``TrainResult``)."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ...core.level import Level
from ..checks import ENV_SETTINGS
from .config import PPOConfig
from .inputs import make_inputs
from .window import window_form


@dataclass
class EvalPoint:
    """One evaluation: timesteps and training seconds so far, the mean training return of recent
    episodes, and the evaluation's score (one robot: mean greedy return; race: win rate)."""

    timesteps: int
    seconds: float
    train_return: float
    score: float


@dataclass
class TrainResult:
    """What ``train_ppo`` returns: the network, where it was trained, the curve and the totals.

    ``seconds`` is training time (rollouts and updates, evaluations excluded), wall-clock;
    ``cpu_seconds`` the process's CPU time over the same spans (on a busy machine wall time also
    counts the others); ``reached`` the first ``(timesteps, seconds)`` whose evaluation met
    ``target`` (None if never or no target).
    """

    net: Any
    level: Level
    n_robots: int
    config: PPOConfig
    seed: int
    timesteps: int = 0
    seconds: float = 0.0
    eval_seconds: float = 0.0
    cpu_seconds: float = 0.0
    history: list[EvalPoint] = field(default_factory=list)
    reached: tuple[int, float] | None = None
    family: str | None = None  # a level family's spec: the net reads local windows (window.WindowForm)
    env: dict[str, Any] = field(default_factory=dict)  # the env settings trained under (``trained_env``)

    @property
    def goals(self) -> str:
        return self.env.get("goals", "exit")

    @property
    def steps_per_second(self) -> float:
        """Timesteps per second of wall-clock training time."""
        return self.timesteps / self.seconds if self.seconds > 0 else float("nan")

    @property
    def steps_per_cpu_second(self) -> float:
        """Timesteps per second of the process's CPU time while training."""
        return self.timesteps / self.cpu_seconds if self.cpu_seconds > 0 else float("nan")

    def policy(self, deterministic: bool = True, seed: int | None = None) -> Any:
        """The trained policy with the scripted policies' interface (``policy(obs) -> action``)."""
        from ..policy import TrainedPolicy, WindowPolicy

        if self.family is not None:
            form = window_form(self.config, self.n_robots, self.goals)
            return WindowPolicy(self.net, form, self.n_robots, deterministic, seed)
        inputs = make_inputs(self.level, self.n_robots, self.config.near_radius)
        return TrainedPolicy(self.net, inputs, self.n_robots, deterministic, seed)

    def save(self, path: str) -> str:
        """Write the network and what it was trained on to ``path`` exactly (a torch file); returns it."""
        from ..policy import save_policy

        return save_policy(self, path)



def trained_env(env_kwargs: dict[str, Any] | None) -> dict[str, Any]:
    """The env settings a policy was trained under (goals, collisions, lifelong, finished), each named with its default."""
    kwargs = env_kwargs or {}
    return {k: kwargs.get(k, default) for k, default in ENV_SETTINGS.items()}


def evaluate_now(result: TrainResult, evaluate: Callable[[TrainResult], float] | None,
                 on_eval: Callable[[EvalPoint], None] | None, target: float | None, span: tuple[float, float],
                 train_return: float) -> tuple[float, float]:
    """Close the training span begun at ``span`` (wall-clock, CPU time), evaluate the net (its time counted as
    evaluation, not training), record the point (and ``reached`` at ``target``), call ``on_eval``; returns the
    next training span's start."""
    result.seconds += time.perf_counter() - span[0]
    result.cpu_seconds += time.process_time() - span[1]
    t0 = time.perf_counter()
    result.net.eval()
    score = float(evaluate(result)) if evaluate is not None else float("nan")
    point = EvalPoint(result.timesteps, result.seconds, train_return, score)
    result.history.append(point)
    if target is not None and result.reached is None and score >= target:
        result.reached = (result.timesteps, result.seconds)
    result.eval_seconds += time.perf_counter() - t0
    if on_eval is not None:
        on_eval(point)
    return time.perf_counter(), time.process_time()
