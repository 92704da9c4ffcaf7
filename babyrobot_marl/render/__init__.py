"""Rendering: text frames (``ansi``) and numpy images (``rgb_array``) of the same state."""

from .ansi import frame, robot_glyph
from .rgb import THEMES, RgbRenderer, Theme

__all__ = ["THEMES", "RgbRenderer", "Theme", "frame", "robot_glyph"]
