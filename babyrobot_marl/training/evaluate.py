"""A trained racer against scripted robots, many races at once on the batch engine.

``race_rates`` plays ``races`` races in one ``BatchRace``: robot 0 acts greedily with the trained
policy, the others follow ``"random"`` or ``"shortest"``. It counts what ``race.evaluate_race``
counts (a win: robot 0 finished first, ties included; a tie: another robot finished in the same
step) in a fraction of its time, which lets training evaluate often.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.level import Level
from ..policies import POLICY_NAMES, shortest_path_actions
from .deps import torch_module
from .ppo.loop import make_batch, torch_threads


@dataclass(frozen=True)
class RaceRates:
    races: int
    win_rate: float
    tie_rate: float


def race_rates(
    policy: Any, level: Level, n_robots: int, opponent: str = "random", races: int = 100, seed: int = 0, start: str = "fill",
    threads: int | None = 1,
) -> RaceRates:
    """Robot 0 with ``policy`` (a ``TrainedPolicy`` of a race, or ``"shortest"`` / ``"random"`` for
    the scripted robot in that seat: the reference) against ``n_robots - 1`` ``opponent`` robots.

    ``threads``: torch threads meanwhile (as in training: more than one stalls on a busy machine)."""
    if opponent not in POLICY_NAMES:
        raise ValueError(f"opponent: must be one of {', '.join(POLICY_NAMES)}, got {opponent!r}")
    with torch_threads(threads):
        return _race_rates(policy, level, n_robots, opponent, races, seed, start)


def _race_rates(policy: Any, level: Level, n_robots: int, opponent: str, races: int, seed: int, start: str) -> RaceRates:
    torch = torch_module()
    batch = make_batch(level, n_robots, races, start, seed)
    rng = np.random.default_rng(seed)
    shortest = shortest_path_actions(batch.table) if "shortest" in (opponent, policy) else None
    while not batch.over.all():
        if policy == "shortest":
            mine = shortest[batch.cells[:, 0]]
        elif policy == "random":
            mine = rng.integers(0, 5, size=races)
        else:
            rows = policy.inputs.rows(policy.inputs.keys(batch.cells, batch.racing)[:, 0])
            with torch.no_grad():
                mine = policy.net.actor(torch.from_numpy(rows)).argmax(1).numpy()
        others = rng.integers(0, 5, size=(races, n_robots - 1)) if opponent == "random" else shortest[batch.cells[:, 1:]]
        batch.step(np.concatenate([mine[:, None], others], axis=1))
    win = batch.rank[:, 0] == 1
    tie = win & (batch.rank[:, 1:] == 1).any(axis=1)
    return RaceRates(races, float(win.mean()), float(tie.mean()))
