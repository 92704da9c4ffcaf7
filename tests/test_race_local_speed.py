"""The crowded race's fast paths ("local" and "nearest" rows of the racing robots alone, infos' cells
as rows of one array) give what the general paths give, and nothing a user keeps changes later."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level

# an open 8x8 room with four exits: 12 robots finish often, one by one or several in a step
ROOM = Level(width=8, height=8, exits={(0, 0), (7, 0), (0, 7), (7, 7)})


def expected_rows(env, agents) -> np.ndarray:
    """The rows of ``agents`` the long way: from all robots' cells and racing flags, then the agents' rows."""
    cells, racing, ids = np.array(env._cells), np.array(env._racing), [env._index[a] for a in agents]
    if env._goal_columns is None:
        return env.encoder(env._observer(cells, racing)[ids])
    cols = env._goal_columns
    rows = cols(env.table, cells, env._goal_arr, out=env._observer(cells, racing, cols.size))
    return env.encoder(rows[ids])


@pytest.mark.parametrize("observe", ["local", "nearest"])
@pytest.mark.parametrize("goals", ["exit", "own"])
@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_rows_of_the_racing_robots_alone_equal_the_rows_of_everyone(observe, goals, finished):
    steps = finishes = 0
    for seed in range(3):
        env = race_v0.parallel_env(level=ROOM, n_robots=12, start="random", observe=observe, goals=goals,
                                   finished=finished, collisions="soft", max_cycles=60)
        obs, _ = env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        while obs:
            assert np.array_equal(np.stack(list(obs.values())), expected_rows(env, obs)), (seed, env._t)
            if not env.agents:
                break
            obs, _, term, _, infos = env.step(dict(zip(env.agents, rng.integers(0, 5, len(env.agents)).tolist())))
            assert [tuple(i["cell"].tolist()) for i in infos.values()] == [env.robot_cells[env._index[a]] for a in infos]
            steps += 1
            finishes += sum(term.values())
    assert steps > 50 and finishes > 5


def test_rows_and_infos_a_user_keeps_do_not_change_with_later_steps():
    level = Level(width=16, height=16, exits={(15, 15)})
    env = race_v0.parallel_env(level=level, n_robots=64, start="random", observe="local", max_cycles=500, collisions="soft")
    obs, _ = env.reset(seed=0)
    kept = []
    rng = np.random.default_rng(0)
    for _ in range(6):
        before = {a: o.copy() for a, o in obs.items()}
        obs, _, _, _, infos = env.step(dict(zip(env.agents, rng.integers(0, 5, len(env.agents)).tolist())))
        kept.append((obs, {a: o.copy() for a, o in obs.items()}, infos, {a: i["cell"].copy() for a, i in infos.items()}))
        assert all(not np.shares_memory(before[a], obs[a]) for a in obs if a in before)
        for o in obs.values():
            o[:] = -7  # a user writing into their rows reaches nobody else's
            break
        for i in infos.values():
            i["cell"][:] = -7
            break
        kept[-1][1][next(iter(obs))][:] = -7
        kept[-1][3][next(iter(infos))][:] = -7
    for rows, copies, infos, cells in kept:
        assert all(np.array_equal(rows[a], copies[a]) for a in rows)
        assert all(np.array_equal(infos[a]["cell"], cells[a]) for a in infos)
