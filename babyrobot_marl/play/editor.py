"""The level editor's state: a level text being drawn, changed by pure functions.

A draft is the level text as a tuple of lines (2H+1 lines of 2W+1 characters, DESIGN.md's format),
valid or not: while a level is being drawn it may well have no exit yet. Every change returns a
new draft; ``verdict`` says what the parser thinks of it. No widget, no browser: the notebook
editor (``play.notebook``) only maps clicks to these functions.

- ``cycle_cell``: floor -> small puddle -> large puddle -> blocked -> start -> exit -> floor. A
  single-robot draft has one start ``S`` (placing it moves it); a race draft numbers its starts
  ``0``, ``1``, ... and renumbers them without gaps when one is removed.
- ``cycle_edge``: open -> wall -> glass wall -> open. The border is always a wall.
- ``resize``: keeps what fits, closes the new border.
"""

from __future__ import annotations

import re

from ..core.level import Cell, Level
from .checks import MAX_SIDE, check_editor_cell, check_editor_size  # noqa: F401  (MAX_SIDE: read as editor.MAX_SIDE)

Draft = tuple[str, ...]
CELL_CYCLE = (" ", "p", "P", "#", "start", "E")  # what a click on a cell turns it into, in turn


def blank(width: int, height: int, race: bool = False) -> Draft:
    """An open grid: the start top left, the exit bottom right (a valid level from the first click)."""
    w, h = check_editor_size(width, height)
    lines = [list(("+-" * w) + "+")]
    for _ in range(h):
        lines.append(list("|" + " " * (2 * w - 1) + "|"))
        lines.append(list(("+ " * w) + "+"))
    lines[-1] = list(("+-" * w) + "+")
    lines[-2][-2] = "E"
    lines[1][1] = "0" if race else "S"
    if w == h == 1:
        lines[1][1] = "E"  # one cell: an exit and no start
    return tuple("".join(line) for line in lines)


def from_level(level: Level | str) -> Draft:
    """The draft of a level (or a level text)."""
    if isinstance(level, str):
        level = Level.from_ascii(level)
    if not isinstance(level, Level):
        raise TypeError(f"level: expected a Level or a level text, got {type(level).__name__}")
    check_editor_size(level.width, level.height)
    return tuple(level.to_ascii().split("\n"))


def size(draft: Draft) -> tuple[int, int]:
    return (len(draft[0]) - 1) // 2, (len(draft) - 1) // 2


def is_race(draft: Draft) -> bool:
    """True when the starts are numbered (a race draft), False for ``S`` or no start."""
    return any(ch.isdigit() for line in draft[1::2] for ch in line[1::2])


def text(draft: Draft) -> str:
    return "\n".join(draft)


def cell_char(draft: Draft, cell: Cell) -> str:
    x, y = cell
    return draft[2 * y + 1][2 * x + 1]


def _set(draft: Draft, slot: tuple[int, int], ch: str) -> Draft:
    i, j = slot
    lines = list(draft)
    lines[i] = lines[i][:j] + ch + lines[i][j + 1 :]
    return tuple(lines)


def _starts(draft: Draft) -> list[tuple[int, Cell]]:
    """(number, cell) of every start; ``S`` counts as 0."""
    out = []
    for y, line in enumerate(draft[1::2]):
        for x, ch in enumerate(line[1::2]):
            if ch == "S" or ch.isdigit():
                out.append((0 if ch == "S" else int(ch), (x, y)))
    return out


def _renumber(draft: Draft) -> Draft:
    """Race starts numbered 0, 1, ... without gaps, keeping their order."""
    for k, (_, cell) in enumerate(sorted(_starts(draft))):
        draft = _set(draft, (2 * cell[1] + 1, 2 * cell[0] + 1), str(k))
    return draft


def cycle_cell(draft: Draft, cell: Cell, race: bool | None = None) -> Draft:
    """The cell turned into the next kind of ``CELL_CYCLE`` (a start: ``S``, or the next number in a race)."""
    w, h = size(draft)
    x, y = check_editor_cell(cell, w, h)
    race = is_race(draft) if race is None else race
    ch = cell_char(draft, (x, y))
    kind = "start" if ch == "S" or ch.isdigit() else " " if ch == "." else ch
    nxt = CELL_CYCLE[(CELL_CYCLE.index(kind) + 1) % len(CELL_CYCLE)] if kind in CELL_CYCLE else " "
    slot = (2 * y + 1, 2 * x + 1)
    if nxt != "start":
        draft = _set(draft, slot, nxt)
        return _renumber(draft) if kind == "start" and race else draft
    if not race:  # one start: it moves here
        for _, c in _starts(draft):
            draft = _set(draft, (2 * c[1] + 1, 2 * c[0] + 1), " ")
        return _set(draft, slot, "S")
    n = len(_starts(draft))
    if n >= 10:  # the text format numbers starts 0..9: the click moves on to the exit
        return _set(draft, slot, "E")
    return _set(draft, slot, str(n))


