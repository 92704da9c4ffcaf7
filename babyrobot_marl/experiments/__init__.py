"""Experiments: N seeded races of given policies, with per-robot and per-race metrics and 95% intervals.

    from babyrobot_marl import experiments
    stats = experiments.run_races("race-4", ["shortest", "shortest", "random", "random"], n_races=200, seed=0)
    print(stats.table())
    stats.plot()  # matplotlib (the "plot" extra), imported only here

Per robot, over the races: win rate (first to finish, alone), tie rate (first together with
others), finish rate, mean rank (a robot that did not finish ranks after every robot that did),
mean steps to finish (finishers only), mean return, and mean steps blocked by other robots.
Per race: makespan (steps until the last robot finished; the race's length when some did not),
sum of costs (each robot's steps until it finished, or the race's length), collisions (steps in
which some robot was stopped by another), and the rate of races every robot finished.
With ``goals="own"`` a robot finishes on its own target and ``"shortest"`` walks to it
(``OwnGoalRobot``); with ``lifelong=True`` the table counts each robot's targets reached and the
races' throughput (targets reached per step) instead.

Intervals are 95%: Wilson score intervals for rates, mean +- 1.96 standard errors for means
(normal approximation: read them as rough below some 30 races), truncated at the range the
figure can take (counts of steps and collisions >= 0, steps to finish >= 1, ranks 1..robots):
a mean near a bound gets a one-sided interval, never one that reaches past it. Race ``i`` resets the env with
seed ``seed + i``; a ``"random"`` robot ``k`` of race ``i`` draws from ``default_rng([seed, i, k])``,
so every figure is reproducible.

``evaluate(policy, level="maze:8..16", n_robots=4, episodes=200, seed=0)`` runs a policy's crowd
beside the shortest-path and random robots on the same seeded episodes (mazes from
``EVAL_MAZE_SEEDS``, never trained on) and gives POGEMA's metrics: ``success_rate``,
``all_reached_rate``, ``sum_of_costs``, ``makespan``, each with a 95% interval inside its range
(``experiments.evaluate``; the command line's ``babyrobot-marl evaluate``).
"""

from .evaluate import Episode, Evaluation, crowd_metrics, evaluate
from .races import OwnGoalRobot, Policy, RaceRecord, RaceStats, run_races, summary
from .stats import Z95, Metric, mean_interval, wilson

__all__ = [
    "Z95", "Episode", "Evaluation", "Metric", "OwnGoalRobot", "Policy", "RaceRecord", "RaceStats", "crowd_metrics", "evaluate",
    "mean_interval", "run_races", "summary", "wilson",
]
