"""TEMPORARY stand-in (helper r25b) for issue 25's play/screen.py: re-exports only. Dropped at merge for r25a's module."""

from ..animation import DEFAULT_DELAY, Display, animate, isatty

__all__ = ["DEFAULT_DELAY", "Display", "animate", "isatty"]
