"""Hypothesis strategies and independent oracles shared by the reliability tests.

The oracles here (reachability, free cells, the reward of a cell, wall look-ups) are written
from DESIGN.md and the ``Level`` / ``Rules`` fields alone, never from the compiled tables or
the envs, so that a test comparing an env against them can fail.
"""

from __future__ import annotations

import dataclasses
from collections import deque

import numpy as np
from hypothesis import strategies as st

from babyrobot_marl import Level, Rules, levels
from babyrobot_marl.core.rules import COLLISION_MODES

Cell = tuple[int, int]
DELTAS = ((0, 0), (0, -1), (1, 0), (0, 1), (-1, 0))  # STAY, NORTH, EAST, SOUTH, WEST (DESIGN.md)
SHORTEST = 5  # an action token meaning "what the shortest-path robot would do": lets robots reach exits
MAX_SIDE = 32

# An open 5x5 race level: starts 0..5 along the top and the second row, the exit at (4, 4).
OPEN = """
+-+-+-+-+-+
|0 1 2 3 4|
+ + + + + +
|5        |
+ + + + + +
|         |
+ + + + + +
|         |
+ + + + + +
|        E|
+-+-+-+-+-+
"""


def edge(a: Cell, b: Cell) -> tuple[Cell, Cell]:
    return (a, b) if a < b else (b, a)


def inside(level: Level, c: Cell) -> bool:
    return 0 <= c[0] < level.width and 0 <= c[1] < level.height


def open_neighbours(level: Level, c: Cell, through_glass: bool = True) -> list[Cell]:
    """Cells one move away from ``c``: on the grid, not blocked, no wall (glass only if allowed)."""
    out = []
    for dx, dy in DELTAS[1:]:
        n = (c[0] + dx, c[1] + dy)
        if not inside(level, n) or n in level.blocked:
            continue
        e = edge(c, n)
        if e in level.walls or (e in level.glass and not through_glass):
            continue
        out.append(n)
    return out


def reaching_exit(level: Level) -> set[Cell]:
    """Cells from which an exit can be reached, glass walls counted as passable (DESIGN.md)."""
    seen = set(level.exits)
    todo = deque(level.exits)
    while todo:
        c = todo.popleft()
        for n in open_neighbours(level, c):
            if n not in seen:
                seen.add(n)
                todo.append(n)
    return seen


def free_cells(level: Level) -> set[Cell]:
    """Where a robot may be placed at random: open floor that can reach an exit."""
    taken = level.blocked | level.exits | level.small_puddles | level.large_puddles
    return {c for c in reaching_exit(level) if c not in taken}


def cell_reward(level: Level, rules: Rules, c: Cell) -> float:
    """The reward of ending a step in ``c`` (custom rewards first, then the cell's kind)."""
    custom = dict(level.rewards)
    if c in custom:
        return custom[c]
    if c in level.exits:
        return rules.exit_reward
    if c in level.small_puddles:
        return rules.small_puddle_reward
    if c in level.large_puddles:
        return rules.large_puddle_reward
    return rules.floor_reward


def check_move(level: Level, rules: Rules, before: Cell, after: Cell, action: int | None) -> None:
    """A single robot's move obeys the map: on the grid, not blocked, at most one cell, no wall crossed.

    ``action`` None: the action is not known (a scripted opponent); only the map is checked.
    """
    assert inside(level, after), f"{after} is off the {level.width}x{level.height} grid"
    assert after not in level.blocked, f"robot in blocked cell {after}"
    dist = abs(after[0] - before[0]) + abs(after[1] - before[1])
    assert dist <= 1, f"moved {dist} cells in one step: {before} -> {after}"
    if action is None:
        if dist == 1:
            e = edge(before, after)
            assert e not in level.walls, f"crossed the wall {e}"
            assert e not in level.glass or rules.glass_pass_prob > 0, f"crossed the glass wall {e} with glass_pass_prob 0"
        return
    if action == 0:
        assert after == before, f"STAY moved the robot {before} -> {after}"
    if dist == 1:
        e = edge(before, after)
        assert e not in level.walls, f"crossed the wall {e}"
        if e in level.glass:
            assert rules.glass_pass_prob > 0, f"crossed the glass wall {e} with glass_pass_prob 0"
            intended = (before[0] + DELTAS[action][0], before[1] + DELTAS[action][1])
            assert after == intended, f"skidded through the glass wall {e}"
        on_puddle = before in level.small_puddles or before in level.large_puddles
        if not on_puddle:
            intended = (before[0] + DELTAS[action][0], before[1] + DELTAS[action][1])
            assert after == intended, f"moved {before} -> {after} off a puddle with action {action}"


