"""Grid maps: rows of ``.`` (free) and ``#``, ``@``, ``T``, ``O`` (blocked), and MovingAI ``.map`` texts.

The format of POGEMA's maps and of the MovingAI benchmark maps::

    ..#.          type octile
    ....          height 2
    .@..          width 4
                  map
                  ..#.
                  ....

A grid map holds no walls between cells, no puddles, starts or exits; the level's outer border
is the wall around it (no border rows needed). ``parse_grid`` returns the size and the blocked
cells; ``Level.from_grid`` builds the level. Errors are ``ValueError`` naming the line and column
(1-based) of the text.
"""

from __future__ import annotations

from .checks import MAX_LEVEL_TEXT_CHARS, check_level_size, shown

FREE = "."
BLOCKED = "#@TO"
GRID_CHARS = FREE + BLOCKED
_NOT_IN_GRIDS = "+|-"  # characters of level texts (corners and walls) that no grid map holds
_HEADER_KEYS = ("type", "height", "width")
_ALLOWED = "allowed: '.' (free), '#', '@', 'T', 'O' (blocked)"


def looks_like_grid_map(spec: str) -> bool:
    """A grid map rather than a level text, a name or a path: no ``+``, ``|`` or ``-``, and its rows
    (blank lines and surrounding spaces aside) hold only ``.``, ``#``, ``@``, ``T`` and ``O``."""
    if any(ch in spec for ch in _NOT_IN_GRIDS) or not spec.strip():
        return False
    rows = spec.replace("\r", "\n").split("\n")
    return all(ch in GRID_CHARS for row in rows for ch in row.strip())


def parse_grid(text: str) -> tuple[int, int, list[tuple[int, int]]]:
    """``(width, height, blocked cells)`` of a grid map or a MovingAI ``.map`` text.

    Blank lines before and after the rows, trailing whitespace and a common indent are dropped;
    every row has the same length. A text whose first line starts with ``type`` is a MovingAI map:
    ``type``, ``height``, ``width`` and ``map`` lines, then the rows.
    """
    if not isinstance(text, str):
        raise TypeError(f"text: expected a grid map (str), got {type(text).__name__}")
    if len(text) > MAX_LEVEL_TEXT_CHARS:  # before splitting it into lines
        raise ValueError(f"text: a grid map has at most {MAX_LEVEL_TEXT_CHARS:,} characters, got {len(text):,}")
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    first = next((i for i, line in enumerate(lines) if line.strip()), None)
    if first is None:
        raise ValueError("text: the grid map is empty")
    size = None
    if lines[first].split(None, 1)[0] == "type":
        size, first = _movingai_header(lines, first)
    filled = [i for i in range(first, len(lines)) if lines[i].strip()]
    if not filled:
        raise ValueError(f"line {first}: the map has no rows")
    first = filled[0]
    rows = [line.rstrip() for line in lines[first : filled[-1] + 1]]
    indent = min(len(row) - len(row.lstrip(" \t")) for row in rows if row)
    rows = [row[indent:] for row in rows]
    width, height = len(rows[0]), len(rows)
    if size is not None and (height, width) != size:
        raise ValueError(f"line {first + 1}: the header says height {size[0]}, width {size[1]}; the map has "
                         f"{height} rows of {width} characters")
    check_level_size(width, height, what="text")  # before looking at the cells
    blocked = []
    for y, row in enumerate(rows):
        line = first + y + 1
        if len(row) != width:
            raise ValueError(f"line {line}, column {min(len(row), width) + indent + 1}: ragged row: {len(row)} "
                             f"characters long, the first row {width}; every row of a grid map has the same length")
        for x, ch in enumerate(row):
            if ch in BLOCKED:
                blocked.append((x, y))
            elif ch != FREE:
                raise ValueError(f"line {line}, column {x + indent + 1}: bad character {ch!r} in a grid map; {_ALLOWED}")
    return width, height, blocked


def _movingai_header(lines: list[str], first: int) -> tuple[tuple[int, int], int]:
    """``((height, width), index of the first map row)`` from the header lines at ``first``."""
    values: dict[str, int] = {}
    i = first
    while i < len(lines) and lines[i].split() != ["map"]:
        words = lines[i].split()
        if words and (len(words) != 2 or words[0] not in _HEADER_KEYS or words[0] in values):
            raise ValueError(f"line {i + 1}: a MovingAI map starts with lines 'type NAME', 'height H', 'width W' "
                             f"and 'map'; got {shown(lines[i], 80)}")
        if words and words[0] != "type" and (not words[1].isdigit() or int(words[1]) < 1):
            raise ValueError(f"line {i + 1}: {words[0]} is an integer >= 1, got {shown(words[1], 40)}")
        if words:
            values[words[0]] = int(words[1]) if words[0] != "type" else 0
        i += 1
    if i == len(lines):
        raise ValueError(f"line {i}: the MovingAI header lacks the line 'map'")
    missing = [k for k in _HEADER_KEYS if k not in values]
    if missing:
        raise ValueError(f"line {i + 1}: the MovingAI header lacks the line {' and '.join(missing)} before 'map'")
    return (values["height"], values["width"]), i + 1
