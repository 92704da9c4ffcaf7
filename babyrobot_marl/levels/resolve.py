"""``resolve_level``: a ``Level`` from a built-in name, a level text or a ``Level`` (the envs' ``level=``)."""

from __future__ import annotations

from ..core.level import Level, looks_like_level_text
from . import builtin


def resolve_level(level: str | Level) -> Level:
    """A ``Level`` from a built-in name, a level text (several lines) or a ``Level``."""
    if isinstance(level, Level):
        return level
    if isinstance(level, str):
        return Level.from_ascii(level) if looks_like_level_text(level) else builtin.get(level)
    raise TypeError(f"level: expected a level name, a level text or a Level, got {type(level).__name__}")
