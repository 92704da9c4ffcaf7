"""The race step's fast paths (issue 28) give what the general paths give.

Kept gathers for finishing steps, the common step's copied info template, the lone robot's
step, and the batch engine's step limit: each checked against a fresh env or the rules.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from babyrobot_marl import BabyRobotEnv, race_v0

# the benchmark's scenario level (open 8x8, the four starts in the corners, the exit inside)
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
try:
    from bench_race import CORNERS_8X8 as CORNERS
finally:
    sys.path.pop(0)


def play(env, seed: int, actions: np.ndarray) -> list:
    """Every output of one race, as plain values."""
    obs, infos = env.reset(seed=seed)
    out = [({a: o.tolist() for a, o in obs.items()}, {a: {**i, "cell": i["cell"].tolist()} for a, i in infos.items()})]
    for row in actions:
        if not env.agents:
            break
        obs, rew, term, trunc, infos = env.step(dict(zip(env.agents, row.tolist())))
        infos = {a: {**i, "cell": i["cell"].tolist()} for a, i in infos.items()}
        out.append(({a: o.tolist() for a, o in obs.items()}, rew, term, trunc, infos, list(env.agents)))
    return out


def test_one_env_racing_again_and_again_gives_what_a_fresh_env_gives_each_race():
    """Finishing steps reuse the observation gathers of earlier races (by robot numbers): the
    observations must be those of a fresh env in every finishing order."""
    rng = np.random.default_rng(0)
    for finished in ("remove", "freeze"):
        reused = race_v0.parallel_env(level=CORNERS, n_robots=4, max_cycles=200, finished=finished)
        for seed in range(12):
            actions = rng.integers(0, 5, (200, 4))
            fresh = race_v0.parallel_env(level=CORNERS, n_robots=4, max_cycles=200, finished=finished)
            assert play(reused, seed, actions) == play(fresh, seed, actions), (finished, seed)


def test_infos_are_fresh_each_step_whatever_a_user_does_to_them():
    env = race_v0.parallel_env(level=CORNERS, n_robots=4, max_cycles=200)
    env.reset(seed=0)
    kept = []
    for _ in range(3):
        _, _, _, _, infos = env.step(dict.fromkeys(env.agents, 0))  # STAY: nothing changes but the step count
        for info in infos.values():
            kept.append(info)
            info["rank"], info["finished"], info["note"] = 9, True, "mine"
            info["cell"][:] = -1
    _, _, _, _, infos = env.step(dict.fromkeys(env.agents, 0))
    assert [tuple(i["cell"].tolist()) for i in infos.values()] == [(0, 0), (7, 0), (7, 7), (0, 7)]
    assert all(i["rank"] == 0 and i["finished"] is False and "note" not in i for i in infos.values())
    assert len({id(i) for i in kept}) == len(kept) and len({id(i["cell"]) for i in kept}) == len(kept)


def test_the_last_racing_robot_steps_as_the_batch_engine_steps_it():
    """Once one robot is left racing it takes the one-robot path: on puddles and glass (random draws,
    addressed by robot number and step) it must move as the batch engine, which has no such path,
    moves it."""
    lone_steps = 0
    for level in ("puddles", "glass", "mixed-8x8"):
        for seed in range(4):
            env = race_v0.parallel_env(level=level, n_robots=3, start="random", collisions="pass", finished="freeze")
            env.reset(seed=seed)
            batch = env.batch(1)
            batch.seed([seed])
            batch.reset_envs([0])
            rng = np.random.default_rng(seed)
            while env.agents:
                row = rng.integers(0, 5, 3)
                lone_steps += len(env._live) == 1
                env.step(dict(zip(env.agents, row.tolist())))
                batch.step(row[None, :])
                assert env.robot_cells == [env.table.cell_xy(c) for c in batch.cells[0].tolist()], (level, seed)
    assert lone_steps > 50


def test_the_batch_engine_truncates_at_a_step_limit_set_after_it_was_built():
    batch = BabyRobotEnv(level="maze-8x8").batch(3)
    batch.max_steps = 5
    batch.seed([0, 1, 2])
    batch.reset_envs([0, 1, 2])
    overs = [batch.step(np.zeros((3, 1), dtype=np.int64))[4].tolist() for _ in range(5)]
    assert overs == [[False] * 3] * 4 + [[True] * 3]


def test_two_robots_step_as_the_general_collision_rules_say():
    """Two racing robots take their own path (two comparisons instead of the general resolution):
    every pair of cells and actions of an open level, in every mode, against ``resolve_collisions``."""
    from babyrobot_marl.core.race import race_step, resolve_collisions

    for mode in ("block", "bounce", "pass"):
        env = race_v0.parallel_env(level=CORNERS, n_robots=2, collisions=mode)
        env.reset(seed=0)
        t = env._lists
        cells = [c for c in range(env.table.n_cells) if not t.is_exit[c]][:20]
        checked = stopped = 0
        for c0 in cells:
            for c1 in cells:
                if c0 == c1:
                    continue
                for a0 in range(5):
                    for a1 in range(5):
                        desired = (t.sure[c0][a0][0], t.sure[c1][a1][0])
                        want = resolve_collisions(mode, (c0, c1), desired, 7, 3, (0, 1), 2)
                        final, _, blocked, _ = race_step(t, mode, (c0, c1), (a0, a1), 7, 3, (0, 1), 2)
                        assert list(final) == list(want), (mode, c0, c1, a0, a1)
                        assert blocked == [f != d for f, d in zip(want, desired)]
                        checked += 1
                        stopped += True in blocked
        assert checked > 9000 and (stopped > 0) == (mode != "pass")


def test_crowds_step_on_arrays_as_robot_by_robot_on_puddles_glass_and_exits():
    """A crowd takes the array path of a step (look-ups in the flat table, conflicts found on arrays):
    every output equals the robot-by-robot path's, on puddles and glass walls (random draws) too,
    in every collision mode, while robots finish and the crowd thins out below the array path's size."""
    from unittest import mock

    from babyrobot_marl.core import race as race_core
    from babyrobot_marl.core.level import Level

    w = h = 14
    cells = [(x, y) for y in range(h) for x in range(w)]
    exits, blocked = {(0, 0), (13, 13)}, set(cells[20:200:23])
    small = set(cells[5:190:11]) - blocked - exits
    large = set(cells[7:190:17]) - blocked - exits - small
    level = Level(
        width=w, height=h, exits=frozenset(exits), blocked=frozenset(blocked), small_puddles=frozenset(small),
        large_puddles=frozenset(large), glass=frozenset(((x, y), (x + 1, y)) for x, y in cells[3:180:13] if x + 1 < w),
    )
    actions = np.random.default_rng(5).integers(0, 5, (150, 90))
    skids = 0
    for mode in ("block", "bounce", "soft", "pass"):
        env = race_v0.parallel_env(level=level, n_robots=90, start="random", collisions=mode, max_cycles=150)
        arrays = play(env, 3, actions)
        skids += sum(i["outcome"] == 3 for step in arrays[1:] for i in step[4].values())
        with mock.patch.object(race_core, "_ARRAYS_FROM", 10**9):
            assert play(env, 3, actions) == arrays, mode
    assert skids > 0


