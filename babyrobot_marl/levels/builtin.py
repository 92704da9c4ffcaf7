"""The built-in levels by name: ``names()``, ``get(name)``, ``text(name)``.

``get`` also takes ``"maze-WxH"`` and ``"maze-WxH-sSEED"`` for any size and seed (``mazes.maze``).
The table of levels is in the package docstring (``babyrobot_marl.levels``).
"""

from __future__ import annotations

import re
from functools import cache

from ..core.checks import shown
from ..core.level import Level
from .mazes import _maze

_TEXTS: dict[str, str] = {
    "default": """
+-+-+-+
|S    |
+ + + +
|     |
+ + + +
|    E|
+-+-+-+
""",
    "walls": """
+-+-+-+-+-+
|S    |   |
+-+-+ + + +
|     |   |
+ +-+-+ +-+
|   |     |
+ + + +-+ +
|   |   | |
+-+ +-+ + +
|       |E|
+-+-+-+-+-+
""",
    "puddles": """
+-+-+-+-+-+
|S     p  |
+ + + + + +
|  p P p  |
+ + + + + +
|    p    |
+ + + + + +
|  P   P  |
+ + + + + +
|      p E|
+-+-+-+-+-+
""",
    "blocked": """
+-+-+-+-+-+
|S   #    |
+ + + + + +
|    #   #|
+ + + + + +
|#        |
+ + + + + +
|    # #  |
+ + + + + +
|  #     E|
+-+-+-+-+-+
""",
    "glass": """
+-+-+-+-+-+
|S        |
+ + + + + +
|         |
+-+-+*+-+-+
|         |
+ + + + + +
|         |
+-+*+-+-+ +
|        E|
+-+-+-+-+-+
""",
    "mixed-8x8": """
+-+-+-+-+-+-+-+-+
|S    |    p    |
+ +-+ + + +-+-+ +
|   | |    P|   |
+ + + +-+ + + + +
|p  |        #  |
+ +-+-+ + + + + +
|    p    |     |
+-+-+ + +-+ +-+ +
|   |      P|   |
+ + + +-+ + + + +
|  #|   |    p  |
+ + + + +-+-+ + +
|   *   | |   | |
+ +-+ +-+ + + + +
|     |     |  E|
+-+-+-+-+-+-+-+-+
""",
    "race-2": """
+-+-+-+-+-+
|0        |
+ + + + + +
|  p   #  |
+ + +-+ + +
|    E    |
+ + + + + +
|  #   p  |
+ + + + + +
|        1|
+-+-+-+-+-+
""",
    "race-4": """
+-+-+-+-+-+-+-+
|0    |      1|
+ + + + + + + +
|    p     #  |
+ +-+-+ +-+-+ +
|     |   |   |
+ + + +-+ + + +
|     |E      |
+ + + +-+ +-+ +
|    p P      |
+ +-+ + + +-+ +
|  #    *    p|
+ + + + + + + +
|3      |    2|
+-+-+-+-+-+-+-+
""",
    "race-corridor": """
+-+-+-+-+-+-+-+
|0 1         #|
+ +-+-+-+-+-+ +
|      E      |
+ +-+-+-+-+-+ +
|#         3 2|
+-+-+-+-+-+-+-+
""",
}

_MAZE = re.compile(r"maze-(\d+)x(\d+)(?:-s(\d+))?")
_MAZE_NAMES = ("maze-8x8", "maze-16x16")


def names() -> list[str]:
    """The built-in level names (``get`` also makes ``maze-WxH[-sSEED]`` of any size)."""
    return [*_TEXTS, *_MAZE_NAMES]


def text(name: str) -> str:
    """The level text of a built-in level."""
    return get(name).to_ascii()


def get(name: str) -> Level:
    """The built-in level called ``name``; a ``ValueError`` lists the known names."""
    if not isinstance(name, str):
        raise TypeError(f"level: expected a level name (str), got {type(name).__name__}")
    return _get(name)


def _get(name: str) -> Level:
    if name in _TEXTS:
        return _builtin(name)
    m = _MAZE.fullmatch(name)
    if m:
        try:
            w, h, seed = int(m[1]), int(m[2]), int(m[3] or 0)
        except ValueError:  # over Python's 4,300 digits of int("...")
            raise ValueError(f"level {shown(name)}: a maze size or seed has too many digits") from None
        try:
            return _maze(w, h, seed, name)
        except ValueError as err:
            raise ValueError(f"level {shown(name)}: {err}") from None
    raise ValueError(
        f"level: unknown level {shown(name)}; known levels: {', '.join(names())} "
        "(and maze-WxH or maze-WxH-sSEED for any size and seed), or pass a Level or a level text"
    )


@cache  # the few built-in texts: a fixed set
def _builtin(name: str) -> Level:
    return Level.from_ascii(_TEXTS[name], name=name)
