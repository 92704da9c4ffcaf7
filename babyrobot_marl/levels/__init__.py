"""Levels: the built-in ones, a seeded maze generator, level files and level families.

``names()`` lists the built-in levels, ``get(name)`` returns one as a ``Level``, ``maze(w, h, seed)``
makes a perfect maze (randomized depth-first search: one path between any two cells).
``get`` also takes ``"maze-WxH"`` and ``"maze-WxH-sSEED"`` for any size and seed.

=================  ==============================================================================
module             holds
=================  ==============================================================================
``builtin``        the built-in levels by name (``names``, ``get``, ``text``)
``mazes``          ``maze(w, h, seed)``, the seeded maze generator
``files``          ``read_level_file`` and ``load_level`` (what a user types: a name, a text, a file)
``sources``        level families drawn per reset (``maze_family``, ``level_source``, ``LevelPicker``)
``resolve``        ``resolve_level``: a ``Level`` from a name, a text or a ``Level``
``checks``         the levels' argument checks (maze sizes and seeds, level files)
=================  ==============================================================================

Built-in levels:

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

from .builtin import _TEXTS, get, names, text  # noqa: F401  (_TEXTS: the tests read the texts)
from .mazes import MAX_MAZE_SIDE, _maze, maze  # noqa: F401  (_maze: its cache, read by the tests)

__all__ = ["MAX_MAZE_SIDE", "get", "maze", "names", "text"]
