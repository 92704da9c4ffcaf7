"""A text stream for tests: it records what is written and says whether it is a terminal."""

from __future__ import annotations


class TextSink:
    """Records what is written (``.text``); ``isatty()`` answers ``tty``."""

    def __init__(self, tty: bool = False):
        self.text = ""
        self.tty = tty

    def write(self, s: str) -> int:
        self.text += s
        return len(s)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return self.tty
