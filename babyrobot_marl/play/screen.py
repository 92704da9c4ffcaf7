"""Text frames on a screen: redrawn in place on a terminal, one after another in a file.

``animate(frames, display, out)`` is what ``babyrobot-marl play`` and ``race`` use; ``Display``
says how (colour, clearing, pause). ANSI control sequences are written only to a terminal.
``draw(out, text)`` redraws one frame in place (the terminal game and ``watch_race``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TextIO

DEFAULT_DELAY = 0.15  # seconds between frames on a terminal: fast, yet each move is visible

CLEAR_SCREEN = "\x1b[2J"
CURSOR_HOME = "\x1b[H"
CLEAR_TO_EOL = "\x1b[K"
CLEAR_BELOW = "\x1b[J"
HIDE_CURSOR = "\x1b[?25l"
SHOW_CURSOR = "\x1b[?25h"


@dataclass(frozen=True)
class Display:
    """How frames reach the terminal: colour, clearing between frames, pause between frames."""

    colour: bool
    clear: bool
    delay: float


def isatty(out: TextIO) -> bool:
    try:
        return out.isatty()
    except (AttributeError, ValueError):  # a closed or unusual stream: treat as a file
        return False


def animate(frames: Iterable[str], display: Display, out: TextIO, sleep: Callable[[float], None] = time.sleep) -> int:
    """Show text frames one after another; returns how many were shown.

    On a terminal (``display.clear``) each frame is redrawn in place: cursor home, the frame
    with every line cleared to its end, the rest of the screen cleared (no flicker from a full
    clear). Elsewhere frames follow each other, separated by a blank line, so a log reads top
    to bottom.
    """
    n = 0
    if display.clear:
        out.write(HIDE_CURSOR + CLEAR_SCREEN)
    try:
        for text in frames:
            if n and display.delay > 0:
                sleep(display.delay)
            if display.clear:
                out.write(CURSOR_HOME + text.replace("\n", CLEAR_TO_EOL + "\n") + CLEAR_TO_EOL + "\n" + CLEAR_BELOW)
            else:
                out.write(("\n" if n else "") + text + "\n")
            out.flush()
            n += 1
    finally:
        if display.clear:
            out.write(SHOW_CURSOR)
            out.flush()
    return n


def draw(out: TextIO, text: str) -> None:
    """Redraw the screen in place: cursor home, each line cleared to its end, the rest cleared."""
    out.write(CURSOR_HOME + text.replace("\n", CLEAR_TO_EOL + "\n") + CLEAR_TO_EOL + "\n" + CLEAR_BELOW)
    out.flush()
