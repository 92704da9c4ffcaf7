"""Baby Robot, drawn by code: a small robot with a round-cornered head, a dark visor with two
glowing eyes, an antenna, arms, a chest plate and a track, facing the way it moves.

``robot(cx, cy, size, ...)`` returns the ``paint`` operations of one robot centred on
``(cx, cy)`` and ``size`` pixels tall (a cell's size at full scale). Its eyes and head turn to
its heading; its pose tells what its last step did:

| pose | when | drawn as |
|---|---|---|
| ``idle`` | reset, STAY | upright, eyes on its heading |
| ``moving`` | moved as intended | leaning in, speed lines behind |
| ``bumped`` | stopped by a wall, a block, the border or a robot | squeezed eyes, stars at its brow |
| ``skidding`` | a puddle sent it elsewhere | tilted, splashes under the track |
| ``glass`` | a glass wall held it back | wide eyes, a glint on its visor |
| ``finished`` | reached an exit | arms up, happy eyes, confetti |

In a race a robot wears its colour and carries its number on its chest.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from .glyphs import fit
from .palette import Theme
from .shapes import Colour, Fill, Op, Points, Text, circle, ellipse, round_rect, segment, shade, star, turned

POSES = ("idle", "moving", "bumped", "skidding", "glass", "finished")
HEADINGS = {0: (0.0, 0.0), 1: (0.0, -1.0), 2: (1.0, 0.0), 3: (0.0, 1.0), 4: (-1.0, 0.0)}  # by Action
SCALE = 0.86  # a full-size robot's height in cells


class _Pen:
    """Turns robot units (the robot about (0, 0), 1 = its height, y down) into pixels."""

    def __init__(self, cx: float, cy: float, size: float, tilt: float = 0.0):
        self.cx, self.cy, self.s, self.tilt = cx, cy, size * SCALE, tilt
        self.ops: list[Op] = []

    def _px(self, pts: Points) -> Points:
        pts = np.column_stack([self.cx + pts[:, 0] * self.s, self.cy + pts[:, 1] * self.s])
        return turned(pts, self.tilt, self.cx, self.cy + 0.42 * self.s) if self.tilt else pts

    def fill(self, pts: Points, colour: Colour, alpha: float = 1.0) -> None:
        self.ops.append(Fill(self._px(pts), colour, alpha))

    def box(self, x0: float, y0: float, x1: float, y1: float, r: float, colour: Colour, outline: Colour | None = None,
            width: float = 0.035) -> None:  # fmt: skip
        if outline is not None:
            self.fill(round_rect(x0 - width, y0 - width, x1 + width, y1 + width, r + width), outline)
        self.fill(round_rect(x0, y0, x1, y1, r), colour)

    def disc(self, x: float, y: float, r: float, colour: Colour, alpha: float = 1.0) -> None:
        self.fill(circle(x, y, r, n=max(10, min(40, int(r * self.s * 2.2) + 8))), colour, alpha)

    def stroke(self, x0: float, y0: float, x1: float, y1: float, width: float, colour: Colour) -> None:
        self.fill(segment(x0, y0, x1, y1, width), colour)


def robot(
    cx: float,
    cy: float,
    size: float,
    theme: Theme,
    colour: Colour,
    heading: int = 0,
    pose: str = "idle",
    number: int | None = None,
    outlined: bool = False,
) -> list[Op]:
    """The operations that draw one Baby Robot (see the module's table for ``pose``);
    ``outlined``: ringed in its ink, then in the floor's colour (a small robot on a tinted cell)."""
    dx, dy = HEADINGS.get(heading, (0.0, 0.0))
    tilt = {"skidding": 14.0 * (dx or 1.0), "moving": 6.0 * dx}.get(pose, 0.0)
    shift = 0.05 if pose == "bumped" and not outlined else 0.0  # leaning into the wall; in a corner, off it
    p = _Pen(cx + dx * shift * size, cy + dy * shift * size, size, tilt)
    ink, body, dark = theme.robot_ink, colour, shade(colour, 0.72)
    light = shade(colour, 1.55)

    if outlined:
        for grow, ring in zip(OUTLINE[::-1], (theme.floor, ink)):
            _silhouette(p, grow, ring, dx, dy, pose == "finished")
    # shadow, speed lines and splashes: under the robot
    p.fill(ellipse(0.0, 0.45, 0.3, 0.055), (0, 0, 0), 0.16)
    if pose == "moving" and (dx or dy):
        for k, off in enumerate((-0.12, 0.04, 0.2)):
            x0, y0 = -dx * 0.36 + dy * off, -dy * 0.36 + dx * off
            p.stroke(x0, y0, x0 - dx * (0.14 - 0.03 * k), y0 - dy * (0.14 - 0.03 * k), 0.035, ink)
    if pose == "skidding":
        for x, y, r in ((-0.34, 0.4, 0.05), (0.36, 0.38, 0.04), (-0.42, 0.3, 0.03), (0.44, 0.28, 0.025)):
            p.disc(x, y, r, (80, 160, 230))

    # track and wheels
    p.box(-0.25, 0.3, 0.25, 0.43, 0.06, (58, 62, 74), ink)
    for x in (-0.15, 0.0, 0.15):
        p.disc(x, 0.365, 0.035, (170, 176, 190))

    # arms (behind the body): down, or up when celebrating / pressing on glass
    if pose == "finished":
        p.stroke(-0.25, 0.08, -0.42, -0.16, 0.09, ink)
        p.stroke(0.25, 0.08, 0.42, -0.16, 0.09, ink)
        p.stroke(-0.25, 0.08, -0.42, -0.16, 0.055, dark)
        p.stroke(0.25, 0.08, 0.42, -0.16, 0.055, dark)
        p.disc(-0.42, -0.16, 0.05, body)
        p.disc(0.42, -0.16, 0.05, body)
    elif pose == "glass":
        for side in (-1, 1):
            hx, hy = side * 0.22 + dx * 0.2, -0.02 + dy * 0.12
            p.stroke(side * 0.24, 0.1, hx, hy, 0.09, ink)
            p.stroke(side * 0.24, 0.1, hx, hy, 0.055, dark)
            p.disc(hx, hy, 0.05, body)
    else:
        swing = 0.04 if pose == "moving" else 0.0
        p.box(-0.33, 0.04 - swing, -0.25, 0.24 - swing, 0.035, dark, ink, 0.025)
        p.box(0.25, 0.04 + swing, 0.33, 0.24 + swing, 0.035, dark, ink, 0.025)

    # body and chest plate with the number (or a heart light for a lone robot)
    p.box(-0.25, -0.01, 0.25, 0.31, 0.07, body, ink)
    p.box(-0.15, 0.04, 0.15, 0.25, 0.04, light)
    if number is not None:
        px_size = number_size(number, size)
        if px_size is not None:
            p.ops.append(Text(cx + dx * shift * size, p._px(np.array([[0.0, 0.145]]))[0, 1], str(number), px_size, ink))
    else:
        p.disc(0.0, 0.145, 0.045, (235, 80, 90))

    # neck, head, visor, eyes: the head turns towards the heading
    hx, hy = dx * 0.035, dy * 0.02
    p.box(-0.05, -0.06, 0.05, 0.0, 0.0, (58, 62, 74))
    ax = hx - dx * 0.05
    p.stroke(hx, -0.33, ax, -0.46, 0.03, ink)
    glow = (255, 214, 60) if pose == "finished" else light
    if pose == "finished":
        p.disc(ax, -0.46, 0.1, (255, 236, 140), 0.6)
    p.disc(ax, -0.46, 0.065 if pose == "finished" else 0.045, glow)
    p.box(-0.27 + hx, -0.37 + hy, 0.27 + hx, -0.05 + hy, 0.1, body, ink)
    vx, vy = hx + dx * 0.03, hy + dy * 0.015
    p.box(-0.2 + vx, -0.3 + vy, 0.2 + vx, -0.11 + vy, 0.065, theme.visor)
    ex, ey = vx + dx * 0.045, vy + dy * 0.03 - 0.205
    _eyes(p, pose, ex, ey, theme.eye)

    # marks on top: stars when bumped, a glint on glass, confetti when finished
    if pose == "bumped":
        for sx, sy, r in ((dx * 0.26 + 0.24, -0.33, 0.1), (dx * 0.26 - 0.22, -0.36, 0.075)):
            sx = min(max(sx, r - STAR_REACH), STAR_REACH - r)  # inside its cell, off the wall it hit
            p.fill(star(sx, sy, r, r * 0.45), (255, 200, 40))
            p.fill(star(sx, sy, r * 0.5, r * 0.22), (255, 250, 210))
    elif pose == "glass":
        p.stroke(0.08 + vx, -0.28 + vy, 0.16 + vx, -0.16 + vy, 0.025, (255, 255, 255))
    elif pose == "finished":
        for k, (x, y) in enumerate(((-0.4, -0.42), (0.38, -0.44), (-0.46, 0.02), (0.47, -0.02), (0.18, -0.56), (-0.2, -0.56))):
            c = ((255, 200, 40), (86, 180, 233), (213, 94, 0), (0, 158, 115))[k % 4]
            p.fill(turned(round_rect(x - 0.03, y - 0.02, x + 0.03, y + 0.02, 0.005), 30.0 * k, x, y), c)
    return p.ops


@lru_cache(maxsize=16384)  # about 2 MB at most: a few numbers to a cache entry
def number_size(number: int, size: float) -> int | None:
    """The text size of ``number`` on the chest of a robot ``size`` pixels tall; None: too small to be drawn."""
    return fit(str(number), 0.27 * size * SCALE, 0.16 * size * SCALE, largest=40, smallest=6)


STAR_REACH = 0.46  # a bumped robot's stars: this far from its centre at most (robot units; it leans 0.05 of
# a cell into the wall: the stars stay within 0.45 of a cell from the cell's centre, inside its walls)
OUTLINE = (0.08, 0.2)  # an outlined robot's rings: its ink, then the floor's colour, this far out (robot units)


def _silhouette(p: _Pen, grow: float, colour: Colour, dx: float, dy: float, arms_up: bool) -> None:
    """The robot's head, body, track and antenna (and raised arms), ``grow`` wider all round
    (arms held down lie within); placed as ``robot`` places them for heading ``(dx, dy)``."""
    hx, hy = dx * 0.035, dy * 0.02
    ax = hx - dx * 0.05
    # under the track, half as wide: a robot in its corner stays inside its cell
    p.fill(round_rect(-0.25 - grow, 0.3 - grow, 0.25 + grow, 0.43 + grow / 2, 0.06 + grow / 2), colour)
    p.fill(round_rect(-0.25 - grow, -0.01 - grow, 0.25 + grow, 0.31 + grow, 0.07 + grow), colour)
    p.fill(round_rect(-0.27 + hx - grow, -0.37 + hy - grow, 0.27 + hx + grow, -0.05 + hy + grow, 0.1 + grow), colour)
    p.stroke(hx, -0.33, ax, -0.46, 0.03 + grow, colour)
    p.disc(ax, -0.46, 0.045 + grow * 0.6, colour)
    if arms_up:
        for side in (-1, 1):
            p.stroke(side * 0.25, 0.08, side * 0.42, -0.16, 0.09 + grow, colour)


def _eyes(p: _Pen, pose: str, ex: float, ey: float, eye: Colour) -> None:
    for side in (-1, 1):
        x = ex + side * 0.09
        if pose == "bumped":  # > <: squeezed shut
            d = -side * 0.035
            p.stroke(x - d, ey - 0.04, x + d, ey, 0.03, eye)
            p.stroke(x + d, ey, x - d, ey + 0.04, 0.03, eye)
        elif pose == "finished":  # happy arcs
            t = np.radians(np.linspace(200, 340, 8))
            arc = np.column_stack([x + 0.05 * np.cos(t), ey + 0.03 + 0.05 * np.sin(t)])
            inner = np.column_stack([x + 0.027 * np.cos(t[::-1]), ey + 0.03 + 0.027 * np.sin(t[::-1])])
            p.fill(np.concatenate([arc, inner]), eye)
        else:
            r = 0.058 if pose in ("glass", "skidding") else 0.047
            p.disc(x, ey, r, eye)
            if pose in ("glass", "skidding"):
                p.disc(x, ey, r * 0.45, (20, 24, 36))


CORNER = (0.44, 0.24, 0.76)  # a lone robot while an overlay is on: its scale and centre, bottom left of its cell
REACH = 0.76  # rows of robots sharing a cell: this many scales apart (its drawn height, antenna to
# track, is 0.82: the antenna's tip may reach past the track of the robot above, which hides nothing)


def icon_scale(n: int, top: float = 0.0) -> tuple[float, list[tuple[float, float]]]:
    """Robots in one cell: their scale and centres in cell units, in the part of the cell below
    ``top`` (a label's band), side by side when there are several (as large as their drawn
    height lets them: the rows are ``REACH`` of a scale apart; 4 robots at 56-pixel cells below an
    EXIT label are 25 pixels)."""
    if n <= 1:
        s = 1.0 - top
        return s, [(0.5, top + s / 2)]
    k = math.ceil(math.sqrt(n))
    rows = math.ceil(n / k)
    s = min(1.0 / k, (1.0 - top) / rows / REACH)
    y0 = top + (1.0 - top - rows * s * REACH) / 2
    return s, [((i % k + 0.5) / k, y0 + (i // k + 0.5) * s * REACH) for i in range(n)]
