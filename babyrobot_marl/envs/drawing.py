"""Overlays and the live canvas, shared by the single-robot env and the race (a mixin)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..core.level import Cell
from ..render.overlay import KEEP, Overlay, update_overlay


class Drawing:
    """``set_overlay`` / ``clear_overlay`` and the ``"human"`` mode: a live canvas in Jupyter
    (when ipycanvas is installed), the text frame printed anywhere else."""

    animation_frames: int
    canvas: Any  # render.canvas.LiveCanvas once shown, else None
    _overlay: Overlay

    def set_overlay(
        self, values: Any = KEEP, q_values: Any = KEEP, arrows: Any = KEEP, text: Any = KEEP, panel: Any = KEEP
    ) -> None:
        """Draw values, action values, policy arrows, cell text or a text panel over the grid
        (``rgb_array`` frames and the live canvas); see ``babyrobot_marl.render.overlay``.

        Parts not given are kept; ``None`` clears a part. Checked before anything changes.
        """
        self._overlay = update_overlay(self._overlay, self.level, values, q_values, arrows, text, panel)  # type: ignore[attr-defined]
        if self.canvas is not None:
            self.canvas.set_overlay(self._overlay)

    def clear_overlay(self) -> None:
        """Remove every overlay."""
        self.set_overlay(values=None, q_values=None, arrows=None, text=None, panel=None)

    @property
    def overlay(self) -> Overlay:
        return self._overlay

    def _overlay_frame(self, robots: Sequence[Cell | None]) -> np.ndarray:
        return self.rgb_renderer.frame(robots, self._overlay)  # type: ignore[attr-defined]

    def _show_human(self, robots: Sequence[Cell | None], text_frame: Callable[[], str], animate: bool) -> None:
        """The live canvas in a notebook (made and shown on first use), else the text frame."""
        if self.canvas is None:
            from ..render.canvas import LiveCanvas, notebook_available

            if notebook_available():
                self.canvas = LiveCanvas(self.rgb_renderer, self.animation_frames, self.metadata["render_fps"])  # type: ignore[attr-defined]
                self.canvas.show()
        if self.canvas is not None:
            self.canvas.draw(robots, self._overlay, animate=animate)
        else:
            print(text_frame(), flush=True)

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["canvas"] = None  # a widget lives in one kernel; a copy draws on a new canvas
        return state
