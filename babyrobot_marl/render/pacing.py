"""The live canvas's clock: robot frames sent on time, in-between frames dropped when late.

A step glides in ``animation_frames`` frames at ``fps`` steps a second. A slow browser or a busy
machine makes sending a frame take longer than its share: the frames still due are then dropped
(never a step's last one), so the picture keeps to the clock instead of falling behind it.
Time the program spends between steps is not caught up: each step's frames start when it does.
"""

from __future__ import annotations

import time


class Pacer:
    """When the next robot frame is due (``time.monotonic()``), and how many were dropped."""

    def __init__(self) -> None:
        self.due = 0.0
        self.dropped = 0

    def start_step(self) -> None:
        """A step's frames from now on (the time since the last one, the program's, is not caught up)."""
        self.due = max(self.due, time.monotonic())

    def late(self, interval: float) -> bool:
        """Behind the clock by a whole frame: the frame due is dropped, the clock moves to the next."""
        if interval > 0 and time.monotonic() >= self.due + interval:
            self.due += interval
            self.dropped += 1
            return True
        return False

    def wait(self, interval: float) -> None:
        """Wait until the next frame is due, then set the one after ``interval`` seconds later."""
        now = time.monotonic()
        if now < self.due:
            time.sleep(self.due - now)
            now = self.due
        self.due = now + interval
