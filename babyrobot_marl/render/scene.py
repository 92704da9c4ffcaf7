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
from .robot import CORNER, icon_scale
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
    corner: bool = False  # an overlay is on: a lone robot stands small in its cell's corner, clear of the numbers
    goals: tuple[tuple[int, Cell], ...] = ()  # (robot number, its own target cell) of robots still going there


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
    outlined: bool = False  # ringed so it reads small on a tinted cell (a lone robot in an overlay's corner)


def placements(scene: Scene, labelled: frozenset = frozenset(), top: float = 0.0) -> list[Placement]:
    """Where each robot is drawn, lowest number on top (drawn last); robots in a ``labelled``
    cell stand below its label (``top``: the label band's bottom, in cell units)."""
    return _placements(scene.robots, scene.corner, labelled, top)


@lru_cache(maxsize=64)
def _placements(robots: tuple[RobotView, ...], corner: bool, labelled: frozenset, top: float) -> list[Placement]:
    by_cell: dict[Cell, list[RobotView]] = {}
    for v in robots:
        by_cell.setdefault(v.cell, []).append(v)
    out = []
    for cell, views in by_cell.items():
        if len(views) == 1:
            out.append(lone_placement(views[0], corner, top if cell in labelled else 0.0))
            continue
        views.sort(key=lambda v: (v.rank == 0, v.rank, v.number))  # finished first, by rank
        scale, slots = icon_scale(len(views), top if cell in labelled else 0.0)
        for v, (u, w) in zip(views, slots):
            out.append(Placement(v, cell[0] + u, cell[1] + w, scale))
    out.sort(key=lambda p: -p.view.number)
    return out


@lru_cache(maxsize=8192)
def lone_placement(view: RobotView, corner: bool, top: float) -> Placement:
    """A robot alone in its cell (the same object each time: renderers key their caches by it)."""
    x, y = view.cell
    if corner:
        return Placement(view, x + CORNER[1], y + CORNER[2], CORNER[0], outlined=True)
    scale, ((u, w),) = icon_scale(1, top)
    return Placement(view, x + u, y + w, scale)


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
        (bx, by) = ends[i]
        # from the same spot of the cell it left (its corner, with an overlay)
        ox, oy = (bx - v.cell[0], by - v.cell[1]) if scene.corner else (0.5, 0.5)
        ax, ay = v.came_from[0] + ox, v.came_from[1] + oy  # type: ignore[index]
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
        pose = (pose_override or {}).get(p.view.number, p.view.pose)
        cx, cy = (at or {}).get(p.view.number, (p.cx, p.cy))
        robot, rank = placement_sprites(p, cs, theme, pose, cx, cy)
        out.append(robot)
        if rank is not None:
            badges.append(rank)
    for own, other in scene.marks:
        out.append((burst(theme, round(cs * BURST[0], 2)), *burst_centre(own, other, cs)))
    return out + badges


def placement_sprites(p: Placement, cs: float, theme: Theme, pose: str, cx: float, cy: float) -> tuple[tuple, tuple | None]:
    """A placed robot's sprite and its rank badge (None while racing), centred at ``(cx, cy)`` cells, in pixels."""
    v = p.view
    numbered = v.numbered and not v.rank  # on the podium: its rank only (its number is in the legend)
    robot = (robot_sprite(theme, v.number, v.heading, pose, numbered, round(cs * p.scale, 2), p.outlined), cx * cs, cy * cs)
    if not v.rank:
        return robot, None
    # a medal on its chest, where a racing robot's id is: clear of the label above and of the
    # other robots' faces, large enough for its digit
    r = max(5.0, cs * p.scale * 0.15)
    return robot, (badge(theme, v.rank, round(r, 2)), cx * cs, (cy + 0.17 * p.scale) * cs)


def at_rest(v: RobotView) -> RobotView:
    """The view without the cell it came from: its picture at rest is the same."""
    if v.came_from is None:
        return v
    return RobotView(v.number, v.cell, v.heading, v.pose, None, v.rank, v.numbered)


def with_numbers(entries: list[tuple], views: list[RobotView]) -> list[tuple]:
    """A cell's drawn robots ``(number, robot, badge or None)`` with their own numbers: a lone
    robot's may come from another robot that looks the same."""
    if len(views) > 1:
        return entries
    _, robot, badge = entries[0]
    return [(views[0].number, robot, badge)]


def drawing_order(entries: list[tuple], marks: list) -> list:
    """``robot_sprites``' order: the robots (highest number first, drawn under the lower), the
    bursts, then the badges."""
    entries = sorted(entries, key=lambda e: -e[0])
    return [e[1] for e in entries] + marks + [e[2] for e in entries if e[2] is not None]


BURST = (0.15, 0.32)  # a collision's burst: its radius, and how far beside the robots' faces, in cells


def burst_centre(own: Cell, other: Cell, cs: float) -> tuple[float, float]:
    """Where a collision's burst goes: on the edge the robot could not cross, moved along it to
    below (or beside) the two robots' faces, so both faces stay visible."""
    dx, dy = other[0] - own[0], other[1] - own[1]
    u = own[0] + 0.5 + dx * 0.5 + (BURST[1] if dy else 0.0)
    w = own[1] + 0.5 + dy * 0.5 + (BURST[1] if dx else 0.0)
    return u * cs, w * cs


def colour_of(theme: Theme, number: int) -> Colour:
    return robot_colour(theme, number)
