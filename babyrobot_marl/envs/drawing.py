"""Overlays, scenes and the live canvas, shared by the single-robot env and the race (mixins).

An env records its last step (``_last_step``); ``_scene()`` turns that into what the
renderers draw (``render.scene.Scene``): each robot's cell, heading and pose, the marks of
collisions, and for a race the legend.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..core.engine import BUMPED, MOVED, move
from ..core.rng import SLOTS
from ..render.checks import check_overlay_frame
from ..render.overlay import KEEP, Overlay, update_overlay
from ..render.panel import LegendRow
from ..render.scene import POSE_OF_OUTCOME, RobotView, Scene


class Drawing:
    """``set_overlay`` / ``clear_overlay`` and the ``"human"`` mode: a live canvas in Jupyter
    (when ipycanvas is installed), the text frame printed anywhere else."""

    animation_frames: int
    canvas: Any  # render.canvas.LiveCanvas once shown, else None
    _overlay: Overlay

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
        n = getattr(self, "n_robots", 1)
        overlay = update_overlay(self._overlay, self.level, values, q_values, arrows, text, panel, names, n)  # type: ignore[attr-defined]
        if getattr(self, "render_mode", None) in ("rgb_array", "human"):  # its frames within the limit, legend and all
            check_overlay_frame(self.level, self.cell_size, overlay, n if isinstance(self, RaceDrawing) else 0)  # type: ignore[attr-defined]
        self._overlay = overlay
        if self.canvas is not None:
            self.canvas.set_overlay(self._overlay, self._scene())

    def clear_overlay(self) -> None:
        """Remove every overlay."""
        self.set_overlay(values=None, q_values=None, arrows=None, text=None, panel=None, names=None)

    @property
    def overlay(self) -> Overlay:
        return self._overlay

    def _scene(self) -> Scene:
        raise NotImplementedError

    def _overlay_frame(self) -> np.ndarray:
        return self.rgb_renderer.frame(self._scene(), self._overlay)  # type: ignore[attr-defined]

    def _show_human(self, text_frame: Callable[[], str], animate: bool) -> None:
        """The live canvas in a notebook (made and shown on first use), else the text frame."""
        if self.canvas is None:
            from ..render.canvas import LiveCanvas, notebook_available

            if notebook_available():
                self.canvas = LiveCanvas(self.rgb_renderer, self.animation_frames, self.metadata["render_fps"])  # type: ignore[attr-defined]
                self.canvas.draw(self._scene(), self._overlay, animate=False)
                self.canvas.show()
                return
        if self.canvas is not None:
            self.canvas.draw(self._scene(), self._overlay, animate=animate)
        else:
            print(text_frame(), flush=True)

    def _close_canvas(self) -> None:
        if self.canvas is not None:
            self.canvas.snapshot()

    def close(self) -> None:
        """Release nothing but refresh the canvas's saved picture (the output's PNG)."""
        self._close_canvas()

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["canvas"] = None  # a widget lives in one kernel; a copy draws on a new canvas
        return state


class SingleDrawing(Drawing):
    """The single-robot env's scene: the robot, turned and posed by its last step."""

    def _scene(self) -> Scene:
        env: Any = self
        if env._cell < 0:
            return Scene()
        cell = env._xy[env._cell]
        last = env._last_step
        if last is None:
            return Scene((RobotView(0, cell, numbered=False),), done=env._done)
        prev, action, outcome = last
        finished = bool(env._lists.is_exit[env._cell])
        pose = "finished" if finished else ("idle" if outcome == MOVED and action == 0 else POSE_OF_OUTCOME[outcome])
        view = RobotView(0, cell, action, pose, env._xy[prev], numbered=False)
        return Scene((view,), done=env._done)


class RaceDrawing(Drawing):
    """The race's scene: racing robots posed by their last step, finished robots at their exits
    with their ranks, bursts where robots stopped each other, and the legend."""

    def _scene(self) -> Scene:
        env: Any = self
        if not env._rank:  # before the first reset
            return Scene()
        xy, cells, racing, n = env._xy, env._cells, env._racing, env.n_robots
        heading, pose, came, marks = [0] * n, ["idle"] * n, [None] * n, []
        if env._last_step is not None:
            live, prev, acts, outcome, blocked, finishing, t = env._last_step
            for k, i in enumerate(live):
                heading[i], came[i] = acts[k], xy[prev[k]]
                if finishing[k]:
                    pose[i] = "finished"
                elif blocked[k]:
                    pose[i] = "bumped"
                    want = _desired(env._lists, prev[k], acts[k], env._key, t * n * SLOTS + i * SLOTS)
                    marks.append((xy[prev[k]], xy[want]))
                else:
                    o = outcome[k]
                    pose[i] = "idle" if o == MOVED and acts[k] == 0 else POSE_OF_OUTCOME[o]
        views = []
        for i in range(n):
            if not racing[i]:
                pose[i] = "finished"
            views.append(RobotView(i, xy[cells[i]], heading[i], pose[i], came[i], env._rank[i]))
        live_returns = dict(zip(env._live, env._live_returns))
        names = self._overlay.names
        legend = tuple(
            LegendRow(i, names.get(i, ""), live_returns.get(i, env._returns[i]), env._rank[i], racing[i]) for i in range(n)
        )
        return Scene(tuple(views), tuple(marks), legend, done=not env.agents)


def _desired(lists: Any, cell: int, action: int, key: int, counter: int) -> int:
    """Where a robot's move would have taken it before the collision rules (the same draw as the step)."""
    sure = lists.sure[cell][action]
    if sure is not None:
        return sure[0]
    to, outcome = move(lists, cell, action, key, counter)
    return to if outcome != BUMPED else cell
