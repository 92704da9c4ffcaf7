"""The live canvas: the grid drawn in the Jupyter cell with ipycanvas and updated as the episode runs.

A ``MultiCanvas`` of three layers:

0. the level (floor, walls, glass, puddles, labels) with the overlay's value tints: the
   ``rgb_array`` image (``RgbRenderer.tinted``), sent as lossless RGBA (PNG; RGB would go as
   lossy JPEG) so canvas and ``rgb_array`` show the same pixels; sent once, and again only
   when the values change;
1. the robots, redrawn each step: ``animation_frames`` interpolated frames glide them from
   cell to cell (0: jump), each frame one ``hold_canvas()`` batch, paced at ``fps`` steps
   per second;
2. the overlay's ink (arrows, numbers, text) over the robots, and the panel below the grid,
   redrawn only when it changes.

As in ``rgb_array``: tints under the robots, arrows and text over them, one shared geometry
(``render.geometry``). Every number sent is a Python number (without ``orjson`` ipycanvas
cannot serialise numpy scalars).

``on_client_ready`` redraws everything when a browser (re)connects: a canvas keeps no state
of its own. Needs the ``notebook`` extra (ipycanvas, ipywidgets, orjson); imported lazily.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..checks import check_int
from ..core.level import Cell
from .geometry import ARROWS, CELL_TEXT_CENTRE, ROBOT_RADIUS, TRIANGLE_LABELS, VALUE_TEXT_CENTRE, scaled
from .overlay import Overlay, format_value
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
    return check_int(n, "animation_frames", 0, MAX_ANIMATION_FRAMES)  # numpy integers too


def check_fps(fps: object, name: str = "render_fps") -> float:
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not 0 <= fps < float("inf"):
        raise ValueError(f"{name}: must be a finite number >= 0 (steps per second; 0: no pacing), got {fps!r}")
    return float(fps)


def _css(colour: Sequence[int]) -> str:
    return f"rgb({int(colour[0])}, {int(colour[1])}, {int(colour[2])})"


class LiveCanvas:
    """Draws one env's level, robots and overlay on an ipycanvas ``MultiCanvas`` (``widget``).

    ``fps``: steps per second (``env.metadata["render_fps"]``; 0: as fast as drawn), frames
    are sent at most ``fps * max(1, animation_frames)`` a second, measured from the frame
    before, so the time a program spends between steps is not added to it;
    ``animation_frames``: frames per step (0: robots jump to their new cells).
    """

    def __init__(self, renderer: RgbRenderer, animation_frames: int = 4, fps: float = 4.0):
        from ipycanvas import MultiCanvas

        self.renderer = renderer
        self.animation_frames = check_animation_frames(animation_frames)
        self.fps = check_fps(fps, "fps")
        h, w = renderer.shape[:2]
        self.grid_height, self.width = h, w
        self.widget = MultiCanvas(3, width=w, height=h)
        self.robots: list[Cell | None] = []
        self.overlay = Overlay()
        self.frames_sent = 0  # hold_canvas batches sent (tests, benchmarks)
        self._level_image: np.ndarray | None = None  # what layer 0 shows
        self._due = 0.0  # time.monotonic() at which the next robot frame may be sent
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
        if overlay is not None:
            self.set_overlay(overlay)
        start, end = self.robots, list(robots)
        self.robots = end
        steps = self.animation_frames if animate and len(start) == len(end) else 0
        if steps == 0:
            self._pace(1.0 / self.fps if animate and self.fps > 0 else 0.0)
            self._draw_robots(end)
            return
        for k in range(1, steps + 1):
            self._pace(1.0 / (self.fps * steps) if self.fps > 0 else 0.0)
            self._draw_robots([_between(a, b, k / steps) for a, b in zip(start, end)])

    def set_overlay(self, overlay: Overlay) -> None:
        """Show ``overlay``: the level layer again if its tints changed, the ink layer if anything did."""
        if overlay is self.overlay:
            return
        self.overlay = overlay
        height = self.grid_height + (len(overlay.panel) * PANEL_LINE + 6 if overlay.panel else 0)
        if height != self.widget.height:
            self.widget.height = height  # resizing clears every layer
            self._draw_level()
            self._draw_robots(self.robots)
        elif self.renderer.tinted(overlay) is not self._level_image:
            self._draw_level()
        self._draw_overlay()

    def redraw(self, *_: Any) -> None:
        """Everything again (a browser connected: it starts from an empty canvas)."""
        self._draw_level()
        self._draw_overlay()
        self._draw_robots(self.robots)

    # ------------------------------------------------------------------ layers
    def _pace(self, interval: float) -> None:
        """Wait until the next frame is due, then set the one after ``interval`` seconds later."""
        now = time.monotonic()
        if now < self._due:
            time.sleep(self._due - now)
            now = self._due
        self._due = now + interval

    def _hold(self) -> Any:
        from ipycanvas import hold_canvas

        self.frames_sent += 1
        return hold_canvas()

    def _draw_level(self) -> None:
        bg = self._level_image = self.renderer.tinted(self.overlay)
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
                layer.fill_circle(float((cell[0] + 0.5) * cs), float((cell[1] + 0.5) * cs), float(ROBOT_RADIUS * cs))

    def _draw_overlay(self) -> None:
        ov, r = self.overlay, self.renderer
        cs, th = r.cell_size, r.theme
        layer = self.widget[2]
        with self._hold():
            layer.clear()
            if ov.arrows is not None:
                layer.fill_style = _css(th.arrow)
                for action, polygon in ARROWS.items():
                    for y, x in zip(*np.nonzero(ov.arrows[:, :, action])):
                        layer.fill_polygon(scaled(polygon, int(x), int(y), cs))
            layer.fill_style = _css(th.text)
            layer.font = f"{max(9, cs // 4)}px sans-serif"
            layer.text_align, layer.text_baseline = "center", "middle"
            u, v = VALUE_TEXT_CENTRE
            if ov.values is not None:
                for y, x in zip(*np.nonzero(np.isfinite(ov.values))):
                    layer.fill_text(format_value(float(ov.values[y, x])), float((x + u) * cs), float((y + v) * cs))
            if ov.q_values is not None and cs >= 48:  # the numbers fit in the triangles
                for action, (u, v) in TRIANGLE_LABELS.items():
                    for y, x in zip(*np.nonzero(np.isfinite(ov.q_values[:, :, action]))):
                        q = float(ov.q_values[y, x, action])
                        layer.fill_text(format_value(q), float((x + u) * cs), float((y + v) * cs))
            u, v = CELL_TEXT_CENTRE
            for (x, y), text in ov.text.items():
                layer.fill_text(text, float((x + u) * cs), float((y + v) * cs))
            if ov.panel:
                layer.fill_style = _css(th.panel)
                layer.fill_rect(0.0, float(self.grid_height), float(self.width), float(self.widget.height - self.grid_height))
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
