"""N seeded races of given policies: per-robot and per-race metrics (``RaceStats``), as a table or a plot."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import policies as policy_module
from ..core.checks import check_int
from ..core.level import Level
from ..envs.race import RaceEnv
from ..envs.race_goals import towards_own_goal
from .stats import Metric, mean_metric, rate_metric

Policy = Callable[[np.ndarray], int]


@dataclass
class RaceRecord:
    """One race: per robot its rank (0: not finished), finishing step (0: not), return and blocked steps."""

    seed: int
    steps: int
    ranks: list[int]
    finish_steps: list[int]
    returns: list[float]
    blocked: list[int]
    collisions: int
    goals_reached: list[int] = field(default_factory=list)  # own goals: the targets each robot reached


@dataclass
class RaceStats:
    """The races of ``run_races`` and their metrics (``robots``, ``race``), as a table or a plot."""

    level: str
    policies: list[str]
    records: list[RaceRecord]
    lifelong: bool = False  # own goals renewed on reaching them: targets reached and throughput count
    robots: list[dict[str, Any]] = field(init=False)
    race: dict[str, Metric] = field(init=False)

    def __post_init__(self) -> None:
        self.robots = [self._robot(k) for k in range(len(self.policies))]
        self.race = self._race()

    @property
    def n_races(self) -> int:
        return len(self.records)

    def _robot(self, k: int) -> dict[str, Any]:
        recs, n = self.records, len(self.records)
        firsts = [r for r in recs if r.ranks[k] == 1]
        tied = sum(1 for r in firsts if r.ranks.count(1) > 1)
        finished = [r for r in recs if r.ranks[k]]
        ranks = [r.ranks[k] or (sum(1 for x in r.ranks if x) + 1) for r in recs]  # unfinished: after every finisher
        return {
            "robot": f"robot_{k}",
            "policy": self.policies[k],
            "win rate": rate_metric(len(firsts) - tied, n),
            "tie rate": rate_metric(tied, n),
            "finish rate": rate_metric(len(finished), n),
            "mean rank": mean_metric(ranks, 1, len(self.policies)),
            "steps to finish": mean_metric([r.finish_steps[k] for r in finished], 1),
            "return": mean_metric([r.returns[k] for r in recs]),  # any sign: the rules set the rewards
            "blocked steps": mean_metric([r.blocked[k] for r in recs], 0),
            **({"targets reached": mean_metric([r.goals_reached[k] for r in recs], 0)} if self.lifelong else {}),
        }

    def _race(self) -> dict[str, Metric]:
        recs = self.records
        costs = [sum(f or r.steps for f in r.finish_steps) for r in recs]
        makespans = [max(r.finish_steps) if all(r.finish_steps) else r.steps for r in recs]
        return {
            "makespan": mean_metric(makespans, 0),
            "sum of costs": mean_metric(costs, 0),
            "collisions": mean_metric([r.collisions for r in recs], 0),
            "all finished": rate_metric(sum(1 for r in recs if all(r.finish_steps)), len(recs)),
            # POGEMA's lifelong measure: targets reached per step, all robots together
            **({"throughput": mean_metric([sum(r.goals_reached) / r.steps for r in recs], 0)} if self.lifelong else {}),
        }

    def table(self) -> str:
        """Per-robot rows, then the per-race figures: ``value [95% interval]``."""
        cols = ["robot", "policy", "win rate", "tie rate", "finish rate", "mean rank", "steps to finish", "blocked steps"]
        if self.lifelong:  # nobody finishes: each reached target brings a new one
            cols = ["robot", "policy", "targets reached", "blocked steps"]
        rows = [cols] + [[str(r[c]) for c in cols] for r in self.robots]
        widths = [max(len(row[i]) for row in rows) for i in range(len(cols))]
        lines = [f"{self.n_races} races on {self.level}, 95% intervals in brackets"]
        lines += ["  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip() for row in rows]
        lines.append("")
        lines += [f"{name}: {metric}" for name, metric in self.race.items()]
        return "\n".join(lines)

    def plot(self, ax: Any = None) -> Any:
        """Win, tie and finish rates per robot with their 95% intervals (matplotlib, imported here)."""
        try:
            import matplotlib.pyplot as plt
        except ImportError as err:
            raise ImportError("RaceStats.plot needs matplotlib: pip install 'babyrobot_marl[plot]'") from err
        if ax is None:
            _, ax = plt.subplots(figsize=(1.2 + 0.9 * len(self.robots), 3.2))
        x = np.arange(len(self.robots))
        for j, (name, colour) in enumerate((("win rate", "C0"), ("tie rate", "C1"), ("finish rate", "C2"))):
            m = [r[name] for r in self.robots]
            v = np.array([q.value for q in m])
            err = np.array([[q.value - q.low for q in m], [q.high - q.value for q in m]])
            ax.bar(x + (j - 1) * 0.27, v, 0.27, yerr=err, capsize=3, label=name, color=colour)
        ax.set_xticks(x, [f"{r['robot']}\n{r['policy']}" for r in self.robots])
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("rate (95% interval)")
        ax.set_title(f"{self.n_races} races on {self.level}")
        ax.legend(fontsize="small")
        return ax


def run_races(
    level: str = "race-4",
    policies: Sequence[str | Policy] = ("shortest", "shortest"),
    n_races: int = 100,
    seed: int = 0,
    **env_kwargs: Any,
) -> RaceStats:
    """Run ``n_races`` seeded races of ``race_v0.parallel_env(level=level, n_robots=len(policies),
    **env_kwargs)``, robot ``k`` acting with ``policies[k]``: a name from ``policies.POLICY_NAMES``
    or a callable ``observation -> action``. Returns their ``RaceStats``."""
    if isinstance(policies, str) or not isinstance(policies, Sequence) or not policies:
        raise ValueError(f"policies: expected a non-empty list of policy names or callables, got {policies!r}")
    for p in policies:
        if not callable(p) and p not in policy_module.POLICY_NAMES:
            raise ValueError(f"policies: {p!r} is neither a policy name ({', '.join(policy_module.POLICY_NAMES)}) nor callable")
    n_races, seed = check_int(n_races, "n_races", 1), check_int(seed, "seed", 0)
    if "n_robots" in env_kwargs:
        raise ValueError("n_robots: given by the number of policies")
    env = RaceEnv(level=level, n_robots=len(policies), **env_kwargs)
    names = [p if isinstance(p, str) else getattr(p, "name", getattr(p, "__name__", type(p).__name__)) for p in policies]
    records = [_one_race(env, policies, seed, i) for i in range(n_races)]
    return RaceStats(_level_name(level, env), names, records, env.lifelong)


def _level_name(level: Any, env: RaceEnv) -> str:
    if isinstance(level, str) and not env.levels.fixed:
        return level  # a family: "maze-WxH-*", "maze:A..B"
    if isinstance(level, (str, Level)):
        return env.level.name or "custom level"
    return getattr(level, "family", "drawn levels")


class OwnGoalRobot:
    """Robot ``k``'s shortest-path robot with own goals: the first step of a shortest path to its own target,
    read from the race itself, so it plays with any observation form (a copy of the race and this robot taken
    together, as ``copy.deepcopy`` takes them, plays on the copy)."""

    name = "shortest"

    def __init__(self, race: RaceEnv, k: int):
        self.race, self.k = race, k

    def __call__(self, obs: Any = None) -> int:
        return towards_own_goal(self.race, self.k)


def bound_policy(policy: Policy, env: RaceEnv) -> Policy:
    """A trained policy bound to this race's env, one per robot and race (``for_env``: a policy with
    memory remembers one robot's episode); any other callable as it is."""
    for_env = getattr(policy, "for_env", None)
    return for_env(env) if for_env is not None else policy


