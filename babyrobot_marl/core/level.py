"""Levels: the map a robot moves on, and its text format.

A ``Level`` is immutable and knows nothing of rewards' defaults or probabilities (those are
``Rules``). Cells are ``(x, y)`` with ``x`` the column and ``y`` the row, ``(0, 0)`` top left.
An edge is the pair of adjacent cells it separates, stored in sorted order.

Text format (see DESIGN.md): a W x H level is 2H+1 lines of 2W+1 characters. Cells sit at odd
line and column indices, edge slots between them, corners at even/even indices::

    +-+-+-+
    |S    |
    + + + +
    |     |
    + + + +
    |    E|
    +-+-+-+
"""

from __future__ import annotations

import numbers
from collections import deque
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from .checks import MAX_LEVEL_TEXT_CHARS, check_int, check_level_size, check_real, shown
from .grid import parse_grid

Cell = tuple[int, int]
Edge = tuple[Cell, Cell]

# Characters of the text format, by slot kind.
FLOOR_CHARS = " ."
CORNER_CHARS = "+#-| "
WALL_V = "|#"  # a wall in a vertical slot (between horizontal neighbours)
WALL_H = "-#"  # a wall in a horizontal slot (between vertical neighbours)
GLASS = "*"
MAX_TEXT_STARTS = 10


class LevelError(ValueError):
    """A ``ValueError`` that may point at the cell (or edge slot) at fault."""

    def __init__(self, message: str, cell: Cell | None = None, slot: tuple[int, int] | None = None):
        super().__init__(message)
        self.cell = cell
        self.slot = slot  # (line index, column index) in a level text, 0-based


def as_cell(value: object, what: str) -> Cell:
    """``(x, y)`` from a pair of integers (numpy's too; not bools, not floats such as ``1.0``)."""
    try:
        x, y = value  # type: ignore[misc]
        if type(x) is int and type(y) is int:  # the common case, checked at once (not bools: their type is bool)
            return (x, y)
        return (check_int(x, what), check_int(y, what))
    except (TypeError, ValueError):
        pass
    raise LevelError(f"{what}: {shown(value)} is not a cell; a cell is a pair of integers (x, y)")


def _as_edge(value: object, what: str) -> Edge:
    try:
        a, b = value  # type: ignore[misc]
    except (TypeError, ValueError):
        raise LevelError(f"{what}: {value!r} is not an edge; an edge is a pair of adjacent cells") from None
    a, b = as_cell(a, what), as_cell(b, what)
    if abs(a[0] - b[0]) + abs(a[1] - b[1]) != 1:
        raise LevelError(f"{what}: {value!r} does not join two adjacent cells", cell=a)
    return (a, b) if a < b else (b, a)


