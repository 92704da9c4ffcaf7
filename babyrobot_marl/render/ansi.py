"""Text frames: the level text with robots drawn on it (pure Python, no terminal needed)."""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

from ..core.level import MAX_TEXT_STARTS, Cell, Level

ROBOT_LETTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
# Foreground colours for robots in a terminal (ANSI SGR codes), cycled.
ROBOT_COLOURS = (31, 34, 32, 35, 33, 36, 91, 94, 92, 95)


# One character per robot: Latin letters, then the Greek ones that look like no Latin letter.
GLYPHS = ROBOT_LETTERS + ROBOT_LETTERS.lower() + "ΓΔΘΛΞΠΣΦΨΩ" + "αβγδεζηθικλμξπρστυφχψω"
MANY = "@"  # robots past the last glyph; the frame says so under the grid


def robot_glyph(i: int, n_robots: int) -> str:
    """``R`` for a lone robot, else ``A``..``Z``, ``a``..``z``, then Greek letters (84 in all);
    ``@`` past those (the frame's status line says which robots share it)."""
    if n_robots == 1:
        return "R"
    return GLYPHS[i] if i < len(GLYPHS) else MANY


@lru_cache(maxsize=8)
def _level_text(level: Level) -> str:  # once per level: a 256x256 level's text takes a second to write
    return level.to_ascii(starts=len(level.starts) <= MAX_TEXT_STARTS)  # more starts than digits: plain floor


def symbols(level: Level, robots: str = "") -> str:
    """One line naming the symbols ``level``'s text frame uses (only those), after ``robots`` (e.g. "R you")."""
    text = _level_text(level)
    lines = text.split("\n")
    cells = {ch for line in lines[1::2] for ch in line[1::2]}  # cell slots: odd lines, odd columns
    slots = {ch for y, line in enumerate(lines) for x, ch in enumerate(line) if (x + y) % 2}  # edge slots
    digits = sorted(ch for ch in cells if ch.isdigit())
    puddles = "/".join(ch for ch in "pP" if ch in cells)
    parts = [robots] if robots else []
    parts += ["+-| wall"]
    wall_hash, cell_hash = "#" in slots, "#" in cells
    if wall_hash or cell_hash:
        parts.append("# " + " or ".join(w for w, on in (("wall", wall_hash), ("blocked cell", cell_hash)) if on))
    if "*" in slots:
        parts.append("* glass wall (sometimes passed)")
    if puddles:
        parts.append(f"{puddles} {'small/large ' if len(puddles) > 1 else ('small ' if puddles == 'p' else 'large ')}puddle")
    if digits:
        parts.append(f"{digits[0]}-{digits[-1]} numbered starts" if len(digits) > 1 else f"{digits[0]} a start")
    if "S" in cells:
        parts.append("S start")
    if "E" in cells:
        parts.append("E exit")
    return "key: " + ", ".join(parts)


def frame(level: Level, robots: Sequence[Cell | None], status: str = "", colour: bool = False,
          goals: Sequence[tuple[int, Cell]] = ()) -> str:  # fmt: skip
    """The level as text with robot ``i`` drawn at ``robots[i]`` (``None``: off the board), and
    each robot's own target (``goals``: ``(i, cell)``) as its letter in lower case, under the robots.

    Several robots in one cell (collision mode "pass") show the lowest-numbered one.
    ``colour=True`` adds ANSI colours for a terminal.
    """
    text = _level_text(level)
    lines = [list(line) for line in text.split("\n")]
    n = len(robots)
    shown = [(i, cell) for i, cell in goals if n == 1 or i < len(ROBOT_LETTERS)]
    for i, (x, y) in shown:
        glyph = robot_glyph(i, n).lower()
        lines[2 * y + 1][2 * x + 1] = f"\x1b[{ROBOT_COLOURS[i % len(ROBOT_COLOURS)]}m{glyph}\x1b[0m" if colour else glyph
    for i in reversed(range(n)):
        cell = robots[i]
        if cell is None:
            continue
        glyph = robot_glyph(i, n)
        if colour:
            glyph = f"\x1b[1;{ROBOT_COLOURS[i % len(ROBOT_COLOURS)]}m{glyph}\x1b[0m"
        lines[2 * cell[1] + 1][2 * cell[0] + 1] = glyph
    text = "\n".join("".join(line) for line in lines)
    if goals:
        note = goal_key(n, len(shown) < len(goals))
        status = f"{status}\n{note}" if status else note
    if n > len(GLYPHS):
        note = f"robots {len(GLYPHS)}..{n - 1} drawn as {MANY} (one character each is not enough; rgb_array draws their numbers)"
        status = f"{status}\n{note}" if status else note
    return f"{text}\n{status}" if status else text


def goal_key(n_robots: int, some_unshown: bool = False) -> str:
    """The text frame's line naming the targets' letters."""
    if n_robots == 1:
        return "r: the robot's target"
    last = ROBOT_LETTERS[min(n_robots, len(ROBOT_LETTERS)) - 1]
    key = f"a-{last.lower()}: the targets of robots A-{last} (each its robot's letter in lower case)"
    return key + (f"; robots past {last}: targets not shown (rgb_array draws them)" if some_unshown else "")
