"""The live canvas: the grid drawn in the Jupyter cell with ipycanvas and updated as the episode runs.

A ``MultiCanvas`` of three layers:

0. the level (floor, walls, glass, puddles, labels): the ``rgb_array`` background, sent once
   as lossless RGBA (PNG) so canvas and ``rgb_array`` show the same pixels;
1. the robots, redrawn each step: ``animation_frames`` interpolated frames glide them from
   cell to cell (0: jump), each frame one ``hold_canvas()`` batch;
2. the overlay (values, action values, arrows, text) and the panel below the grid, redrawn
   only when it changes.

``on_client_ready`` redraws everything when a browser (re)connects: a canvas keeps no state
of its own. Needs the ``notebook`` extra (ipycanvas, ipywidgets, orjson); imported lazily.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.level import Cell
from .geometry import ARROWS, TRIANGLE_LABELS, TRIANGLES, scaled
from .overlay import Overlay, format_value, value_colours
from .rgb import RgbRenderer

PANEL_LINE = 18  # pixels per panel line
MAX_ANIMATION_FRAMES = 60


def notebook_available() -> bool:
    """True inside a running IPython kernel (Jupyter) with ipycanvas installed."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    if shell is None or getattr(shell, "kernel", None) is None:
        return False
    try:
        import ipycanvas  # noqa: F401
    except ImportError:
        return False
    return True


def check_animation_frames(n: object) -> int:
    if isinstance(n, bool) or not isinstance(n, int) or not 0 <= n <= MAX_ANIMATION_FRAMES:
        raise ValueError(f"animation_frames: must be an integer in 0..{MAX_ANIMATION_FRAMES} (0: no animation), got {n!r}")
    return n


def _css(colour: Sequence[int]) -> str:
    return f"rgb({int(colour[0])}, {int(colour[1])}, {int(colour[2])})"