@dataclass(frozen=True, repr=False)
class Level:
    """An immutable grid: walls and glass walls on edges; blocked, puddle, start and exit cells.

    Build one from text with :meth:`from_ascii`, from a grid map (POGEMA's and MovingAI's rows of
    ``.`` and ``#``) with :meth:`from_grid`, or directly::

        Level(width=3, height=1, starts=[(0, 0)], exits=[(2, 0)], walls=[((0, 0), (1, 0))])

    A level may have no exits (a grid map): it is a map for robots with targets of their own,
    and the race to an exit refuses it.

    ``rewards`` maps cells to custom rewards that replace the rules' reward for entering (or
    staying in) those cells; see :meth:`with_rewards`. They are not part of the text format.
    """

    width: int
    height: int
    walls: frozenset[Edge] = frozenset()
    glass: frozenset[Edge] = frozenset()
    blocked: frozenset[Cell] = frozenset()
    small_puddles: frozenset[Cell] = frozenset()
    large_puddles: frozenset[Cell] = frozenset()
    starts: tuple[Cell, ...] = ()
    exits: frozenset[Cell] = frozenset()
    rewards: tuple[tuple[Cell, float], ...] = ()
    name: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        norm = object.__setattr__
        for dim in ("width", "height"):
            try:
                norm(self, dim, check_int(getattr(self, dim), dim, lo=1))
            except ValueError as err:
                raise LevelError(str(err)) from None
        try:
            check_level_size(self.width, self.height)  # before any per-cell work
        except ValueError as err:
            raise LevelError(str(err)) from None
        for name in ("walls", "glass"):
            norm(self, name, frozenset(_as_edge(e, name) for e in _items(getattr(self, name), name, "edges")))
        for name in ("blocked", "small_puddles", "large_puddles", "exits"):
            norm(self, name, frozenset(as_cell(c, name) for c in _items(getattr(self, name), name, "cells")))
        norm(self, "starts", tuple(as_cell(c, "starts") for c in _items(self.starts, "starts", "cells")))
        norm(self, "rewards", _reward_pairs(self.rewards))
        self._validate()

    # ----------------------------------------------------------------------------- checks
    def _validate(self) -> None:
        for name in ("walls", "glass"):
            for a, b in sorted(getattr(self, name)):
                self._check_inside(a, name)
                self._check_inside(b, name)
        both = self.walls & self.glass
        if both:
            e = min(both)
            raise LevelError(f"walls, glass: edge {e} is both a wall and a glass wall", cell=e[0])
        kinds = ("blocked", "small_puddles", "large_puddles", "exits", "starts")
        seen: dict[Cell, str] = {}
        for kind in kinds:
            for c in sorted(getattr(self, kind)) if kind != "starts" else self.starts:
                self._check_inside(c, kind)
                if c in seen:
                    other = "the same start" if seen[c] == kind else seen[c]
                    raise LevelError(f"{kind}: cell {c} is already in {other}; a cell holds one thing", cell=c)
                seen[c] = kind
        for c, _ in self.rewards:
            self._check_inside(c, "rewards")
        if not self.exits:  # a grid map's level: each robot's target is given elsewhere (no race to an exit)
            return
        reach = self.cells_reaching_exit()
        for i, c in enumerate(self.starts):
            if c not in reach:
                raise LevelError(f"starts: start {i} at {c} cannot reach any exit", cell=c)

    def _check_inside(self, c: Cell, what: str) -> None:
        if not (0 <= c[0] < self.width and 0 <= c[1] < self.height):
            raise LevelError(
                f"{what}: cell {c} is outside the {self.width}x{self.height} grid "
                f"(x in 0..{self.width - 1}, y in 0..{self.height - 1})"
            )

    # ----------------------------------------------------------------------------- queries
    @property
    def n_cells(self) -> int:
        return self.width * self.height

    def neighbours(self, c: Cell) -> list[tuple[Cell, bool]]:
        """Cells reachable in one move from ``c``, each with whether a glass wall lies between."""
        out = []
        x, y = c
        for n in ((x, y - 1), (x + 1, y), (x, y + 1), (x - 1, y)):
            if not (0 <= n[0] < self.width and 0 <= n[1] < self.height) or n in self.blocked:
                continue
            e = (c, n) if c < n else (n, c)
            if e not in self.walls:
                out.append((n, e in self.glass))
        return out

    def cells_reaching_exit(self) -> frozenset[Cell]:
        """Open cells from which some exit can be reached (glass walls count as passable)."""
        return self._reaching_exit

    @cached_property
    def _reaching_exit(self) -> frozenset[Cell]:  # once per level: validating it and its free cells both ask
        seen = set(self.exits)
        todo = deque(self.exits)
        while todo:
            c = todo.popleft()
            for n, _ in self.neighbours(c):  # edges are symmetric
                if n not in seen:
                    seen.add(n)
                    todo.append(n)
        return frozenset(seen)

    def free_cells(self) -> list[Cell]:
        """Cells a robot may be placed on: open floor (no puddle, exit) that can reach an exit (any, without exits)."""
        taken = self.blocked | self.exits | self.small_puddles | self.large_puddles
        if not self.exits:
            return [(x, y) for y in range(self.height) for x in range(self.width) if (x, y) not in taken]
        reach = self.cells_reaching_exit()
        return [(x, y) for y in range(self.height) for x in range(self.width) if (x, y) not in taken and (x, y) in reach]

    def reward_map(self) -> dict[Cell, float]:
        return dict(self.rewards)

    def with_rewards(self, rewards: Mapping[Cell, float] | Iterable[tuple[Cell, float]]) -> Level:
        """A copy with custom rewards for the given cells (added to any already set)."""
        merged = self.reward_map()
        merged.update(_reward_pairs(rewards))
        return replace(self, rewards=tuple(merged.items()))

    def with_area_reward(self, corner_a: Cell, corner_b: Cell, reward: float) -> Level:
        """A copy in which every cell of the rectangle between two corners pays ``reward``."""
        (x0, y0), (x1, y1) = as_cell(corner_a, "corner_a"), as_cell(corner_b, "corner_b")
        xs = range(min(x0, x1), max(x0, x1) + 1)
        ys = range(min(y0, y1), max(y0, y1) + 1)
        return self.with_rewards({(x, y): reward for y in ys for x in xs})

    def __repr__(self) -> str:
        label = f"{self.name!r}, " if self.name else ""
        return f"Level({label}{self.width}x{self.height}, starts={len(self.starts)}, exits={len(self.exits)})"

    def __str__(self) -> str:
        return self.to_ascii()

    # ----------------------------------------------------------------------------- text
    def to_ascii(self, starts: bool = True) -> str:
        """The level in the text format of DESIGN.md (custom rewards are not part of it).

        ``starts=False`` draws start cells as floor: the map of a level with more starts than
        the format holds (used by text frames, which draw the robots themselves).
        """
        if starts and len(self.starts) > MAX_TEXT_STARTS:
            raise ValueError(
                f"to_ascii: the text format holds at most {MAX_TEXT_STARTS} starts, this level has {len(self.starts)}"
            )
        w, h = self.width, self.height
        grid = [["+"] * (2 * w + 1) for _ in range(2 * h + 1)]
        start_char = {c: ("S" if len(self.starts) == 1 else str(i)) for i, c in enumerate(self.starts)} if starts else {}
        for y in range(h):
            for x in range(w):
                c = (x, y)
                if c in self.blocked:
                    ch = "#"
                elif c in self.exits:
                    ch = "E"
                elif c in self.small_puddles:
                    ch = "p"
                elif c in self.large_puddles:
                    ch = "P"
                else:
                    ch = start_char.get(c, " ")
                grid[2 * y + 1][2 * x + 1] = ch
                # the edge slot east of and south of this cell
                grid[2 * y + 1][2 * x + 2] = self._edge_char((x, y), (x + 1, y), "|")
                grid[2 * y + 2][2 * x + 1] = self._edge_char((x, y), (x, y + 1), "-")
            grid[2 * y + 1][0] = "|"
        for x in range(w):
            grid[0][2 * x + 1] = "-"
        return "\n".join("".join(row) for row in grid)

    def _edge_char(self, a: Cell, b: Cell, wall: str) -> str:
        if b[0] >= self.width or b[1] >= self.height or (a, b) in self.walls:
            return wall
        return GLASS if (a, b) in self.glass else " "

    @classmethod
    def from_grid(cls, text: str, name: str = "") -> Level:
        """A level from rows of ``.`` (free) and ``#``, ``@``, ``T``, ``O`` (blocked), or a MovingAI
        ``.map`` text (``core.grid``): no walls, starts or exits. Errors name the line and column."""
        width, height, blocked = parse_grid(text)
        return cls(width=width, height=height, blocked=frozenset(blocked), name=name)

    @classmethod
    def from_ascii(cls, text: str, name: str = "") -> Level:
        """Parse the text format. Errors are ``ValueError`` naming the line and column (1-based).

        Lines end with ``\\n``, ``\\r\\n`` or a lone ``\\r``; trailing spaces are trimmed, any other
        whitespace is a character like any other. A text of more than ``MAX_LEVEL_TEXT_CHARS``
        characters or ``MAX_LEVEL_CELLS`` cells is refused before it is parsed.
        """
        if not isinstance(text, str):
            raise TypeError(f"text: expected a level text (str), got {type(text).__name__}")
        if len(text) > MAX_LEVEL_TEXT_CHARS:  # before splitting it into lines
            raise ValueError(f"text: a level text has at most {MAX_LEVEL_TEXT_CHARS:,} characters, got {len(text):,}")
        raw = split_lines(text)
        nonblank = [i for i, line in enumerate(raw) if line.strip(BLANK)]
        if not nonblank:
            raise ValueError("text: the level text is empty")
        first = nonblank[0]
        # Editors trim trailing spaces; any other character (a tab, a form feed) stays and is checked.
        lines = [line.rstrip(" ") for line in raw[first : nonblank[-1] + 1]]
        # Levels written in indented triple-quoted strings: drop the common indent.
        indent = min(len(line) - len(line.lstrip(" ")) for line in lines if line)
        lines = [line[indent:] for line in lines]
        width, height = max(len(line) for line in lines) // 2, len(lines) // 2
        if width * height > 0:
            check_level_size(width, height, what="text")  # before parsing it cell by cell
        try:
            return _parse(lines, name)
        except LevelError as err:
            if err.slot is None and err.cell is not None:
                err.slot = (2 * err.cell[1] + 1, 2 * err.cell[0] + 1)
            if err.slot is None:
                raise ValueError(f"{err}") from None
            line, col = err.slot
            raise ValueError(f"line {line + first + 1}, column {col + indent + 1}: {err}") from None


