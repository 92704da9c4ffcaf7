"""Shapes drawn many times, made once: robots, rank badges, collision bursts.

(``Sprite``, ``Stamp``, ``patch`` and ``blend`` live in ``paint``, the rasteriser; they are
imported here too.) A ``Sprite`` is a picture's operations about its centre at one pixel size, flattened into
arrays (the canvas sends all of a frame's sprites in one ``fill_styled_polygons`` call); the
numpy renderer rasterises each sprite once per quarter-pixel offset (``patch``). Both caches
are bounded by bytes (``memo``).
"""

from __future__ import annotations

from functools import lru_cache

from .glyphs import fit
from .memo import MB, byte_cached
from .paint import Patch, Sprite, Stamp, blend, flatten, patch
from .palette import Theme, robot_colour
from .robot import number_size, robot
from .shapes import Fill, Op, Text, circle, star

__all__ = ["MEDALS", "OTHER_RANK", "Patch", "Sprite", "Stamp", "badge", "blend", "burst", "flatten", "goal_mark", "patch",
           "robot_sprite"]

MEDALS = {1: (240, 190, 40), 2: (190, 196, 206), 3: (205, 130, 70)}  # gold, silver, bronze; then grey
OTHER_RANK = (150, 154, 166)


SPRITE_BYTES = 8 * MB  # robots' outlines: a few kB each, one per robot number, heading, pose and size


def robot_sprite(theme: Theme, number: int, heading: int, pose: str, numbered: bool, size: float,
                 outlined: bool = False) -> Sprite:  # fmt: skip
    """Baby Robot number ``number`` (its colour; its number on its chest when ``numbered``;
    ringed when ``outlined``). Robots that look the same share a sprite: below the size a number
    is drawn at, a robot is its colour."""
    shown = number if numbered and number_size(number, size) is not None else None
    return _robot_sprite(theme, robot_colour(theme, number), heading, pose, numbered, shown, size, outlined)


@byte_cached(SPRITE_BYTES)
def _robot_sprite(theme: Theme, colour: tuple, heading: int, pose: str, numbered: bool, shown: int | None,
                  size: float, outlined: bool) -> Sprite:  # fmt: skip
    if numbered and shown is None:  # a chest too small for its number: drawn as robot() draws it then
        ops = robot(0.0, 0.0, size, theme, colour, heading, pose, 0, outlined)
        return flatten([op for op in ops if not isinstance(op, Text)])
    return flatten(robot(0.0, 0.0, size, theme, colour, heading, pose, shown, outlined))


@lru_cache(maxsize=256)
def badge(theme: Theme, rank: int, r: float) -> Sprite:
    """A round rank badge of radius ``r``: gold, silver, bronze, then grey, with the rank."""
    fill = MEDALS.get(rank, OTHER_RANK)
    ops: list[Op] = [Fill(circle(0.0, 0.0, r + max(1.0, r * 0.15)), theme.robot_ink), Fill(circle(0.0, 0.0, r), fill)]
    s = fit(str(rank), r * 1.5, r * 1.1, largest=30, smallest=6)
    if s is not None:
        ops.append(Text(0.0, 0.0, str(rank), s, (20, 20, 24)))
    return flatten(ops)


@lru_cache(maxsize=64)
def burst(theme: Theme, r: float) -> Sprite:
    """The mark where a robot was stopped by another: an eight-pointed burst."""
    return flatten(
        [
            Fill(star(0.0, 0.0, r * 1.12, r * 0.58, 8, -90 + 22.5), theme.robot_ink),
            Fill(star(0.0, 0.0, r, r * 0.48, 8, -90 + 22.5), theme.mark),
            Fill(star(0.0, 0.0, r * 0.5, r * 0.26, 8, -90), (255, 226, 90)),
        ]
    )


@lru_cache(maxsize=256)
def goal_mark(theme: Theme, colour: tuple, cs: int) -> Sprite:
    """A robot's own target, in its colour, in a cell of ``cs`` pixels: a ring round a dot (a
    target), outlined in the robots' ink; below 16 pixels a diamond, a shape no robot has."""
    ink = theme.robot_ink
    if cs < 16:
        r = cs * 0.48
        return flatten([Fill(_diamond(r), ink), Fill(_diamond(r - 1.0), colour)])
    r, e = cs * 0.40, max(1.0, cs * 0.035)
    t = max(2.0, cs * 0.1)  # the ring's width
    return flatten([Fill(circle(0.0, 0.0, r), ink), Fill(circle(0.0, 0.0, r - e), colour),
                    Fill(circle(0.0, 0.0, r - e - t), ink), Fill(circle(0.0, 0.0, r - 2 * e - t), theme.floor),
                    Fill(circle(0.0, 0.0, r * 0.3 + e), ink), Fill(circle(0.0, 0.0, r * 0.3), colour)])  # fmt: skip


def _diamond(r: float):
    return star(0.0, 0.0, r, r * 0.5**0.5, 4, -90)  # a square on its corner: its sides' middles at r / sqrt 2