class LiveCanvas:
    """Draws one env's level, robots and overlay on an ipycanvas ``MultiCanvas`` (``widget``).

    ``fps``: steps per second when animating (``env.metadata["render_fps"]`` by default);
    ``animation_frames``: frames per step (0: robots jump to their new cells).
    """

    def __init__(self, renderer: RgbRenderer, animation_frames: int = 4, fps: float = 4.0):
        from ipycanvas import MultiCanvas

        self.renderer = renderer
        self.animation_frames = check_animation_frames(animation_frames)
        self.fps = float(fps)
        h, w = renderer.shape[:2]
        self.grid_height, self.width = h, w
        self.widget = MultiCanvas(3, width=w, height=h)
        self.robots: list[Cell | None] = []
        self.overlay = Overlay()
        self.frames_sent = 0  # hold_canvas batches sent (tests, benchmarks)
        self.widget.on_client_ready(self.redraw)
        self._draw_level()

    # ------------------------------------------------------------------ public
    def show(self) -> None:
        """Display the canvas in the current notebook cell."""
        from IPython.display import display

        display(self.widget)

    def draw(self, robots: Sequence[Cell | None], overlay: Overlay | None = None, animate: bool = True) -> None:
        """Move the robots to ``robots`` (gliding from where they were, unless ``animate`` is
        False or this is the first draw), and redraw the overlay if it changed."""
        if overlay is not None and overlay is not self.overlay:
            self.overlay = overlay
            self._draw_overlay()
        start, end = self.robots, list(robots)
        self.robots = end
        steps = self.animation_frames if animate and len(start) == len(end) else 0
        if steps == 0:
            self._draw_robots(end)
            return
        pause = 1.0 / (self.fps * steps) if self.fps > 0 else 0.0
        for k in range(1, steps + 1):
            t = k / steps
            self._draw_robots([_between(a, b, t) for a, b in zip(start, end)])
            if k < steps and pause:
                time.sleep(pause)

    def redraw(self, *_: Any) -> None:
        """Everything again (a browser connected: it starts from an empty canvas)."""
        self._draw_level()
        self._draw_overlay()
        self._draw_robots(self.robots)

    # ------------------------------------------------------------------ layers
    def _hold(self) -> Any:
        from ipycanvas import hold_canvas

        self.frames_sent += 1
        return hold_canvas()

    def _draw_level(self) -> None:
        bg = self.renderer.background
        rgba = np.concatenate([bg, np.full(bg.shape[:2] + (1,), 255, dtype=np.uint8)], axis=2)  # RGBA: sent as PNG
        with self._hold():
            self.widget[0].clear()
            self.widget[0].put_image_data(rgba, 0, 0)

    def _draw_robots(self, robots: Sequence[tuple[float, float] | None]) -> None:
        cs, colours = self.renderer.cell_size, self.renderer.theme.robots
        layer = self.widget[1]
        with self._hold():
            layer.clear()
            for i in reversed(range(len(robots))):  # robot 0 on top, as in rgb_array
                cell = robots[i]
                if cell is None:
                    continue
                layer.fill_style = _css(colours[i % len(colours)])
                layer.fill_circle(float((cell[0] + 0.5) * cs), float((cell[1] + 0.5) * cs), float(0.34 * cs))

    def _draw_overlay(self) -> None:
        ov, r = self.overlay, self.renderer
        cs, th = r.cell_size, r.theme
        height = self.grid_height + (len(ov.panel) * PANEL_LINE + 6 if ov.panel else 0)
        if height != self.widget.height:
            self.widget.height = height  # resizing clears every layer
            self._draw_level()
            self._draw_robots(self.robots)
        layer = self.widget[2]
        with self._hold():
            layer.clear()
            layer.global_alpha = 0.65
            if ov.values is not None:
                colours = value_colours(ov.values, th.value_low, th.value_high)
                for y, x in zip(*np.nonzero(np.isfinite(ov.values))):
                    layer.fill_style = _css(colours[y, x])
                    layer.fill_rect(float(x * cs), float(y * cs), float(cs), float(cs))
            if ov.q_values is not None:
                colours = value_colours(ov.q_values[:, :, 1:], th.value_low, th.value_high)
                for action, polygon in TRIANGLES.items():
                    for y, x in zip(*np.nonzero(np.isfinite(ov.q_values[:, :, action]))):
                        layer.fill_style = _css(colours[y, x, action - 1])
                        layer.fill_polygon(scaled(polygon, int(x), int(y), cs))
            layer.global_alpha = 1.0
            if ov.arrows is not None:
                layer.fill_style = _css(th.arrow)
                for action, polygon in ARROWS.items():
                    for y, x in zip(*np.nonzero(ov.arrows[:, :, action])):
                        layer.fill_polygon(scaled(polygon, int(x), int(y), cs))
            layer.fill_style = _css(th.text)
            layer.font = f"{max(9, cs // 4)}px sans-serif"
            layer.text_align, layer.text_baseline = "center", "middle"
            if ov.values is not None:
                for y, x in zip(*np.nonzero(np.isfinite(ov.values))):
                    layer.fill_text(format_value(float(ov.values[y, x])), float((x + 0.5) * cs), float((y + 0.8) * cs))
            if ov.q_values is not None and cs >= 48:  # the numbers fit in the triangles
                for action, (u, v) in TRIANGLE_LABELS.items():
                    for y, x in zip(*np.nonzero(np.isfinite(ov.q_values[:, :, action]))):
                        q = float(ov.q_values[y, x, action])
                        layer.fill_text(format_value(q), float((x + u) * cs), float((y + v) * cs))
            for (x, y), text in ov.text.items():
                layer.fill_text(text, float((x + 0.5) * cs), float((y + 0.2) * cs))
            if ov.panel:
                layer.fill_style = _css(th.panel)
                layer.fill_rect(0.0, float(self.grid_height), float(self.width), float(height - self.grid_height))
                layer.fill_style = _css(th.text)
                layer.font = "14px monospace"
                layer.text_align, layer.text_baseline = "left", "top"
                for k, line in enumerate(ov.panel):
                    layer.fill_text(line, 6.0, float(self.grid_height + 4 + k * PANEL_LINE))


def _between(a: Cell | None, b: Cell | None, t: float) -> tuple[float, float] | None:
    """The point a fraction ``t`` of the way from cell ``a`` to cell ``b`` (None: off the board)."""
    if b is None:
        return None if t >= 1.0 or a is None else (float(a[0]), float(a[1]))
    if a is None:
        return (float(b[0]), float(b[1]))
    return (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t)
