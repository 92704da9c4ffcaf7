"""The settings that train a crowd best, applied when several robots stop each other's moves (numpy-free, torch-free:
the ``train`` command's help names them)."""

from __future__ import annotations

from typing import Any

# collision rules under which a robot stops another's move: a crowd can jam
CROWD_COLLISIONS = ("block", "bounce", "soft")
# what trained 32 robots on maze:16..16 under "bounce" best: every robot that could contest the next cell in
# view (near_radius 2), and a cost on each move another robot stops, which breaks the jams a crowd otherwise keeps
CROWD_DEFAULTS: dict[str, Any] = {"near_radius": 2, "blocked_cost": 0.5}


def crowd_defaults(n_robots: int, collisions: str | None, chosen: dict[str, Any],
                   view_radius: int | None = None) -> dict[str, Any]:
    """The ``CROWD_DEFAULTS`` that ``chosen`` leaves unset (missing or None), for several robots under a rule
    where they stop each other (``collisions`` None: the env's default, ``"block"``); none for one robot or
    under ``"pass"``. Robots that read a window of ``view_radius`` see the robots within it, no farther."""
    if n_robots < 2 or (collisions or "block") not in CROWD_COLLISIONS:
        return {}
    defaults = dict(CROWD_DEFAULTS)
    if view_radius is not None:
        defaults["near_radius"] = min(defaults["near_radius"], view_radius)
    return {name: value for name, value in defaults.items() if chosen.get(name) is None}


def said(settings: dict[str, Any]) -> str:
    """``settings`` as the summary line names them: ``near_radius 2, blocked_cost 0.5``."""
    return ", ".join(f"{name} {value:g}" for name, value in settings.items())
