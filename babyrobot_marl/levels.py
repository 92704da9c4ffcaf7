"""Built-in levels and a seeded maze generator.

``names()`` lists the built-in levels, ``get(name)`` returns one as a ``Level``, ``maze(w, h, seed)``
makes a perfect maze (randomized depth-first search: one path between any two cells).
``get`` also takes ``"maze-WxH"`` and ``"maze-WxH-sSEED"`` for any size and seed.

=============  =======  ======  ==========================================================
name           size     starts  what it shows
=============  =======  ======  ==========================================================
default        3x3      1       the empty grid of DESIGN.md: start top left, exit bottom right
walls          5x5      1       walls between cells make a long winding path
puddles        5x5      1       small ``p`` and large ``P`` puddles: costly, and robots skid
blocked        5x5      1       blocked cells ``#`` that no robot may enter
glass          5x5      1       glass walls ``*`` passed with probability ``glass_pass_prob``
mixed-8x8      8x8      1       walls, glass, puddles and blocked cells together
race-2         5x5      2       two robots from opposite corners to a central exit
race-4         7x7      4       four robots from the corners to the centre, walls and puddles
race-corridor  7x3      4       a narrow corridor: collisions, swaps and queues
maze-8x8       8x8      1       ``maze(8, 8, seed=0)``
maze-16x16     16x16    1       ``maze(16, 16, seed=0)``
=============  =======  ======  ==========================================================
"""

from __future__ import annotations

import re
from functools import cache, lru_cache

import numpy as np

from .core.checks import check_int, shown
from .core.level import Level

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
MAX_MAZE_SIDE = 256  # a 256x256 maze is the largest level (checks.MAX_LEVEL_CELLS)


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


@lru_cache(maxsize=8)  # bounded: a 256x256 maze holds about 20 MB, and any size and seed may be asked for
def _maze(width: int, height: int, seed: int, name: str) -> Level:
    return maze(width, height, seed, name=name)


def maze(width: int, height: int, seed: int = 0, name: str = "") -> Level:
    """A perfect maze by randomized depth-first search: start top left, exit bottom right."""
    sides = {}
    for arg, v in (("width", width), ("height", height)):
        try:  # Python and numpy integers, not bools or floats (checks.check_int)
            sides[arg] = check_int(v, arg, 1, MAX_MAZE_SIDE)
        except ValueError:
            raise ValueError(f"{arg}: a maze side is an integer in 1..{MAX_MAZE_SIDE}, got {shown(v)}") from None
    width, height = sides["width"], sides["height"]
    try:
        seed = check_int(seed, "seed", lo=0)
    except ValueError:
        raise ValueError(f"seed: a maze seed is an integer >= 0, got {shown(seed)}") from None
    if width * height < 2:
        raise ValueError(f"width, height: a maze needs at least 2 cells for a start and an exit, got {width}x{height}")
    rng = np.random.default_rng(seed)
    open_edges: set[tuple[tuple[int, int], tuple[int, int]]] = set()
    seen = {(0, 0)}
    stack = [(0, 0)]
    while stack:
        x, y = stack[-1]
        nbrs = [
            (nx, ny)
            for nx, ny in ((x, y - 1), (x + 1, y), (x, y + 1), (x - 1, y))
            if 0 <= nx < width and 0 <= ny < height and (nx, ny) not in seen
        ]
        if not nbrs:
            stack.pop()
            continue
        nxt = nbrs[int(rng.integers(len(nbrs)))]
        open_edges.add(((x, y), nxt) if (x, y) < nxt else (nxt, (x, y)))
        seen.add(nxt)
        stack.append(nxt)
    walls = set()
    for y in range(height):
        for x in range(width):
            for n in ((x + 1, y), (x, y + 1)):
                if n[0] < width and n[1] < height and ((x, y), n) not in open_edges:
                    walls.add(((x, y), n))
    return Level(
        width=width,
        height=height,
        walls=frozenset(walls),
        starts=((0, 0),),
        exits=frozenset({(width - 1, height - 1)}),
        name=name or f"maze-{width}x{height}" + (f"-s{seed}" if seed else ""),
    )