def check_outcome(level: Level, rules: Rules, before: Cell, after: Cell, action: int, outcome: str) -> None:
    """A robot's own outcome (before other robots interfere) agrees with the map and the rules."""
    intended = (before[0] + DELTAS[action][0], before[1] + DELTAS[action][1])
    reachable = inside(level, intended) and intended in open_neighbours(level, before)
    behind_glass = reachable and edge(before, intended) in level.glass
    on_puddle = before in level.small_puddles or before in level.large_puddles
    move_prob = (
        rules.small_puddle_move_prob
        if before in level.small_puddles
        else rules.large_puddle_move_prob
        if before in level.large_puddles
        else 1.0
    )
    if outcome == "stayed":
        assert action == 0
    elif outcome == "moved":
        assert action != 0 and reachable and (not behind_glass or rules.glass_pass_prob > 0)
    elif outcome == "bumped":
        assert action != 0 and not reachable, f"bumped although {intended} is open from {before}"
    elif outcome == "glass":
        assert action != 0 and behind_glass and rules.glass_pass_prob < 1, f"glass outcome {before} -> {intended}"
    elif outcome == "skidded":
        assert action != 0 and on_puddle and move_prob < 1, f"skidded from {before} (move prob {move_prob})"
        if after != before:
            assert after != intended and after in open_neighbours(level, before, through_glass=False)
    else:
        raise AssertionError(f"unknown outcome {outcome!r}")
    if outcome in ("bumped", "glass", "stayed"):
        assert after == before


# --------------------------------------------------------------------------------------- levels
def _random_level(width: int, height: int, seed: int, density: dict[str, float], n_starts: int, n_rewards: int) -> Level:
    """A level drawn by numpy from ``seed``: walls, glass, blocked cells, puddles, exits, starts."""
    g = np.random.default_rng(seed)
    cells = [(x, y) for y in range(height) for x in range(width)]
    walls, glass = set(), set()
    for x, y in cells:
        for n in ((x + 1, y), (x, y + 1)):
            if n[0] < width and n[1] < height:
                u = g.random()
                if u < density["wall"]:
                    walls.add(((x, y), n))
                elif u < density["wall"] + density["glass"]:
                    glass.add(((x, y), n))
    kinds: dict[Cell, str] = {}
    for c in cells:
        u = g.random()
        if u < density["blocked"]:
            kinds[c] = "#"
        elif u < density["blocked"] + density["puddle"]:
            kinds[c] = "p" if g.random() < 0.5 else "P"
    n_exits = 1 + int(g.integers(3))
    for k in g.choice(len(cells), size=min(n_exits, len(cells)), replace=False):
        kinds[cells[int(k)]] = "E"
    base = Level(
        width=width,
        height=height,
        walls=walls,
        glass=glass,
        blocked={c for c, k in kinds.items() if k == "#"},
        small_puddles={c for c, k in kinds.items() if k == "p"},
        large_puddles={c for c, k in kinds.items() if k == "P"},
        exits={c for c, k in kinds.items() if k == "E"},
    )
    return _decorate(base, g, n_starts, n_rewards)


def _decorate(level: Level, g: np.random.Generator, n_starts: int, n_rewards: int) -> Level:
    """Random starts on free cells and custom rewards on random open cells."""
    free = sorted(free_cells(level) - set(level.starts))
    extra = [free[int(k)] for k in g.permutation(len(free))[: max(0, n_starts - len(level.starts))]]
    starts = tuple(level.starts) + tuple(extra)
    open_cells = [(x, y) for y in range(level.height) for x in range(level.width) if (x, y) not in level.blocked]
    picks = g.permutation(len(open_cells))[:n_rewards]
    rewards = {open_cells[int(k)]: float(g.choice([-7.5, -0.5, 0.0, 1.0, 3.25])) for k in picks}
    return dataclasses.replace(level, starts=starts, rewards=tuple(rewards.items()))