def _one_race(env: RaceEnv, policies: Sequence[str | Policy], seed: int, i: int) -> RaceRecord:
    obs, _ = env.reset(seed=seed + i)
    # named policies after the reset: a drawn level (level= a family) changes the table
    acting = [
        OwnGoalRobot(env, k) if p == "shortest" and env.goals_mode == "own"
        else policy_module.make(p, env.table, seed=np.random.default_rng([seed, i, k])) if isinstance(p, str)
        else bound_policy(p, env)
        for k, p in enumerate(policies)
    ]  # fmt: skip
    n = env.n_robots
    index = {a: k for k, a in enumerate(env.possible_agents)}
    finish = [0] * n
    collisions = 0
    while env.agents:
        actions = {a: int(acting[index[a]](obs[a])) for a in env.agents}
        obs, _, _, _, infos = env.step(actions)
        collisions += any(info["blocked"] for info in infos.values())
        for a, info in infos.items():
            if info["finished"] and not finish[index[a]]:
                finish[index[a]] = env.elapsed_steps
    return RaceRecord(seed + i, env.elapsed_steps, env.ranks, finish, env.returns, env.collisions_count, collisions,
                      env.goals_reached)


def summary(stats: RaceStats) -> Mapping[str, Any]:
    """The metrics as plain numbers (for JSON): per robot and per race, each ``[value, low, high]``."""

    def plain(m: Any) -> Any:
        return [m.value, m.low, m.high] if isinstance(m, Metric) else m

    return {
        "level": stats.level,
        "races": stats.n_races,
        "robots": [{k: plain(v) for k, v in r.items()} for r in stats.robots],
        "race": {k: plain(v) for k, v in stats.race.items()},
    }
