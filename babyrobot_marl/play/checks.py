"""The play layer's argument checks: the notebook's keywords, the editor's sizes and cells, a game's robots.

The integer rule is the core's (``core.checks``); the sentences are the play layer's own.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..core.checks import as_int, check_int
from ..core.level import Cell

MAX_SIDE = 64  # the editor's canvas: a bigger level is better typed as text


def check_keywords(function: str, given: dict[str, Any], known: tuple[str, ...]) -> None:
    """``notebook.play`` / ``edit`` keywords: an unknown one is a ``TypeError`` naming the known ones."""
    unknown = [k for k in given if k not in known]
    if unknown:
        raise TypeError(f"{function}() got an unexpected keyword argument {unknown[0]!r}; known: {', '.join(known)}")


def check_editor_size(width: object, height: object) -> tuple[int, int]:
    """The editor's grid: integers in ``1..MAX_SIDE``."""
    message = "{name}: the editor takes an integer in 1..{hi}, got {value}"
    return check_int(width, "width", 1, MAX_SIDE, message=message), check_int(height, "height", 1, MAX_SIDE, message=message)


def check_editor_cell(cell: Sequence[int], w: int, h: int) -> Cell:
    """A cell ``(x, y)`` of integers inside the editor's ``w x h`` grid."""
    try:
        x, y = cell
    except (TypeError, ValueError):
        raise ValueError(f"cell: expected (x, y), got {cell!r}") from None
    xi, yi = as_int(x), as_int(y)
    if xi is None or yi is None:
        raise ValueError(f"cell: expected integers (x, y), got {cell!r}")
    if not (0 <= xi < w and 0 <= yi < h):
        raise ValueError(f"cell: {cell!r} is outside the {w}x{h} grid")
    return (xi, yi)


def check_robots(robots: object) -> int | None:
    """A game's ``robots``: None (the level's starts) or an integer >= 1."""
    if robots is None:
        return None
    return check_int(robots, "robots", 1, message="{name}: must be None (the level's starts) or an integer >= 1, got {value}")
