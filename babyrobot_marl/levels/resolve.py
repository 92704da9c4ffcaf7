"""``resolve_level``: a ``Level`` from a built-in name, a level text, a grid map, a ``.map`` file or a
``Level`` (the envs' ``level=``)."""

from __future__ import annotations

from ..core.grid import looks_like_grid_map
from ..core.level import Level, looks_like_level_text
from . import builtin
from .checks import check_has_exit
from .files import read_level_file


def resolve_level(level: str | Level, need_exit: bool = True) -> Level:
    """A ``Level`` from a built-in name, a level text (several lines), a grid map (rows of ``.`` and
    ``#``), the path of a MovingAI ``.map`` file, or a ``Level``; one with an exit (the race's goal)
    unless ``need_exit`` is false (robots with targets of their own, ``goals="own"``)."""
    if isinstance(level, Level):
        out = level
    elif isinstance(level, str):
        out = _from_string(level)
    else:
        raise TypeError(f"level: expected a level name, a level text or a Level, got {type(level).__name__}")
    if need_exit:
        check_has_exit(out)
    return out


def _from_string(spec: str) -> Level:
    if looks_like_grid_map(spec):
        try:
            return Level.from_grid(spec)
        except ValueError as err:
            raise ValueError(f"level: grid map: {err}") from None
    if looks_like_level_text(spec):
        return Level.from_ascii(spec)
    if spec.endswith(".map"):
        return read_level_file(spec)
    return builtin.get(spec)
