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
    """How frames reach the terminal: colour, clearing between frames, pause between frames; ``ends_only``:
    in a file or pipe, the first and the last frame (a log reader wants the outcome, not every step)."""

    colour: bool
    clear: bool
    delay: float
    ends_only: bool = False


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
    to bottom; with ``display.ends_only``, only the first and the last, with a line saying how many
    lie between.
    """
    if display.ends_only and not display.clear:
        return _ends(frames, out)
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


def _ends(frames: Iterable[str], out: TextIO) -> int:
    """The first and the last of ``frames``, and how many were left out between them; returns how many there were."""
    n, last = 0, None
    for text in frames:
        if n == 0:
            out.write(text + "\n")
            out.flush()
        last, n = text, n + 1
    if n > 1:
        between = f"({n - 2:,} frames left out: one per step on a terminal, or every one here with --all-frames)\n\n"
        out.write(("\n" + between if n > 2 else "\n") + last + "\n")
    out.flush()
    return n


def draw(out: TextIO, text: str) -> None:
    """Redraw the screen in place: cursor home, each line cleared to its end, the rest cleared."""
    out.write(CURSOR_HOME + text.replace("\n", CLEAR_TO_EOL + "\n") + CLEAR_TO_EOL + "\n" + CLEAR_BELOW)
    out.flush()
