"""A policy beside the shortest-path and random robots on the same seeded episodes (``babyrobot-marl evaluate``).

    from babyrobot_marl.experiments import evaluate
    ev = evaluate(None, level="maze:8..16", n_robots=4, episodes=200, seed=0)  # None: the two baselines only
    print(ev.table()); ev.plot(); ev.metrics["shortest"]["success_rate"]

Every crowd plays the same episodes: episode ``i`` resets its env with ``seed + i``, so each draws
the same level (a family spec, ``"maze:A..B"`` or ``"maze-WxH-*"``, draws from ``EVAL_MAZE_SEEDS``:
mazes the fast trainer never saw)
and the same starts (``start="random"``). All robots of a crowd act with one policy. Metrics
(POGEMA's), each with a 95% interval inside its range:

- ``success_rate``: the share of robots that reached the exit (Wilson, over robot-episodes);
- ``all_reached_rate``: the share of episodes in which every robot did (Wilson, over episodes);
- ``sum_of_costs``: the mean over episodes of the robots' summed steps (a robot that did not
  finish costs the episode's length), in ``[0, n_robots * limit]``;
- ``makespan``: the mean steps until the last robot finished or the episode ended, in ``[0, limit]``;
- ``throughput`` (``lifelong=True`` only, POGEMA's lifelong metric): the mean over episodes of the
  targets reached per step (all robots together), in ``[0, n_robots]``;

means with the normal approximation, clipped to the range (one episode: the whole range).
With ``goals="own"`` (``env_kwargs``) the robots go to their own targets, and the shortest-path
robots walk a shortest path to theirs; with ``finished="stay"`` robots stay on their targets (POGEMA's
``on_target="nothing"``): a robot counts as arrived if it stands on its target when the episode ends
(its cost: the step it last arrived), and an episode ends early only when all stand on theirs; with
``lifelong=True`` nobody finishes (each target reached brings a new one), so the rates read 0 and
``throughput`` is the measure.
``limit`` is the step limit (``max_cycles``: the largest level's default for a family).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import policies as policy_module
from ..core.checks import check_int
from ..envs.race import RaceEnv
from ..envs.race_goals import OwnGoalShortest
from ..levels.sources import EVAL_MAZE_SEEDS, family_of
from .races import bound_policy
from .stats import mean_interval, wilson

METRICS = ("success_rate", "all_reached_rate", "sum_of_costs", "makespan")
LIFELONG_METRICS = (*METRICS, "throughput")
BASELINES = ("shortest", "random")
CROWDS = {"shortest": "shortest-path robots", "random": "random robots"}  # the table's rows; a policy's: "NAME robots"
JSON_DIGITS = 4  # significant digits: 95% intervals of a few hundred episodes tell no more
Policy = Callable[[np.ndarray], int]


@dataclass
class Episode:
    """One episode of a crowd: its level, length, each robot's finishing step (0: did not finish) and the
    targets its robots reached (own goals)."""

    seed: int
    level: str
    steps: int
    finish_steps: list[int]
    goals_reached: int = 0


def crowd_metrics(episodes: list[Episode], n_robots: int, limit: int, lifelong: bool = False) -> dict[str, float]:
    """The four metrics (``lifelong``: and ``throughput``) and their ``_low``/``_high`` bounds, plain floats (JSON-ready)."""
    n = len(episodes)
    reached = sum(1 for e in episodes for f in e.finish_steps if f)
    all_reached = sum(1 for e in episodes if all(e.finish_steps))
    costs = [sum(f or e.steps for f in e.finish_steps) for e in episodes]
    makespans = [max(e.finish_steps) if all(e.finish_steps) else e.steps for e in episodes]
    out: dict[str, float] = {}
    for name, (value, low, high) in (
        ("success_rate", (reached / (n * n_robots), *wilson(reached, n * n_robots))),
        ("all_reached_rate", (all_reached / n, *wilson(all_reached, n))),
        ("sum_of_costs", _mean(costs, n_robots * limit)),
        ("makespan", _mean(makespans, limit)),
        *((("throughput", _mean([e.goals_reached / e.steps for e in episodes], n_robots)),) if lifelong else ()),
    ):
        out[name], out[f"{name}_low"], out[f"{name}_high"] = value, low, high
    return out


def _mean(values: list[float], top: float) -> tuple[float, float, float]:
    m, low, high = mean_interval(values, lo=0.0, hi=top)
    return (m, 0.0, float(top)) if math.isnan(low) else (m, low, high)  # one episode: nothing known beyond the range


@dataclass
class Evaluation:
    """The crowds' metrics (``metrics[name][metric]``), their episodes, and the settings they ran with."""

    level: str
    n_robots: int
    collisions: str
    limit: int
    episodes: dict[str, list[Episode]]
    metrics: dict[str, dict[str, float]]
    policy_name: str = ""  # the policy's own name in the table (a saved policy: its file)
    policy_is: str | None = None  # a baseline's name when the policy is that baseline: its row is shown once

    @property
    def names(self) -> tuple[str, ...]:
        """The metrics reported: ``METRICS``, and ``throughput`` for lifelong runs."""
        return LIFELONG_METRICS if "throughput" in next(iter(self.metrics.values())) else METRICS

    def table(self) -> str:
        """One row per crowd (a crowd of the policy's robots, of shortest-path and of random robots): each
        metric as ``value [low, high]``."""
        rows = [["crowd", *self.names]]
        for name, m in self.metrics.items():
            if name not in BASELINES and self.policy_is is not None:
                continue  # the same crowd as a baseline's row
            label = CROWDS.get(name, f"{name} robots")
            if name not in BASELINES and self.policy_name:
                label += f" ({self.policy_name})"
            if name == self.policy_is:
                label += " (the policy)"
            rows.append([label] + [_shown(k, m[k], m[f"{k}_low"], m[f"{k}_high"]) for k in self.names])
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
        n = len(next(iter(self.episodes.values())))
        head = (f"{n} episodes on {self.level}, {self.n_robots} robots, collisions {self.collisions}, "
                f"step limit {self.limit}; 95% intervals in brackets")
        return "\n".join([head] + ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows])

    def json(self) -> str:
        """``{"policy": M, "shortest": M, "random": M}`` on one line, each figure to ``JSON_DIGITS`` significant digits."""
        rounded = {name: {k: float(f"{v:.{JSON_DIGITS}g}") for k, v in m.items()} for name, m in self.metrics.items()}
        return json.dumps(rounded, separators=(", ", ": "))

    def plot(self, axes: Any = None) -> Any:
        """The four metrics per crowd with their 95% intervals, one panel each (matplotlib, imported here)."""
        try:
            import matplotlib.pyplot as plt
        except ImportError as err:
            raise ImportError("Evaluation.plot needs matplotlib: pip install 'babyrobot_marl[plot]'") from err
        if axes is None:
            _, axes = plt.subplots(1, len(self.names), figsize=(3.0 * len(self.names), 3.2), layout="constrained")
        names = [n for n in self.metrics if n in BASELINES or self.policy_is is None]
        x = np.arange(len(names))
        for ax, k, top in zip(axes, self.names, (1.05, 1.05, None, None, None)):
            v = np.array([self.metrics[n][k] for n in names])
            err = np.array([[self.metrics[n][k] - self.metrics[n][f"{k}_low"] for n in names],
                            [self.metrics[n][f"{k}_high"] - self.metrics[n][k] for n in names]])
            ax.bar(x, v, 0.6, yerr=err, capsize=4, color=[f"C{i}" for i in range(len(names))])
            ax.set_xticks(x, names)
            ax.set_title(k.replace("_", " "))
            if top is not None:
                ax.set_ylim(0, top)
            else:
                ax.set_ylabel("targets per step" if k == "throughput" else "steps")
        n = len(next(iter(self.episodes.values())))
        axes[0].figure.suptitle(f"{n} episodes on {self.level}, {self.n_robots} robots, collisions {self.collisions} "
                                "(bars: 95% intervals)")
        return axes


