"""The POGEMA benchmark's scenario (no timing judged, no POGEMA needed): the race on POGEMA's map,
its exit in the largest open region, the local view of radius 2, the paired collision rules."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"
ROWS = [
    "..#.....",
    "..#.....",
    "###..#..",
    ".#......",
]


def load(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    sys.modules.pop("bench_pogema", None)
    return importlib.import_module("bench_pogema")


def test_the_exit_lies_in_the_largest_open_region_nearest_the_centre(monkeypatch):
    b = load(monkeypatch)
    assert b.largest_region_cell(ROWS) == (4, 2)  # the left pocket (4 cells) and (0, 3) are smaller
    assert b.largest_region_cell(["#.", ".#"]) == (1, 0)  # two regions of one cell: the first found


def test_the_race_runs_on_pogemas_map_with_its_view_and_rule(monkeypatch):
    b = load(monkeypatch)
    for _, ours in b.PAIRINGS.values():
        env = b.race_on(ROWS, 6, ours)
        assert env.collisions == ours and env.observe == "local" and env.level.exits == {(4, 2)}
        assert env.level.blocked == {(x, y) for y, row in enumerate(ROWS) for x, ch in enumerate(row) if ch == "#"}
        wide = b.race_v0.parallel_env(level=env.level, n_robots=6, start="random", observe="local", view_radius=3)
        assert env.observation_space("robot_0").shape < wide.observation_space("robot_0").shape  # radius 2, not more
        for seed in range(20):
            env.reset(seed=seed)
            assert not {(0, 0), (1, 0), (0, 1), (1, 1), (0, 3)} & set(env.robot_cells)  # the exit's region only
    assert b.PAIRINGS == {"soft": ("soft", "soft"), "default": ("priority", "block")}


def test_the_own_goal_race_and_the_batch_engine_play_the_same_ground(monkeypatch):
    b = load(monkeypatch)
    own = b.race_on(ROWS, 6, "soft", "own")
    assert own.goals_mode == "own" and own.observe == "local" and own.collisions == "soft"
    env = b.race_on(ROWS, 6, "soft")
    actions = b.np.random.default_rng(1).integers(0, 5, (12, 6)).tolist()
    batch = b.BatchStepper(env, actions)
    env.reset(seed=0)  # the batch engine seeded 0 plays this env's race seeded 0
    batch.run(12)
    for row in actions:
        env.step({a: row[env._index[a]] for a in env.agents})
    assert batch.agent_steps == 72 and batch.done == 12
    assert [env.table.cell_xy(c) for c in batch.batch.cells[0].tolist()] == env.robot_cells