def cycle_edge(draft: Draft, a: Cell, b: Cell) -> Draft:
    """The edge between neighbours ``a`` and ``b``: open -> wall -> glass wall -> open."""
    w, h = size(draft)
    a, b = sorted((check_editor_cell(a, w, h), check_editor_cell(b, w, h)))
    if abs(a[0] - b[0]) + abs(a[1] - b[1]) != 1:
        raise ValueError(f"edge: {a} and {b} are not neighbours")
    vertical = a[1] == b[1]  # a slot between left and right neighbours
    slot = (2 * a[1] + 1, 2 * a[0] + 2) if vertical else (2 * a[1] + 2, 2 * a[0] + 1)
    wall = "|" if vertical else "-"
    ch = draft[slot[0]][slot[1]]
    nxt = {" ": wall, "*": " "}.get(ch, "*")  # any wall character -> glass
    return _set(draft, slot, nxt)


def resize(draft: Draft, width: int, height: int) -> Draft:
    """A ``width`` x ``height`` draft with what fits of ``draft`` (cells and inner edges), the border closed."""
    w, h = check_editor_size(width, height)
    race = is_race(draft)
    out = [list(line) for line in blank(w, h, race)]
    out[1][1] = " "
    out[-2][-2] = " "
    ow, oh = size(draft)
    for i in range(1, min(2 * h, 2 * oh)):
        for j in range(1, min(2 * w, 2 * ow)):
            out[i][j] = draft[i][j]
    new = tuple("".join(line) for line in out)
    return _renumber(new) if race else new


def with_race(draft: Draft, race: bool) -> Draft:
    """Numbered starts (``race``) or one ``S`` (the start numbered 0 stays; the others become floor)."""
    if race:
        return _renumber(draft)
    for k, cell in _starts(draft):
        draft = _set(draft, (2 * cell[1] + 1, 2 * cell[0] + 1), "S" if k == 0 else " ")
    return draft


def verdict(draft: Draft) -> tuple[Level | None, str, Cell | None]:
    """``(level, message, cell)``: the parsed level and "ok", or None, the parser's ValueError message
    and the cell it points at (None if it names none)."""
    try:
        level = Level.from_ascii(text(draft))
    except ValueError as err:
        return None, str(err), error_cell(str(err))
    starts = len(level.starts)
    what = f"{starts} starts (a race for up to {starts} robots)" if starts > 1 else "1 start" if starts else "no start"
    return level, f"ok: a {level.width}x{level.height} level, {what}, {len(level.exits)} exit(s)", None


