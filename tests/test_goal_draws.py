"""``core.goals.draw_goals`` against the rule it implements, written plainly: each part of the level shuffled
once (``rng.permutation``, in the order robots first need it), its cells taken in turn, a robot skipping its own
start (a swap with the next cell), the last robot of a part trading with the first when only its start is left,
and one error naming ``goals`` when a robot has nothing left to reach."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl.core.goals import draw_goals, own_goal_table, reach
from babyrobot_marl.core.level import Level
from babyrobot_marl.core.rules import Rules
from babyrobot_marl.core.table import compile_level


def plain_draw(rng: np.random.Generator, table, starts: list[int]) -> list[int]:
    r = reach(table)
    shuffled: dict[int, list[int]] = {}
    handed: dict[int, list[int]] = {}  # part -> the robots given a goal there, in turn
    goals = [0] * len(starts)
    for i, s in enumerate(starts):
        k = int(r.component[s])
        if k not in shuffled:
            shuffled[k] = [r.members[k][j] for j in rng.permutation(len(r.members[k]))]
            handed[k] = []
        cells, p = shuffled[k], len(handed[k])
        if p < len(cells) and cells[p] == s:
            if p + 1 < len(cells):
                cells[p], cells[p + 1] = cells[p + 1], cells[p]
            elif handed[k]:
                j = handed[k][0]
                goals[i], goals[j] = goals[j], s
                handed[k].append(i)
                continue
        if p >= len(cells) or cells[p] == s:
            raise ValueError("goals: no free cell is left")
        goals[i] = cells[p]
        handed[k].append(i)
    return goals


def random_table(seed: int, side: int, density: float):
    blocked = np.random.default_rng(seed).random((side, side)) < density
    grid = "\n".join("".join("#" if b else "." for b in row) for row in blocked)
    return own_goal_table(compile_level(Level.from_grid(grid), Rules()))


@pytest.mark.parametrize("side, density", [(8, 0.3), (12, 0.5), (16, 0.6)])
def test_drawn_goals_follow_the_rule_for_any_starts_crowds_and_small_parts(side, density):
    draws = errors = 0
    for seed in range(12):
        table = random_table(seed, side, density)
        r = reach(table)
        open_cells = [c for c in range(table.n_cells) if r.component[c] >= 0]  # singletons and puddles too: errors
        pick = np.random.default_rng(seed)
        for trial in range(12):
            pool = r.free if trial % 3 else open_cells
            if not pool:
                continue
            n = len(pool) if trial % 2 else int(pick.integers(1, len(pool) + 1))  # every free cell a start: trades
            starts = [pool[j] for j in pick.choice(len(pool), size=n, replace=False)]
            try:
                want = plain_draw(np.random.default_rng(trial), table, starts)
            except ValueError:
                with pytest.raises(ValueError, match=r"^goals: no free cell is left for the robot starting at"):
                    draw_goals(np.random.default_rng(trial), table, starts)
                errors += 1
                continue
            assert draw_goals(np.random.default_rng(trial), table, starts) == want
            draws += 1
    assert draws and errors  # both ways were taken
