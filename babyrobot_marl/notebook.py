"""Play Baby Robot and build levels in a Jupyter notebook (needs the ``notebook`` extra).

::

    from babyrobot_marl import notebook
    notebook.play("walls")                    # one robot: buttons, or click the grid and use the arrow keys
    notebook.play("race-4", policies="shortest")  # a race: you drive robot_0, TAB drives the next one
    editor = notebook.edit((6, 4))            # click cells and edges; editor.level, editor.text

ipycanvas and ipywidgets are imported when ``play`` or ``edit`` is called, not before.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .play.notebook import Editor, Player

PLAY_ARGS = ("robots", "policies", "seed", "cell_size", "theme")
EDIT_ARGS = ("race", "cell_size")


def _check_keywords(function: str, given: dict[str, Any], known: tuple[str, ...]) -> None:
    unknown = [k for k in given if k not in known]
    if unknown:
        raise TypeError(f"{function}() got an unexpected keyword argument {unknown[0]!r}; known: {', '.join(known)}")


def play(env_or_level: Any = "default", **kwargs: Any) -> Player:
    """Play a level (a name, a level text or a ``Level``) or an env (``BabyRobotEnv``, ``RaceEnv``):
    the live canvas with move, stay and reset buttons, keys when the canvas has the focus, and a panel
    of steps and returns. Keywords: ``robots`` (a race of that many; default: the level's starts),
    ``policies`` of the robots you do not drive (``"random"`` or ``"shortest"``, one or one per robot),
    ``seed``, ``cell_size``, ``theme``."""
    _check_keywords("play", kwargs, PLAY_ARGS)
    from .play.notebook import Player

    return Player(env_or_level, **kwargs)


def edit(level_or_size: Any = (5, 5), **kwargs: Any) -> Editor:
    """The level editor, on a blank ``(width, height)`` grid or on a level to change. Keywords: ``race``
    (numbered starts), ``cell_size``. ``.level`` and ``.text`` give the result; "play it" plays it."""
    _check_keywords("edit", kwargs, EDIT_ARGS)
    from .play.notebook import Editor

    return Editor(level_or_size, **kwargs)


__all__ = ["edit", "play"]