def _shown(metric: str, v: float, low: float, high: float) -> str:
    f = ".3f" if metric.endswith("_rate") or metric == "throughput" else ".1f"  # rates to 3 decimals, mean steps to one
    return f"{v:{f}} [{low:{f}}, {high:{f}}]"


def evaluate(
    policy: Policy | str | None,
    level: Any = "maze:8..16",
    n_robots: int = 4,
    episodes: int = 200,
    seed: int = 0,
    collisions: str = "block",
    policy_env: Mapping[str, Any] | None = None,
    name: str = "policy",
    **env_kwargs: Any,
) -> Evaluation:
    """``policy`` (every robot acting with it), the shortest-path robots and random robots on the same
    ``episodes`` seeded episodes; returns their metrics with 95% intervals (``Evaluation``).

    ``policy``: a callable ``observation -> action``, ``None`` for the two baselines only, or a baseline's
    name (``"shortest"``, ``"random"``: its crowd plays once, ``metrics["policy"]`` is its figures); one with
    ``for_env(env)`` (a ``TrainedPolicy``) is bound to its env at every episode. ``policy_env``: the
    observation form it reads (``observe``, ``view_radius``, ``k``, ``obs_encoding``, ``hint``);
    ``level``: a level name, text or ``Level``, or a family spec ``"maze:A..B"`` (drawn from
    ``EVAL_MAZE_SEEDS``); ``env_kwargs``: more race arguments (``max_cycles``, ``rules``...), the
    same for every crowd. Robots start at random cells (``start="random"``).
    """
    n_robots, episodes, seed = check_int(n_robots, "n_robots", 1), check_int(episodes, "episodes", 1), check_int(seed, "seed", 0)
    family = family_of(level, EVAL_MAZE_SEEDS) if isinstance(level, str) else None
    kw = {"n_robots": n_robots, "collisions": collisions, "start": "random", **env_kwargs}
    envs = {n: RaceEnv(level=family or level, observe="nearest", k=1, **kw) for n in BASELINES}  # [x, y] is all they read
    crowds: dict[str, Policy | str] = dict(zip(BASELINES, BASELINES))
    baseline = policy if isinstance(policy, str) else None
    if baseline is not None and baseline not in BASELINES:
        raise ValueError(f"policy: a callable, None, or one of {', '.join(BASELINES)}, got {policy!r}")
    if policy is not None and baseline is None:
        envs = {name: RaceEnv(level=family or level, **dict(policy_env or {}), **kw), **envs}
        crowds = {name: policy, **crowds}
        bound_policy(policy, envs[name])  # a policy that cannot read this env fails here, before any episode
    limit = envs[BASELINES[0]].max_cycles
    runs = {n: [_episode(envs[n], crowds[n], seed + i, i) for i in range(episodes)] for n in crowds}
    label = level if isinstance(level, str) and family is not None else envs[BASELINES[0]].level.name or "custom level"
    lifelong = envs[BASELINES[0]].lifelong
    metrics = {n: crowd_metrics(r, n_robots, limit, lifelong) for n, r in runs.items()}
    if baseline is not None:  # the policy is that baseline: its figures under both names, played once
        runs, metrics = {name: runs[baseline], **runs}, {name: metrics[baseline], **metrics}
    policy_name = "" if policy is None or baseline is not None else str(getattr(policy, "name", ""))
    return Evaluation(label, n_robots, envs[BASELINES[0]].collisions, limit, runs, metrics, policy_name, baseline)


