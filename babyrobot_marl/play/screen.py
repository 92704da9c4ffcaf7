"""TEMPORARY stand-in (helper r25b) for issue 25's play/screen.py: re-exports only. Dropped at merge for r25a's module."""

from ..animation import CURSOR_HOME, DEFAULT_DELAY, SHOW_CURSOR, Display, animate, isatty

__all__ = ["CURSOR_HOME", "DEFAULT_DELAY", "SHOW_CURSOR", "Display", "animate", "isatty"]