def error_cell(message: str) -> Cell | None:
    """The cell (or the cell next to the edge slot) a parser message's ``line L, column C`` points at."""
    m = re.match(r"line (\d+), column (\d+)", message)
    if not m:
        return None
    i, j = int(m[1]) - 1, int(m[2]) - 1
    return (max(j - 1, 0) // 2, max(i - 1, 0) // 2)


def hit(px: float, py: float, cell_size: int, width: int, height: int, margin: float = 0.22) -> tuple | None:
    """What a click at pixel ``(px, py)`` of a grid of ``cell_size`` pixels means: ``("cell", (x, y))``,
    ``("edge", a, b)`` within ``margin`` cells of an inner edge (not at a corner), or None (the
    border, a corner, outside)."""
    u, v = px / cell_size, py / cell_size
    if not (0 <= u < width and 0 <= v < height):
        return None
    x, y = int(u), int(v)
    fu, fv = u - x, v - y
    near_v = min(fu, 1 - fu) < margin  # near a vertical line: the edge to the left or right
    near_h = min(fv, 1 - fv) < margin
    if near_v and near_h:
        return None  # a corner: ambiguous
    if near_v:
        a, b = ((x - 1, y), (x, y)) if fu < 0.5 else ((x, y), (x + 1, y))
        return ("edge", a, b) if a[0] >= 0 and b[0] < width else None
    if near_h:
        a, b = ((x, y - 1), (x, y)) if fv < 0.5 else ((x, y), (x, y + 1))
        return ("edge", a, b) if a[1] >= 0 and b[1] < height else None
    return ("cell", (x, y))


KEY_KINDS = {"e": "E", "s": "start", "b": "#", "#": "#", "p": "p", "P": "P", " ": " ", "f": " ", "Delete": " ", "Backspace": " "}


def set_cell(draft: Draft, cell: Cell, kind: str, race: bool | None = None) -> Draft:
    """The cell turned into ``kind`` (one of ``CELL_CYCLE``: a key pressed on a cell clicked)."""
    if kind not in CELL_CYCLE:
        raise ValueError(f"kind: one of {', '.join(map(repr, CELL_CYCLE))}, got {kind!r}")
    w, h = size(draft)
    x, y = check_editor_cell(cell, w, h)
    ch = cell_char(draft, (x, y))
    now = "start" if ch == "S" or ch.isdigit() else " " if ch == "." else ch
    if now == kind:
        return draft
    slot = (2 * y + 1, 2 * x + 1)
    if now == "start":
        draft = cycle_cell(draft, (x, y), race)  # the start leaves (race starts renumbered)
    if kind == "start":
        return cycle_cell(_set(draft, slot, "#"), (x, y), race)  # the cycle's rules: one S, race starts numbered
    return _set(draft, slot, kind)


def advice(draft: Draft) -> tuple[str, Cell | None]:
    """What a learner reads under the editor, and the cell to outline (None: none): "ok: ..." for a
    level, else what is missing and how to fix it, in the editor's own terms (clicks and keys)."""
    level, message, _ = verdict(draft)
    if level is not None:
        return message, None
    if "missing exit" in message:
        return "the level needs an exit: click a cell, then press E", None
    m = re.search(r"start (\d+) at \((\d+), (\d+)\) cannot reach any exit", message)
    if m:
        k, x, y = int(m[1]), int(m[2]), int(m[3])
        who = f"start {k}" if is_race(draft) else "the start"
        return (f"{who} (column {x}, row {y}) cannot reach an exit: click a wall on the way "
                "until it opens (wall, glass, open)", (x, y))  # fmt: skip
    return re.sub(r"^line \d+, column \d+: ", "", message), error_cell(message)


def moved_start(before: Draft, after: Draft) -> str:
    """What a learner reads when placing a start took the only one from another cell (a
    single-robot draft has one start), else ""."""
    if is_race(after):
        return ""
    was, now = [c for _, c in _starts(before)], [c for _, c in _starts(after)]
    if len(was) != 1 or len(now) != 1 or was == now:
        return ""
    (x, y), (nx, ny) = was[0], now[0]
    return (f"the start moved here (column {nx}, row {ny}) from column {x}, row {y}: a level has one "
            "start (tick race for more)")  # fmt: skip


class Sketch(Level):
    """A draft as drawn, without the checks a level to play must pass (an exit, every start
    reaching one): what the editor shows while a level is being made."""

    def _validate(self) -> None:
        pass


def sketch(draft: Draft) -> Level:
    """The draft's cells and edges as a ``Level`` to draw (a ``Sketch``: not necessarily playable)."""
    w, h = size(draft)
    kinds: dict[str, set] = {"#": set(), "p": set(), "P": set(), "E": set()}
    starts = sorted(_starts(draft))
    for y in range(h):
        for x in range(w):
            ch = cell_char(draft, (x, y))
            if ch in kinds:
                kinds[ch].add((x, y))
    walls, glass = set(), set()
    for i, line in enumerate(draft[1:-1], start=1):
        for j, ch in enumerate(line[1:-1], start=1):
            if (i + j) % 2 == 0 or ch == " ":
                continue  # cells, corners, open edges
            edge = (((j - 2) // 2, i // 2), (j // 2, i // 2)) if i % 2 else ((j // 2, (i - 2) // 2), (j // 2, i // 2))
            (glass if ch == "*" else walls).add(edge)
    return Sketch(width=w, height=h, walls=frozenset(walls), glass=frozenset(glass), blocked=frozenset(kinds["#"]),
                  small_puddles=frozenset(kinds["p"]), large_puddles=frozenset(kinds["P"]),
                  starts=tuple(c for _, c in starts), exits=frozenset(kinds["E"]))  # fmt: skip