def arrivals(finish: list[int], infos: Mapping[str, Mapping[str, Any]], index: Mapping[str, int], t: int) -> None:
    """Each robot's step of arrival on its exit or target after step ``t``, kept in ``finish`` (0: not there): a
    robot that stays on its target may leave it again, and then its arrival is forgotten (POGEMA's sum of costs
    counts the last one)."""
    for a, info in infos.items():
        k = index[a]
        finish[k] = (finish[k] or t) if info["finished"] else 0


def _episode(env: RaceEnv, crowd: Policy | str, seed: int, i: int) -> Episode:
    obs, _ = env.reset(seed=seed)
    # after the reset: a drawn level changes the table the scripted robots plan on
    if crowd == "shortest" and env.goals_mode == "own":  # each robot on a shortest path to its own target
        acting: list[Any] = [OwnGoalShortest(env.table)] * env.n_robots
    elif isinstance(crowd, str):
        acting = [policy_module.make(crowd, env.table, seed=np.random.default_rng([seed, i, k])) for k in range(env.n_robots)]
    else:
        acting = [bound_policy(crowd, env) for _ in range(env.n_robots)]  # one each: a policy with memory remembers one robot
    index = {a: k for k, a in enumerate(env.possible_agents)}
    finish = [0] * env.n_robots
    while env.agents:
        obs, _, _, _, infos = env.step({a: int(acting[index[a]](obs[a])) for a in env.agents})
        arrivals(finish, infos, index, env.elapsed_steps)
    return Episode(seed, env.level.name, env.elapsed_steps, finish, sum(env.goals_reached))
