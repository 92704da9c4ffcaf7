"""TEMPORARY stand-in (helper r25b) for issue 25's levels/files.py: re-exports only. Dropped at merge for r25a's module."""

from ..level_files import load_level, read_level_file

__all__ = ["load_level", "read_level_file"]
