"""The level tables built on arrays equal the tables read off ``Level.neighbours`` cell by cell."""

import numpy as np

from babyrobot_marl import levels
from babyrobot_marl.core.actions import DELTAS, N_ACTIONS
from babyrobot_marl.core.level import Level
from babyrobot_marl.core.outcomes import BUMPED, MOVED, STAYED
from babyrobot_marl.core.table import MAX_SKIDS, compile_level
from babyrobot_marl.levels.sources import parse_level_family


def _by_cell(level: Level):
    """Targets, glass flags and skids of every cell and move, from ``Level.neighbours`` one cell at a time."""
    w, n = level.width, level.n_cells
    target = np.tile(np.arange(n)[:, None], (1, N_ACTIONS))
    glass = np.zeros((n, N_ACTIONS), dtype=bool)
    skid = np.tile(np.arange(n)[:, None, None], (1, N_ACTIONS, MAX_SKIDS))
    n_skid = np.zeros((n, N_ACTIONS), dtype=np.int64)
    for c in range(n):
        x, y = c % w, c // w
        if (x, y) in level.blocked:
            continue
        near = dict(level.neighbours((x, y)))
        clear = [a for a in range(1, N_ACTIONS) if (x + DELTAS[a][0], y + DELTAS[a][1]) in near
                 and not near[(x + DELTAS[a][0], y + DELTAS[a][1])]]
        for a in range(1, N_ACTIONS):
            nxt = (x + DELTAS[a][0], y + DELTAS[a][1])
            if nxt in near:
                target[c, a], glass[c, a] = nxt[1] * w + nxt[0], near[nxt]
        for a in range(1, N_ACTIONS):
            others = [target[c, d] for d in clear if d != a]
            n_skid[c, a] = len(others)
            skid[c, a, : len(others)] = others
    return target, glass, skid, n_skid


def test_tables_built_on_arrays_equal_the_cell_by_cell_reading():
    walled = Level(4, 3, walls=[((0, 0), (1, 0)), ((1, 1), (1, 2))], glass=[((2, 0), (2, 1)), ((2, 2), (3, 2))],
                   blocked=[(3, 0)], small_puddles=[(1, 1)], large_puddles=[(2, 1)], exits=[(0, 2)])
    rng = np.random.default_rng(0)
    mazes = [parse_level_family("maze:5..12")(rng) for _ in range(5)]
    for level in [walled, *mazes, *(levels.get(name) for name in levels.names())]:
        t = compile_level(level)
        target, glass, skid, n_skid = _by_cell(level)
        assert np.array_equal(t.target, target) and np.array_equal(t.glass, glass), level.name
        assert np.array_equal(t.skid, skid) and np.array_equal(t.n_skid, n_skid), level.name
        # the draw-free outcomes: the next cell and its code, -1 where a skid or a glass wall is drawn
        nxt, code = t.sure_flat
        for c in range(level.n_cells):
            for a in range(N_ACTIONS):
                drawn = a > 0 and (t.move_prob[c] < 1.0 or t.glass[c, a])
                want = (-1, -1) if drawn else (target[c, a], STAYED if a == 0 else BUMPED if target[c, a] == c else MOVED)
                assert (nxt[c * N_ACTIONS + a], code[c * N_ACTIONS + a]) == want, (level.name, c, a)
