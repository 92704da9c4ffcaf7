"""What moves: the robots of one frame, their poses, the marks of collisions, the legend.

An env describes its state as a ``Scene`` (``envs/drawing.py`` builds it from the last step);
both renderers draw a ``Scene`` the same way:

- each robot at its cell, or side by side with the others in a shared cell (collisions
  "pass", finished robots at an exit), scaled to fit (``robot.icon_scale``);
- a robot that finished this step is drawn in the exit cell, celebrating; finished robots
  stay there as small icons with a rank badge;
- a burst where a robot was stopped by another, in the step it happened, at the edge of the
  cell it could not enter.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..core.level import Cell
from .paint import Colour, Fill, Op, Text, star
from .palette import Theme, robot_colour
from .panel import LegendRow, rank_badge
from .robot import icon_scale, robot

POSE_OF_OUTCOME = ("moving", "idle", "bumped", "skidding", "glass")  # by core.engine outcome code


@dataclass(frozen=True)
class RobotView:
    """One robot as drawn: its number (its colour), cell, heading (an ``Action``), pose, the
    cell it came from this step (the canvas glides from there), its rank once finished, and
    whether its number is shown (a race) or not (a lone robot)."""

    number: int
    cell: Cell
    heading: int = 0
    pose: str = "idle"
    came_from: Cell | None = None
    rank: int = 0
    numbered: bool = True


@dataclass(frozen=True)
class Scene:
    robots: tuple[RobotView, ...] = ()
    marks: tuple[tuple[Cell, Cell], ...] = ()  # (a robot's cell, the cell another robot kept it from)
    legend: tuple[LegendRow, ...] = ()
    done: bool = False  # the episode or race has ended


def as_scene(robots: Scene | Sequence[Cell | None]) -> Scene:
    """A ``Scene`` from a scene, or from a list of cells (robot ``i`` at ``robots[i]``; None: not drawn)."""
    if isinstance(robots, Scene):
        return robots
    lone = len(robots) == 1
    return Scene(tuple(RobotView(i, tuple(c), numbered=not lone) for i, c in enumerate(robots) if c is not None))  # type: ignore[arg-type]


@dataclass(frozen=True)
class Placement:
    view: RobotView
    cx: float  # centre, cell units
    cy: float
    scale: float  # 1: a whole cell


def placements(scene: Scene) -> list[Placement]:
    """Where each robot is drawn, lowest number on top (drawn last)."""
    by_cell: dict[Cell, list[RobotView]] = {}
    for v in scene.robots:
        by_cell.setdefault(v.cell, []).append(v)
    out = []
    for cell, views in by_cell.items():
        views.sort(key=lambda v: (v.rank == 0, v.rank, v.number))  # finished first, by rank
        scale, slots = icon_scale(len(views))
        for v, (u, w) in zip(views, slots):
            out.append(Placement(v, cell[0] + u, cell[1] + w, scale))
    out.sort(key=lambda p: -p.view.number)
    return out


# ---------------------------------------------------------------------- robot shapes, cached flat
@dataclass(frozen=True, eq=False)
class Sprite:
    """A robot's operations about its centre at one pixel size, flattened for fast drawing:
    ``points`` float64[N, 2], ``counts`` (points per polygon), ``colours`` uint8[P, 3], ``alphas``,
    and ``texts`` (Text ops about the centre)."""

    points: np.ndarray
    counts: np.ndarray
    colours: np.ndarray
    alphas: np.ndarray
    texts: tuple[Text, ...]

    def ops(self, cx: float, cy: float) -> list[Op]:
        """The operations at ``(cx, cy)`` (pixels), in drawing order (texts last)."""
        out: list[Op] = []
        start = 0
        for k, n in enumerate(self.counts):
            out.append(Fill(self.points[start : start + n] + (cx, cy), tuple(self.colours[k].tolist()), float(self.alphas[k])))
            start += n
        out += [Text(t.x + cx, t.y + cy, t.text, t.size, t.colour, t.align, t.baseline, t.alpha) for t in self.texts]
        return out


@lru_cache(maxsize=1024)
def sprite(theme: Theme, number: int, heading: int, pose: str, numbered: bool, size: float) -> Sprite:
    colour = robot_colour(theme, number)
    ops = robot(0.0, 0.0, size, theme, colour, heading, pose, number if numbered else None)
    return _flatten(ops)


@lru_cache(maxsize=256)
def badge(theme: Theme, rank: int, r: float) -> Sprite:
    return _flatten(rank_badge(0.0, 0.0, r, rank, theme))


@lru_cache(maxsize=64)
def burst(theme: Theme, size: float) -> Sprite:
    r = size
    return _flatten(
        [
            Fill(star(0.0, 0.0, r * 1.12, r * 0.58, 8, -90 + 22.5), theme.robot_ink),
            Fill(star(0.0, 0.0, r, r * 0.48, 8, -90 + 22.5), theme.mark),
            Fill(star(0.0, 0.0, r * 0.5, r * 0.26, 8, -90), (255, 226, 90)),
        ]
    )


def _flatten(ops: Sequence[Op]) -> Sprite:
    fills = [op for op in ops if isinstance(op, Fill)]
    texts = tuple(op for op in ops if isinstance(op, Text))
    return Sprite(
        np.concatenate([f.points for f in fills]) if fills else np.zeros((0, 2)),
        np.array([len(f.points) for f in fills], dtype=np.int64),
        np.array([f.colour for f in fills], dtype=np.uint8).reshape(-1, 3),
        np.array([f.alpha for f in fills], dtype=np.float64),
        texts,
    )


def robot_sprites(scene: Scene, cs: float, theme: Theme, pose_override: dict[int, str] | None = None,
                  at: dict[int, tuple[float, float]] | None = None) -> list[tuple[Sprite, float, float]]:  # fmt: skip
    """The sprites of a scene's robots, marks and badges with their centres in pixels, in drawing order.

    ``at`` moves robots (by number) to other centres (cell units; the canvas's glide) and
    ``pose_override`` changes their poses on the way.
    """
    out: list[tuple[Sprite, float, float]] = []
    badges = []
    for p in placements(scene):
        v = p.view
        pose = (pose_override or {}).get(v.number, v.pose)
        cx, cy = (at or {}).get(v.number, (p.cx, p.cy))
        out.append((sprite(theme, v.number, v.heading, pose, v.numbered, round(cs * p.scale, 2)), cx * cs, cy * cs))
        if v.rank:
            r = max(4.0, cs * 0.13 * max(p.scale, 0.55))
            badges.append((badge(theme, v.rank, round(r, 2)), (cx + 0.36 * p.scale) * cs, (cy - 0.36 * p.scale) * cs))
    for own, other in scene.marks:
        # at the edge the robot could not cross, a little into the cell it wanted
        u = own[0] + 0.5 + (other[0] - own[0]) * 0.62
        w = own[1] + 0.5 + (other[1] - own[1]) * 0.62
        out.append((burst(theme, round(cs * 0.2, 2)), u * cs, w * cs))
    return out + badges


def colour_of(theme: Theme, number: int) -> Colour:
    return robot_colour(theme, number)