BLANK = " \t"  # what a blank line before or after the level may hold


def split_lines(text: str) -> list[str]:
    """The lines of a level text: ``\\n``, ``\\r\\n`` and a lone ``\\r`` each end a line (as Python's text files)."""
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")


def looks_like_level_text(spec: str) -> bool:
    """A level text rather than a level name or a file path: it has more than one line."""
    return "\n" in spec or "\r" in spec


def is_number(value: object) -> bool:
    """A real number (numpy's too), not a bool."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def _as_reward(r: object) -> float:
    try:
        return check_real(r, "rewards")
    except ValueError:
        raise LevelError(f"rewards: a reward must be a finite number, got {shown(r)}") from None


def _items(value: object, name: str, what: str) -> Iterable:
    """The members of a collection argument; a clear error for a non-collection."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise LevelError(f"{name}: expected a collection of {what}, got {value!r}")
    return value


def _reward_pairs(rewards: object) -> tuple[tuple[Cell, float], ...]:
    """Custom rewards from a mapping cell -> reward or from (cell, reward) pairs, sorted."""
    pairs = rewards.items() if isinstance(rewards, Mapping) else _items(rewards, "rewards", "(cell, reward) pairs")
    out = []
    for pair in pairs:
        try:
            cell, r = pair
        except (TypeError, ValueError):
            raise LevelError(f"rewards: expected (cell, reward) pairs or a dict cell -> reward, got {pair!r}") from None
        out.append((as_cell(cell, "rewards"), _as_reward(r)))
    return tuple(sorted(out))


