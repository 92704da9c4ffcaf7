"""TEMPORARY stand-in (helper r25b) for issue 25's core/checks.py: re-exports only. Dropped at merge for r25a's module."""

from ..checks import MAX_LEVEL_CELLS, MAX_LEVEL_TEXT_CHARS, check_batch, check_int, check_real, shown

__all__ = ["MAX_LEVEL_CELLS", "MAX_LEVEL_TEXT_CHARS", "check_batch", "check_int", "check_real", "shown"]
