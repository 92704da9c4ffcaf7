"""Rendering: text frames (``ansi``), numpy images (``rgb_array``) with overlays, the live
ipycanvas canvas (``canvas``, needs the ``notebook`` extra) and GIF/MP4 saving (``video``,
needs the ``video`` extra); the optional parts are imported only when used."""

from .ansi import frame, robot_glyph
from .overlay import Overlay
from .rgb import THEMES, RgbRenderer, Theme

__all__ = ["THEMES", "Overlay", "RgbRenderer", "Theme", "frame", "robot_glyph"]