def _parse(lines: list[str], name: str) -> Level:
    n_lines = len(lines)
    if n_lines < 3 or n_lines % 2 == 0:
        raise LevelError(
            f"a level has 2*height+1 lines (an odd number, at least 3); this text has {n_lines}",
            slot=(n_lines - 1, 0),
        )
    n_cols = max(len(line) for line in lines)
    if n_cols < 3 or n_cols % 2 == 0:
        i = max(range(n_lines), key=lambda k: len(lines[k]))
        raise LevelError(
            f"ragged line: {n_cols} characters long, but level lines are 2*width+1 (an odd number, at least 3) characters long",
            slot=(i, n_cols - 1),
        )
    width, height = n_cols // 2, n_lines // 2
    walls, glass, blocked, small, large, exits = set(), set(), set(), set(), set(), set()
    starts: dict[int, Cell] = {}
    for i, line in enumerate(lines):
        padded = line.ljust(n_cols)
        for j, ch in enumerate(padded):
            short = f" (line is {len(line)} characters long, the level {n_cols})" if j >= len(line) else ""
            if i % 2 == 0 and j % 2 == 0:
                if ch not in CORNER_CHARS:
                    raise LevelError(f"bad character {ch!r} in a corner slot; allowed: '+', '#', '-', '|', ' '", slot=(i, j))
            elif i % 2 == 1 and j % 2 == 1:
                cell = ((j - 1) // 2, (i - 1) // 2)
                if ch in FLOOR_CHARS:
                    continue
                if ch == "#":
                    blocked.add(cell)
                elif ch == "E":
                    exits.add(cell)
                elif ch == "p":
                    small.add(cell)
                elif ch == "P":
                    large.add(cell)
                elif ch == "S" or ch.isdigit() and ch.isascii():
                    k = 0 if ch == "S" else int(ch)
                    if k in starts:
                        raise LevelError(f"start {k} is given twice ('S' counts as '0')", slot=(i, j))
                    starts[k] = cell
                else:
                    raise LevelError(
                        f"bad character {ch!r} in a cell slot; allowed: ' ', '.', 'S', '0'-'9', 'E', 'p', 'P', '#'",
                        slot=(i, j),
                    )
            else:
                vertical = i % 2 == 1  # a slot between horizontal neighbours
                wall_chars = WALL_V if vertical else WALL_H
                border = j in (0, n_cols - 1) if vertical else i in (0, n_lines - 1)
                if border:
                    if ch not in wall_chars:
                        raise LevelError(
                            f"open border: the outer border must be a wall ({' or '.join(map(repr, wall_chars))}), "
                            f"found {ch!r}{short}",
                            slot=(i, j),
                        )
                    continue
                if vertical:
                    edge = (((j - 2) // 2, (i - 1) // 2), (j // 2, (i - 1) // 2))
                else:
                    edge = (((j - 1) // 2, (i - 2) // 2), ((j - 1) // 2, i // 2))
                if ch in wall_chars:
                    walls.add(edge)
                elif ch == GLASS:
                    glass.add(edge)
                elif ch != " ":
                    kind = "vertical" if vertical else "horizontal"
                    raise LevelError(
                        f"bad character {ch!r} in a {kind} edge slot; allowed: "
                        f"{', '.join(map(repr, wall_chars))} (wall), '*' (glass wall), ' ' (open)",
                        slot=(i, j),
                    )
    for k in sorted(starts):
        if k > 0 and k - 1 not in starts:
            c = starts[k]
            raise LevelError(f"start {k} is given but start {k - 1} is missing (starts are numbered from 0)", cell=c)
    if not exits:
        raise LevelError(f"missing exit: no cell of the {width}x{height} level that begins here is an exit 'E'", slot=(0, 0))
    return Level(
        width=width,
        height=height,
        walls=frozenset(walls),
        glass=frozenset(glass),
        blocked=frozenset(blocked),
        small_puddles=frozenset(small),
        large_puddles=frozenset(large),
        starts=tuple(starts[k] for k in sorted(starts)),
        exits=frozenset(exits),
        name=name,
    )
