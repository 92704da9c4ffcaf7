"""Experiment helpers: seeded races, per-robot and per-race metrics with 95% intervals, table, plot, CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest

from babyrobot_marl import cli, experiments
from babyrobot_marl.experiments import mean_interval, run_races, wilson

MIXED = ["shortest", "shortest", "random", "random"]


def test_wilson_interval_matches_the_textbook_values():
    low, high = wilson(5, 10)
    assert low == pytest.approx(0.2366, abs=1e-4) and high == pytest.approx(0.7634, abs=1e-4)
    assert wilson(0, 20)[0] == 0.0 and wilson(20, 20)[1] == 1.0
    assert wilson(0, 20)[1] == pytest.approx(0.1611, abs=1e-4)
    assert all(math.isnan(v) for v in wilson(0, 0))


def test_mean_interval_is_the_mean_plus_minus_1_96_standard_errors():
    m, low, high = mean_interval([1.0, 2.0, 3.0, 4.0])
    se = np.std([1, 2, 3, 4], ddof=1) / 2
    assert m == 2.5 and low == pytest.approx(2.5 - 1.959964 * se) and high == pytest.approx(2.5 + 1.959964 * se)


def test_races_are_reproducible_from_the_seed_and_differ_across_seeds():
    a = run_races("race-4", MIXED, n_races=15, seed=3)
    b = run_races("race-4", MIXED, n_races=15, seed=3)
    c = run_races("race-4", MIXED, n_races=15, seed=4)
    assert [r.__dict__ for r in a.records] == [r.__dict__ for r in b.records]
    assert [r.__dict__ for r in a.records] != [r.__dict__ for r in c.records]
    assert a.table() == b.table()


def test_metrics_agree_with_the_race_records():
    stats = run_races("race-4", MIXED, n_races=30, seed=0)
    recs = stats.records
    for k, row in enumerate(stats.robots):
        firsts = [r for r in recs if r.ranks[k] == 1]
        alone = [r for r in firsts if r.ranks.count(1) == 1]
        assert row["win rate"].value == len(alone) / 30
        assert row["tie rate"].value == (len(firsts) - len(alone)) / 30
        assert row["finish rate"].value == sum(1 for r in recs if r.ranks[k]) / 30
        assert row["blocked steps"].value == pytest.approx(np.mean([r.blocked[k] for r in recs]))
        assert row["win rate"].low <= row["win rate"].value <= row["win rate"].high
    for r in recs:
        assert all((f > 0) == (rank > 0) for f, rank in zip(r.finish_steps, r.ranks))
        assert max(r.finish_steps) <= r.steps
    makespan = np.mean([max(r.finish_steps) if all(r.finish_steps) else r.steps for r in recs])
    assert stats.race["makespan"].value == pytest.approx(makespan)
    soc = np.mean([sum(f or r.steps for f in r.finish_steps) for r in recs])
    assert stats.race["sum of costs"].value == pytest.approx(soc)
    # the shortest-path robots beat the random ones, and random robots get blocked
    assert stats.robots[0]["finish rate"].value == 1.0 and stats.robots[2]["finish rate"].value < 1.0
    assert stats.race["collisions"].value > 0


def test_ranks_of_robots_that_did_not_finish_come_after_every_finisher():
    def stay(obs):
        return 0

    stats = run_races("race-4", ["shortest", stay], n_races=10, seed=1, max_cycles=30)
    for r in stats.records:
        assert r.ranks == [1, 0] and r.steps == 30  # the staying robot never finishes
    assert stats.robots[1]["mean rank"].value == 2.0 and stats.robots[1]["policy"] == "stay"
    assert stats.race["makespan"].value == 30.0 and stats.race["all finished"].value == 0.0
    assert stats.race["sum of costs"].value == pytest.approx(np.mean([r.finish_steps[0] + 30 for r in stats.records]))


def test_a_callable_policy_races_like_its_named_twin():
    from babyrobot_marl import policies, race_v0

    table = race_v0.parallel_env(level="race-4", n_robots=2).table
    mine = policies.make("shortest", table)
    a = run_races("race-4", ["shortest", mine], n_races=5, seed=0)
    b = run_races("race-4", ["shortest", "shortest"], n_races=5, seed=0)
    assert [r.ranks for r in a.records] == [r.ranks for r in b.records]
    assert a.robots[1]["policy"] == "shortest"


@pytest.mark.parametrize(
    ("kw", "word"),
    [
        ({"policies": "shortest"}, "policies"),
        ({"policies": []}, "policies"),
        ({"policies": ["fastest"]}, "policies"),
        ({"n_races": 0}, "n_races"),
        ({"seed": -1}, "seed"),
        ({"n_robots": 3}, "n_robots"),
    ],
)
def test_bad_arguments_name_themselves(kw, word):
    with pytest.raises(ValueError, match=word):
        run_races(**{"level": "race-4", **kw})


def test_plot_draws_three_bars_per_robot_with_intervals():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    stats = run_races("race-4", MIXED, n_races=8, seed=0)
    ax = stats.plot()
    assert len(ax.patches) == 3 * 4
    assert len(ax.get_xticklabels()) == 4


def test_cli_race_races_prints_the_metrics_table(capsys):
    code = cli.main(["race", "--level", "race-4", "--robots", "4", "--policies", ",".join(MIXED), "--races", "12", "--seed", "5"])
    assert code == 0
    out = capsys.readouterr().out
    assert out.startswith("12 races on race-4")
    assert out == run_races("race-4", MIXED, 12, 5, start="fill").table() + "\nseed 5\n"
    assert "makespan:" in out and "robot_3  random" in out


def test_summary_is_plain_numbers():
    s = experiments.summary(run_races("race-2", ["shortest", "shortest"], n_races=3, seed=0))
    assert s["races"] == 3 and len(s["robots"]) == 2
    assert isinstance(s["race"]["makespan"][0], float)


def test_named_policies_act_on_the_level_drawn_for_each_race():
    from babyrobot_marl.levels.sources import maze_family

    stats = run_races(maze_family(6, 6, seeds=range(20)), ["shortest"], n_races=10, seed=0, start="random")
    assert stats.level == "maze-6x6-*"
    assert all(r.ranks == [1] for r in stats.records)  # alone, the shortest path always gets out
    assert all(r.finish_steps[0] <= 2 * 36 for r in stats.records)


def test_intervals_stay_inside_the_range_a_figure_can_take():
    """A rare count (1 blocked step in 40 races) has mean - 1.96 SE < 0: its interval starts at 0."""
    from babyrobot_marl.experiments import RaceRecord, RaceStats

    recs = [
        RaceRecord(seed=i, steps=9, ranks=[1, 2], finish_steps=[5, 9], returns=[-4.0, -8.0],
                   blocked=[int(i == 0), 0], collisions=int(i == 0))
        for i in range(40)
    ]  # fmt: skip
    recs[1].ranks = [2, 1]  # robot 1 wins one race: its mean rank just under 2, the most a rank can be here
    stats = RaceStats("race-2", ["a", "b"], recs)
    blocked, collisions = stats.robots[0]["blocked steps"], stats.race["collisions"]
    assert blocked.value == pytest.approx(0.025) and blocked.low == 0.0 < blocked.high
    assert collisions.low == 0.0 < collisions.value < collisions.high
    first, last = stats.robots[0]["mean rank"], stats.robots[1]["mean rank"]
    assert first.low == 1.0 < first.value < first.high and last.low < last.value < last.high == 2.0
    assert "blocked steps" in stats.table() and "[-" not in stats.table()
    m, low, high = mean_interval([0, 0, 0, 1], lo=0.0)
    assert low == 0.0 and high == pytest.approx(0.25 + 1.959964 * 0.25)


class _Remembering:
    """A policy with ``for_env``: each binding is a new robot (as a trained policy with memory)."""

    def __init__(self) -> None:
        self.bound: list = []

    def for_env(self, env):
        robot = lambda obs: 0  # noqa: E731  (stays)
        self.bound.append(robot)
        return robot

    def __call__(self, obs) -> int:
        raise AssertionError("used without being bound to the env")


def test_a_policy_with_for_env_is_bound_once_per_robot_and_race():
    """A trained policy with memory remembers one robot's episode: run_races and evaluate give every
    robot of every race its own binding (``for_env``), never one object for all."""
    p = _Remembering()
    run_races("race-4", [p, p], n_races=3, max_cycles=5)
    assert len(p.bound) == 6 and len({id(b) for b in p.bound}) == 6
    q = _Remembering()
    experiments.evaluate(q, level="race-4", n_robots=2, episodes=3, max_cycles=5)
    assert len(q.bound) == 1 + 6  # one binding checks the env first, then one per robot and episode