def test_finishing_steps_build_their_dicts_by_zip_as_the_loop_over_agents_does(monkeypatch):
    """A step where robots finish while every reported agent was racing builds its five dicts with
    ``racing_outputs`` (zip and map) and its rows from the robots that raced (``_finishing_rows``); the
    per-agent loop and the rows of every robot kept for parked robots must give the same: own targets
    and exits, "remove" and "freeze", local, nearest and global rows, with and without the hint."""
    from babyrobot_marl.envs import race as race_module

    calls = []

    def checked(reported, rows, rewards, outcome, blocked, finishing, xy, ranks, over, parked_done):
        rows, xy, ranks = list(rows), list(xy), list(ranks)
        got = race_module_racing_outputs(reported, rows, rewards, outcome, blocked, finishing, xy, ranks, over, parked_done)
        want = race_module.outputs_with_parked(env, list(env._agent_ids), outcome, blocked, rewards, over, parked_done)
        assert [{a: np.asarray(v).tolist() for a, v in d.items()} for d in got[:4]] == [
            {a: np.asarray(v).tolist() for a, v in d.items()} for d in want[:4]
        ]
        plain = [{a: {**i, "cell": i["cell"].tolist()} for a, i in out[4].items()} for out in (got, want)]
        assert plain[0] == plain[1]
        calls.append((over, True in finishing))
        return got

    race_module_racing_outputs = race_module.racing_outputs
    monkeypatch.setattr(race_module, "racing_outputs", checked)
    configs = [("own", "remove", "local", False), ("exit", "remove", "local", False), ("own", "freeze", "local", False),
               ("own", "remove", "local", True), ("exit", "remove", "local", True), ("own", "remove", "nearest", False),
               ("exit", "remove", "global", False)]  # fmt: skip
    for goals, finished, observe, hint in configs:
        env = race_v0.parallel_env(level="mixed-8x8", n_robots=12, start="random", goals=goals, finished=finished,
                                   observe=observe, hint=hint, max_cycles=60)  # fmt: skip
        rng = np.random.default_rng(1)
        for seed in range(6):
            env.reset(seed=seed)
            while env.agents:
                env.step({a: int(rng.integers(5)) for a in env.agents})
    assert (True, False) in calls or (True, True) in calls  # race ends checked
    assert sum(f for _, f in calls) >= 10  # and many finishing steps
