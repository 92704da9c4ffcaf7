"""TEMPORARY stand-in (helper r25b) for issue 25's levels/sources.py: re-exports only. Dropped at merge for r25a's module."""

from ..level_sources import maze_family

__all__ = ["maze_family"]