def _maze_level(width: int, height: int, seed: int, glass_share: float, puddle_share: float, n_starts: int, n_rewards: int):
    """``levels.maze`` with some walls turned into glass and some floor into puddles."""
    maze = levels.maze(width, height, seed)
    g = np.random.default_rng(seed + 1)
    walls = sorted(maze.walls)
    to_glass = {walls[int(k)] for k in g.permutation(len(walls))[: int(len(walls) * glass_share)]}
    floor = sorted(set((x, y) for y in range(height) for x in range(width)) - set(maze.starts) - maze.exits)
    wet = [floor[int(k)] for k in g.permutation(len(floor))[: int(len(floor) * puddle_share)]]
    level = dataclasses.replace(
        maze,
        walls=maze.walls - to_glass,
        glass=frozenset(to_glass),
        small_puddles=frozenset(wet[::2]),
        large_puddles=frozenset(wet[1::2]),
    )
    return _decorate(level, g, n_starts, n_rewards)


DENSITIES = st.fixed_dictionaries(
    {
        "wall": st.sampled_from([0.0, 0.1, 0.3, 0.6]),
        "glass": st.sampled_from([0.0, 0.1, 0.3]),
        "blocked": st.sampled_from([0.0, 0.1, 0.25, 0.5]),
        "puddle": st.sampled_from([0.0, 0.1, 0.3, 0.9]),
    }
)


@st.composite
def grid_levels(draw, max_side: int = MAX_SIDE) -> Level:
    """Random levels of 1x1 to ``max_side`` x ``max_side``: random grids and decorated mazes."""
    side = st.one_of(st.integers(1, min(4, max_side)), st.integers(1, min(12, max_side)), st.integers(1, max_side))
    width, height = draw(side), draw(side)
    seed = draw(st.integers(0, 2**32 - 1))
    n_starts = draw(st.integers(0, 12))
    n_rewards = draw(st.sampled_from([0, 0, 1, 3]))
    if width * height >= 2 and draw(st.booleans()):
        glass_share = draw(st.sampled_from([0.0, 0.2, 1.0]))
        puddle_share = draw(st.sampled_from([0.0, 0.3]))
        return _maze_level(width, height, seed, glass_share, puddle_share, n_starts, n_rewards)
    return _random_level(width, height, seed, draw(DENSITIES), n_starts, n_rewards)


REWARDS = st.sampled_from([-1.0, -2.0, -4.0, 0.0, 0.5, 3.0, -0.25])
PROBABILITIES = st.sampled_from([0.0, 0.4, 0.6, 1.0])


@st.composite
def rules(draw, collisions: str | None = None) -> Rules:
    """Random rules: rewards, skid and glass probabilities (0 and 1 included), win bonus."""
    return Rules(
        floor_reward=draw(REWARDS),
        small_puddle_reward=draw(REWARDS),
        large_puddle_reward=draw(REWARDS),
        exit_reward=draw(REWARDS),
        small_puddle_move_prob=draw(PROBABILITIES),
        large_puddle_move_prob=draw(PROBABILITIES),
        glass_pass_prob=draw(st.sampled_from([0.0, 0.5, 1.0])),
        collisions=collisions or draw(st.sampled_from(COLLISION_MODES)),
        win_bonus=draw(st.sampled_from([10.0, 0.0, 2.5])),
    )


# Action tokens: 0..4 are the actions, SHORTEST the shortest-path robot's choice (so that robots
# reach exits often, and meet there).
ACTION_TOKENS = st.lists(st.sampled_from([0, 1, 2, 3, 4, SHORTEST, SHORTEST, SHORTEST]), min_size=1, max_size=48)

SEEDS = st.integers(0, 2**32 - 1)


# --------------------------------------------------------------------------------------- texts
LEVEL_CHARS = "+-|#* .SEpP0123456789"


def base_texts() -> list[str]:
    """The built-in levels' texts (canonical, as ``levels.text`` writes them)."""
    return [levels.text(name) for name in levels.names()]


@st.composite
def small_level_texts(draw) -> str:
    """The canonical text of a random level of at most 8x8 with at most 10 starts."""
    level = draw(grid_levels(max_side=8))
    if len(level.starts) > 10:
        level = dataclasses.replace(level, starts=level.starts[:10])
    return level.to_ascii()


MUTATION_CHARS = st.one_of(st.sampled_from(LEVEL_CHARS + "\t\r\x0b\x0c\u00a0\u2028\u00b2x!"), st.characters())


