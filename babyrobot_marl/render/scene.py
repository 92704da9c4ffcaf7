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

from ..core.level import Cell
from .paint import Sprite
from .palette import Theme, robot_colour
from .panel import LegendRow
from .robot import icon_scale
from .shapes import Colour
from .sprites import badge, burst, robot_sprite

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


@lru_cache(maxsize=16)
def placements(scene: Scene, labelled: frozenset = frozenset(), top: float = 0.0) -> list[Placement]:
    """Where each robot is drawn, lowest number on top (drawn last); robots sharing a ``labelled``
    cell stand below its label (``top``: the label band's bottom, in cell units)."""
    by_cell: dict[Cell, list[RobotView]] = {}
    for v in scene.robots:
        by_cell.setdefault(v.cell, []).append(v)
    out = []
    for cell, views in by_cell.items():
        views.sort(key=lambda v: (v.rank == 0, v.rank, v.number))  # finished first, by rank
        scale, slots = icon_scale(len(views), top if cell in labelled else 0.0)
        for v, (u, w) in zip(views, slots):
            out.append(Placement(v, cell[0] + u, cell[1] + w, scale))
    out.sort(key=lambda p: -p.view.number)
    return out


def glide(
    scene: Scene, t: float, labelled: frozenset = frozenset(), top: float = 0.0
) -> tuple[dict[int, tuple[float, float]], dict[int, str]]:
    """Where the robots that moved this step are a fraction ``t`` (0..1) of the way, and their
    poses on the way (a finisher walks in, then celebrates): the ``at`` and ``poses`` of
    ``robot_sprites``."""
    moving = {v.number: v for v in scene.robots if v.came_from is not None and v.came_from != v.cell}
    if not moving or t >= 1.0:
        return {}, {}
    ends = {p.view.number: (p.cx, p.cy) for p in placements(scene, labelled, top) if p.view.number in moving}
    at = {}
    for i, v in moving.items():
        (ax, ay), (bx, by) = (v.came_from[0] + 0.5, v.came_from[1] + 0.5), ends[i]  # type: ignore[index]
        at[i] = (ax + (bx - ax) * t, ay + (by - ay) * t)
    return at, {i: "moving" for i, v in moving.items() if v.pose == "finished"}


def robot_sprites(scene: Scene, cs: float, theme: Theme, pose_override: dict[int, str] | None = None,
                  at: dict[int, tuple[float, float]] | None = None,
                  labelled: frozenset = frozenset()) -> list[tuple[Sprite, float, float]]:  # fmt: skip
    """The sprites of a scene's robots, marks and badges with their centres in pixels, in drawing order.

    ``at`` moves robots (by number) to other centres (cell units; the canvas's glide) and
    ``pose_override`` changes their poses on the way; ``labelled``: cells with a START / EXIT label.
    """
    from .picture import label_band

    out: list[tuple[Sprite, float, float]] = []
    badges = []
    for p in placements(scene, labelled, label_band(int(cs))[1] / cs):
        v = p.view
        pose = (pose_override or {}).get(v.number, v.pose)
        cx, cy = (at or {}).get(v.number, (p.cx, p.cy))
        out.append((robot_sprite(theme, v.number, v.heading, pose, v.numbered, round(cs * p.scale, 2)), cx * cs, cy * cs))
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
