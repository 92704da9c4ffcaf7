"""A race step's five dicts (PettingZoo's parallel API: observations, rewards, terminations,
truncations, infos), built by ``zip`` and ``map`` rather than a Python loop per agent: at a
thousand robots, steps where some robot finishes are most steps."""

from __future__ import annotations

import operator
from collections.abc import Iterable, Sequence
from typing import Any

from ..core.outcomes import FINISHED


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


def outputs_with_parked(
    race: Any, live: list[int], outcome: Sequence[int], blocked: list[bool], rewards: list[float], over: bool,
    parked_done: bool,
) -> tuple[dict, dict, dict, dict, dict]:  # fmt: skip
    """A step's dicts in ``race`` when robots parked before this step are reported too (``finished="freeze"``);
    ``live``: the robots racing before the step, whose ``outcome``, ``blocked`` and ``rewards`` these are."""
    reported, ids, ranks, racing_now, all_cells = race.agents, race._agent_ids, race._rank, race._live_set, race._cells
    was_live = dict(zip(live, range(len(live))))  # robot -> its place among the racing robots
    xy = race._cell_xy.take([all_cells[i] for i in ids], axis=0)  # infos' "cell": rows of one fresh array
    obs, rews, terms, truncs, infos = {}, {}, {}, {}, {}  # in one pass
    for a, i, row, cell in zip(reported, ids, race._observations(), xy):
        k = was_live.get(i)  # None: parked before this step (it earns nothing)
        racing = i in racing_now
        obs[a] = row
        rews[a] = 0.0 if k is None else rewards[k]
        terms[a] = not racing and parked_done
        truncs[a] = over and racing
        infos[a] = {
            "cell": cell,
            "outcome": FINISHED if k is None else outcome[k],
            "blocked": k is not None and blocked[k],
            "finished": not racing,
            "rank": ranks[i],
        }
    return obs, rews, terms, truncs, infos
