"""The learning curve of a run as a PNG (matplotlib, in the ``train`` extra; no pyplot state)."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

from .deps import INSTALL_HINT


def save_curve(
    points: Sequence[tuple[int, float, float]],
    path: str | os.PathLike,
    score_name: str = "greedy return",
    target: float | None = None,
    title: str = "",
) -> str:
    """Plot ``(timesteps, training mean return, evaluation score)`` points; returns ``path``.

    Two panels: the evaluation score (with the ``target`` line, e.g. 95% of the optimum) and the
    mean return of recent training episodes, both against timesteps.
    """
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise ImportError(f"a learning curve needs matplotlib (the 'train' extra): {INSTALL_HINT}") from None
    if not points:
        raise ValueError("points: no evaluations to plot (train for at least one update)")
    steps = [p[0] for p in points]
    fig = Figure(figsize=(7, 5), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    top.plot(steps, [p[2] for p in points], marker="o", markersize=3, label=score_name)
    if target is not None and math.isfinite(target):
        top.axhline(target, color="tab:green", linestyle="--", label="target")
    top.set_ylabel(score_name)
    top.legend(loc="lower right")
    bottom.plot(steps, [p[1] for p in points], color="tab:orange")
    bottom.set_ylabel("training return (last 100 episodes)")
    bottom.set_xlabel("timesteps")
    if title:
        top.set_title(title)
    with open(path, "wb") as f:  # exactly this path, whatever its suffix
        fig.savefig(f, format="png", dpi=100)
    return str(path)
