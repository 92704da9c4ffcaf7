"""Rendering: text frames now; rgb_array and the live notebook canvas build on the same state."""

from .ansi import frame, robot_glyph

__all__ = ["frame", "robot_glyph"]
