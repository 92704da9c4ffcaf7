"""What an env draws, as a part the env holds (``env.drawing``): the overlay, the live canvas and the
``rgb_array`` renderer; and ``OverlayMethods``, the env's public drawing methods, each one line that
calls the part.

``EnvDrawing`` holds all the drawing state; the env's own state stays in the env, and what its last
step looks like comes from ``scenes.py`` (``env._scene()``). ``"human"`` mode: a live canvas in
Jupyter (when ipycanvas is installed), the text frame printed anywhere else.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..core.level import Level
from ..render.checks import check_overlay_frame
from ..render.overlay import KEEP, Overlay, update_overlay
from ..render.palette import Theme
from ..render.rgb import RgbRenderer
from ..render.scene import Scene


class EnvDrawing:
    """The drawing part of an env: one level at one cell size and theme, its overlay, its live
    canvas (None until shown) and its renderer (made on first use: large levels make large images).
    ``robots``: the legend's rows (a race's robots; 0: no legend); ``fit``: the live canvas fills
    the notebook column (the env was given no ``cell_size``)."""

    def __init__(self, level: Level, cell_size: int | None, theme: Theme, animation_frames: int, robots: int = 0,
                 fit: bool = False) -> None:  # fmt: skip
        self.level, self.cell_size, self.theme = level, cell_size, theme
        self.animation_frames, self.robots, self.fit = animation_frames, robots, fit
        self.overlay = Overlay()
        self.canvas: Any = None  # render.canvas.LiveCanvas once shown
        self._renderer: RgbRenderer | None = None

    @property
    def renderer(self) -> RgbRenderer:
        if self._renderer is None:
            self._renderer = RgbRenderer(self.level, self.cell_size, self.theme)
        return self._renderer

    def set_overlay(self, render_mode: str | None, scene: Callable[[], Scene], **parts: Any) -> None:
        """Update the overlay's ``parts`` (checked, and the frame within the limit, before anything
        changes) and redraw the live canvas, if any, with ``scene()``."""
        overlay = update_overlay(self.overlay, self.level, **parts, n_robots=max(self.robots, 1))
        if render_mode in ("rgb_array", "human"):  # its frames within the limit, legend and all
            check_overlay_frame(self.level, self.cell_size, overlay, self.robots)  # type: ignore[arg-type]
        self.overlay = overlay
        if self.canvas is not None:
            self.canvas.set_overlay(overlay, scene())

    def frame(self, scene: Scene) -> np.ndarray:
        """The ``rgb_array`` frame of ``scene`` under the overlay."""
        return self.renderer.frame(scene, self.overlay)

    def show(self, scene: Callable[[], Scene], text_frame: Callable[[], str], animate: bool, fps: float) -> None:
        """The live canvas in a notebook (made and shown on first use, its first frame drawn before it
        is shown), else the text frame printed. A frame drawn without ``animate`` starts an episode."""
        if self.canvas is None:
            from ..render.canvas import LiveCanvas, notebook_available

            if notebook_available():
                self.canvas = LiveCanvas(self.renderer, self.animation_frames, fps, fit=self.fit)
                self.canvas.draw(scene(), self.overlay, animate=False)
                self.canvas.show()
                return
        if self.canvas is not None:
            if not animate:
                self.canvas.new_episode()
            self.canvas.draw(scene(), self.overlay, animate=animate)
        else:
            print(text_frame(), flush=True)

    def new_level(self, level: Level) -> None:
        """Draw ``level`` from now on (a race's level drawn at reset): a new renderer, a new canvas."""
        self.level, self._renderer = level, None
        if self.canvas is not None:  # a live canvas shows one level: a new one for this
            self.close()
            self.canvas = None

    def close(self) -> None:
        """Refresh the canvas's saved picture (the output's PNG); nothing else to release."""
        if self.canvas is not None:
            self.canvas.snapshot()

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["canvas"] = None  # a widget lives in one kernel; a copy draws on a new canvas
        return state


class OverlayMethods:
    """The envs' drawing methods, stateless: each calls the env's ``drawing`` part (an ``EnvDrawing``)."""

    drawing: EnvDrawing
    render_mode: str | None

    def set_overlay(
        self,
        values: Any = KEEP,
        q_values: Any = KEEP,
        arrows: Any = KEEP,
        text: Any = KEEP,
        panel: Any = KEEP,
        names: Any = KEEP,
    ) -> None:
        """Draw values, action values, policy arrows, cell text, a text panel or (a race) the
        robots' names in the legend over the grid (``rgb_array`` frames and the live canvas);
        see ``babyrobot_marl.render.overlay``.

        Parts not given are kept; ``None`` clears a part. Checked before anything changes.
        """
        parts = {"values": values, "q_values": q_values, "arrows": arrows, "text": text, "panel": panel, "names": names}
        self.drawing.set_overlay(self.render_mode, self._scene, **parts)

    def clear_overlay(self) -> None:
        """Remove every overlay."""
        self.set_overlay(values=None, q_values=None, arrows=None, text=None, panel=None, names=None)

    @property
    def overlay(self) -> Overlay:
        return self.drawing.overlay

    @property
    def canvas(self) -> Any:
        """The live canvas (``render.canvas.LiveCanvas``) once shown in ``"human"`` mode, else None."""
        return self.drawing.canvas

    @property
    def rgb_renderer(self) -> RgbRenderer:
        """Draws this level (made on first use: large levels make large images)."""
        return self.drawing.renderer

    def close(self) -> None:
        """Release nothing but refresh the canvas's saved picture (the output's PNG)."""
        self.drawing.close()

    def _scene(self) -> Scene:
        raise NotImplementedError