@st.composite
def mutated_texts(draw) -> str:
    """A valid level text (built-in or random) with a few random edits: characters, lines, layout."""
    text = draw(st.one_of(st.sampled_from(base_texts()), small_level_texts()))
    lines = text.split("\n")
    for _ in range(draw(st.integers(1, 4))):
        op = draw(
            st.sampled_from(
                ["replace", "replace", "insert", "delete", "dup_line", "del_line", "swap_lines", "cut_line", "blank_line"]
            )
        )
        i = draw(st.integers(0, len(lines) - 1)) if lines else 0
        line = lines[i] if lines else ""
        j = draw(st.integers(0, len(line))) if line is not None else 0
        if op == "replace" and line:
            j = min(j, len(line) - 1)
            lines[i] = line[:j] + draw(MUTATION_CHARS) + line[j + 1 :]
        elif op == "insert":
            lines[i] = line[:j] + draw(MUTATION_CHARS) + line[j:]
        elif op == "delete" and line:
            j = min(j, len(line) - 1)
            lines[i] = line[:j] + line[j + 1 :]
        elif op == "dup_line" and lines:
            lines.insert(i, line)
        elif op == "del_line" and lines:
            del lines[i]
        elif op == "swap_lines" and len(lines) > 1:
            k = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[k] = lines[k], lines[i]
        elif op == "cut_line":
            lines[i] = line[:j]
        elif op == "blank_line":
            lines.insert(i, draw(st.sampled_from(["", "   ", "\t"])))
    indent = " " * draw(st.sampled_from([0, 0, 2, 5]))
    lines = [indent + line if line else line for line in lines]
    sep = draw(st.sampled_from(["\n", "\n", "\r\n"]))
    head = draw(st.sampled_from(["", "\n", "\n\n  \n"]))
    tail = draw(st.sampled_from(["", "\n", "  \n"]))
    return head + sep.join(lines) + tail


RANDOM_TEXTS = st.text(alphabet=LEVEL_CHARS + "\n\n\n\r\t", max_size=120)


@st.composite
def slot_texts(draw) -> str:
    """Random texts of the right shape: each slot mostly a character allowed there, borders mostly walls."""
    width, height = draw(st.integers(1, 6)), draw(st.integers(1, 5))
    rows = []
    for i in range(2 * height + 1):
        row = []
        for j in range(2 * width + 1):
            border = i in (0, 2 * height) or j in (0, 2 * width)
            if i % 2 == 0 and j % 2 == 0:
                allowed = "+#-| "
            elif i % 2 == 1 and j % 2 == 1:
                allowed = "         ....SEEpP#01"
            elif border:
                allowed = "|#" if i % 2 == 1 else "-#"
            else:
                allowed = ("|#" if i % 2 == 1 else "-#") + "     *"
            row.append(
                draw(st.one_of(st.sampled_from(allowed), MUTATION_CHARS))
                if draw(st.integers(0, 40)) == 0
                else draw(st.sampled_from(allowed))
            )
        rows.append("".join(row))
    return "\n".join(rows)


def exit_distances(level: Level) -> dict[Cell, int]:
    """Moves from each cell to the nearest exit (glass passable), by BFS over the level's own
    sets: an oracle written independently of the compiled tables."""
    dist, todo = dict.fromkeys(level.exits, 0), deque(level.exits)
    while todo:
        x, y = todo.popleft()
        for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
            e = ((x, y), n) if (x, y) < n else (n, (x, y))
            if (
                0 <= n[0] < level.width
                and 0 <= n[1] < level.height
                and n not in level.blocked
                and e not in level.walls
                and n not in dist
            ):
                dist[n] = dist[(x, y)] + 1
                todo.append(n)
    return dist


def resolve_all_robots(mode, cells, desired, racing, key, step):
    """``core.race.resolve_collisions`` for a whole race: the racing robots resolved (with their
    robot numbers), the finished ones left where ``desired`` puts them."""
    from babyrobot_marl.core import race

    live = [i for i in range(len(cells)) if racing[i]]
    got = race.resolve_collisions(mode, [cells[i] for i in live], [desired[i] for i in live], key, step, live, len(cells))
    final = list(desired)
    for k, i in enumerate(live):
        final[i] = got[k]
    return final
