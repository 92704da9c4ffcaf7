"""A race step's five dicts (PettingZoo's parallel API: observations, rewards, terminations,
truncations, infos), built by ``zip`` and ``map`` rather than a Python loop per agent: at a
thousand robots, steps where some robot finishes are most steps."""

from __future__ import annotations

import operator
from collections.abc import Iterable, Sequence
from typing import Any


def racing_outputs(
    reported: list[str], rows: Iterable[Any], rewards: Sequence[float], outcome: Sequence[int], blocked: Sequence[bool],
    finishing: Sequence[bool], xy: Iterable[Any], ranks: Iterable[int], over: bool, parked_done: bool,
    finished: Sequence[bool] | None = None,
) -> tuple[dict, dict, dict, dict, dict]:  # fmt: skip
    """The outputs of a step in which every reported agent was racing: ``reported`` in the racing robots'
    order, one entry per robot in each sequence. A robot that finishes is terminated when finished robots
    leave (``parked_done``: ``finished="remove"`` or the race's end), the others truncated if it is ``over``.
    Infos' ``"finished"``: ``finished`` if given (robots that stay on their targets), else ``finishing``."""
    obs = dict(zip(reported, rows))
    rews = dict(zip(reported, rewards))
    terms = dict(zip(reported, finishing)) if parked_done else dict.fromkeys(reported, False)
    truncs = dict(zip(reported, map(operator.not_, finishing))) if over else dict.fromkeys(reported, False)
    infos = {
        a: {"cell": c, "outcome": o, "blocked": b, "finished": f, "rank": r}
        for a, c, o, b, f, r in zip(reported, xy, outcome, blocked, finishing if finished is None else finished, ranks)
    }
    return obs, rews, terms, truncs, infos
