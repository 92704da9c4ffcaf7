"""The levels' argument checks: maze sizes and seeds, and level files (regular, bounded files only).

The integer rule is the core's (``core.checks.check_int``); the sentences are the levels' own.
"""

from __future__ import annotations

import os
import stat

from ..core.checks import MAX_LEVEL_TEXT_CHARS, check_int, shown

MAX_MAZE_SIDE = 256  # a 256x256 maze is the largest level (core.checks.MAX_LEVEL_CELLS)
PATH_SHOWN = 300  # characters of a path an error message shows


def check_maze_size(value: object, name: str) -> int:
    """A maze side (``width`` or ``height``): an integer in ``1..MAX_MAZE_SIDE``."""
    return check_int(value, name, 1, MAX_MAZE_SIDE, message="{name}: a maze side is an integer in 1..{hi}, got {shown}")


FAMILY_FORM = (
    "'maze:A..B' (square mazes, the side drawn from A..B, 2 <= A <= B <= 256; e.g. 'maze:8..16', one size 'maze:16..16') "
    "or 'gridmaze:A..B' (grid mazes with loops and no exit, for own goals; e.g. 'gridmaze:17..21')"
)


def check_family_sides(low: object, high: object) -> tuple[int, int]:
    """The sides of a family of square mazes ``maze:A..B`` or ``gridmaze:A..B``: integers with ``2 <= A <= B <= MAX_MAZE_SIDE``
    (a 1x1 maze has no room for a start and an exit)."""
    try:
        a = check_int(low, "level", 2, MAX_MAZE_SIDE)
        b = check_int(high, "level", a, MAX_MAZE_SIDE)
    except ValueError:
        raise ValueError(f"level: a level family is {FAMILY_FORM}, got sides {shown(low)}..{shown(high)}") from None
    return a, b


def bad_family(spec: str) -> str:
    """The error line of a malformed family spec (``maze:...``)."""
    return f"level: a level family is {FAMILY_FORM}, got {shown(spec)}"


def check_maze_seed(value: object) -> int:
    """A maze seed: an integer >= 0."""
    return check_int(value, "seed", 0, message="{name}: a maze seed is an integer >= 0, got {shown}")


NO_EXIT = "level: has no exit; use goals='own'"  # a grid map's level in the race to an exit


def check_has_exit(level: object) -> None:
    """A level for the race to an exit (``goals="exit"``) has at least one exit: a grid map has none."""
    if not getattr(level, "exits", None):
        raise ValueError(NO_EXIT)


def check_regular_file(spec: str, info: os.stat_result) -> None:
    """``spec`` (stat ``info``) is a regular file within ``MAX_LEVEL_TEXT_CHARS`` bytes: not a
    directory, a FIFO that would block or a device that never ends."""
    if stat.S_ISDIR(info.st_mode):
        raise ValueError(cannot_read(spec, "it is a directory"))
    if not stat.S_ISREG(info.st_mode):
        mode = info.st_mode
        device = stat.S_ISCHR(mode) or stat.S_ISBLK(mode)
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a device" if device else "not a regular file"
        raise ValueError(cannot_read(spec, f"it is {kind}; a level file is a regular text file"))
    if info.st_size > MAX_LEVEL_TEXT_CHARS:
        raise ValueError(too_large(spec, info.st_size))


def too_large(spec: str, size: int | None = None) -> str:
    """The error line of a level file over ``MAX_LEVEL_TEXT_CHARS`` bytes."""
    got = f" ({size:,} bytes)" if size is not None else ""
    return cannot_read(
        spec,
        f"it is too large{got}; a level file has at most {MAX_LEVEL_TEXT_CHARS:,} bytes "
        "(the largest level, 65,536 cells, takes under 700 kB)",
    )


def cannot_read(spec: str, reason: str) -> str:
    """The error line of a level file that cannot be read, and why."""
    return f"level: cannot read the level file {shown(spec, PATH_SHOWN)}: {reason}"
