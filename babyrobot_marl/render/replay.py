"""The replay bar under a live canvas: after an episode, a play button and a slider show its steps again.

The canvas keeps the scenes it drew this episode (``LiveCanvas.history``); the slider draws the
one it points at (``LiveCanvas.replay``) on the same canvas, and the play button moves the slider
along in the browser (``jslink``). The env is not stepped again.
"""

from __future__ import annotations

from typing import Any


class ReplayBar:
    """A play button and a slider under the canvas, shown when an episode ends: the slider shows
    the episode's ``index``-th scene (the play button moves it along in the browser)."""

    def __init__(self, canvas: Any):
        from ipywidgets import HTML, HBox, IntSlider, Layout, Play, jslink

        self.canvas = canvas
        interval = int(1000 / canvas.fps) if canvas.fps > 0 else 250
        self.play = Play(min=0, max=0, step=1, interval=interval, description="replay")
        self.slider = IntSlider(min=0, max=0, description="step", continuous_update=True, layout=Layout(width="60%"))
        self.label = HTML("<small>replay of the episode</small>")
        jslink((self.play, "value"), (self.slider, "value"))
        self.slider.observe(self._moved, "value")
        self.widget = HBox([self.play, self.slider, self.label], layout=Layout(display="none"))
        self.widget.add_class("babyrobot-replay")
        self._offering = False

    def offer(self, n: int) -> None:
        """The episode has ended after ``n`` scenes: the bar at its last one, shown."""
        self._offering = True  # setting the range and value draws nothing: the canvas shows the end
        try:
            self.play.max = self.slider.max = n - 1
            self.play.value = self.slider.value = n - 1
        finally:
            self._offering = False
        self.widget.layout.display = "flex"

    def hide(self) -> None:
        self.widget.layout.display = "none"

    def _moved(self, change: dict) -> None:
        if not self._offering and 0 <= change["new"] < len(self.canvas.history):
            self.canvas.replay(change["new"])
