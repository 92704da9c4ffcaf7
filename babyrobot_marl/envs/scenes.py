"""What an env's last step looks like: the ``Scene`` the renderers draw (``render.scene``).

An env records its last step (``_last_step``); these functions turn that into each robot's cell,
heading and pose, the marks of collisions, and for a race the legend. Pure functions of the env's
state: the envs call them from ``_scene()``.
"""

from __future__ import annotations

from typing import Any

from ..core.engine import move
from ..core.outcomes import BUMPED, MOVED
from ..core.rng import SLOTS
from ..render.panel import LegendRow
from ..render.scene import POSE_OF_OUTCOME, RobotView, Scene


def single_scene(env: Any) -> Scene:
    """The single-robot env's scene: the robot, turned and posed by its last step."""
    if env._cell < 0:
        return Scene()
    cell = env._xy[env._cell]
    last = env._last_step
    corner = env.drawing.overlay.has_cells
    if last is None:
        return Scene((RobotView(0, cell, numbered=False),), done=env._done, corner=corner)
    prev, action, outcome = last
    finished = bool(env._lists.is_exit[env._cell])
    pose = "finished" if finished else ("idle" if outcome == MOVED and action == 0 else POSE_OF_OUTCOME[outcome])
    view = RobotView(0, cell, action, pose, env._xy[prev], numbered=False)
    return Scene((view,), done=env._done, corner=corner)


def race_scene(env: Any) -> Scene:
    """The race's scene: racing robots posed by their last step, finished robots at their exits
    with their ranks, bursts where robots stopped each other, and the legend."""
    if not env._rank:  # before the first reset
        return Scene()
    xy, cells, racing, n = env._xy, env._cells, env._racing, env.n_robots
    heading, pose, came, marks = [0] * n, ["idle"] * n, [None] * n, []
    if env._last_step is not None:
        live, prev, acts, outcome, blocked, finishing, t = env._last_step
        for k, i in enumerate(live):
            heading[i], came[i] = acts[k], xy[prev[k]]
            if finishing[k]:
                pose[i] = "finished"
            elif blocked[k]:
                pose[i] = "bumped"
                want = _desired(env._lists, prev[k], acts[k], env._key, t * n * SLOTS + i * SLOTS)
                marks.append((xy[prev[k]], xy[want]))
            else:
                o = outcome[k]
                pose[i] = "idle" if o == MOVED and acts[k] == 0 else POSE_OF_OUTCOME[o]
    views = []
    for i in range(n):
        if not racing[i]:
            pose[i] = "finished"
        views.append(_value(RobotView, i, xy[cells[i]], heading[i], pose[i], came[i], env._rank[i]))
    live_returns = dict(zip(env._live, env._live_returns))
    names = env.drawing.overlay.names
    legend = tuple(
        _value(LegendRow, i, names.get(i, ""), live_returns.get(i, env._returns[i]), env._rank[i], racing[i]) for i in range(n)
    )
    corner = env.drawing.overlay.has_cells
    return Scene(tuple(views), tuple(marks), legend, done=not env.agents, corner=corner, goals=own_goals(env))


def own_goals(env: Any) -> tuple[tuple[int, tuple[int, int]], ...]:
    """``Scene.goals``: each racing robot's own target ``(number, (x, y))`` (``goals="own"``), else none."""
    goal_of = getattr(env, "_goal_of", None)
    if goal_of is None:
        return ()
    xy = env._xy
    return tuple((i, xy[g]) for i, (g, on) in enumerate(zip(goal_of, env._racing)) if on)


_VALUES: list[dict[tuple, Any]] = [{}, {}]  # views and legend rows by content, this generation's and the last's
GENERATION = 1 << 14  # values a generation holds: a crowd's frame (a view and a row per robot) reuses the last's


def _value(cls: type, *fields: Any) -> Any:
    """``cls(*fields)``, the same object for the same fields (frozen values: shared safely), so a
    frame costs no new objects where nothing changed and the renderers compare them by identity.
    Bounded by two generations: a value used again moves to the new one, so the values of a
    frame of up to ``GENERATION`` stay the same objects from frame to frame."""
    key = (cls, *fields)
    now = _VALUES[0]
    v = now.get(key)
    if v is None:
        v = _VALUES[1].get(key)
        if v is None:
            v = cls(*fields)
        if len(now) >= GENERATION:
            _VALUES[1], _VALUES[0] = now, {}
            now = _VALUES[0]
        now[key] = v
    return v


def _desired(lists: Any, cell: int, action: int, key: int, counter: int) -> int:
    """Where a robot's move would have taken it before the collision rules (the same draw as the step)."""
    sure = lists.sure[cell][action]
    if sure is not None:
        return sure[0]
    to, outcome = move(lists, cell, action, key, counter)
    return to if outcome != BUMPED else cell
