"""Deprecated: ``babyrobot_marl.notebook`` moved to ``babyrobot_marl.play.notebook``
(``from babyrobot_marl.play import notebook``); this path goes in 0.3."""

import warnings

from .play.notebook import EDIT_ARGS, PLAY_ARGS, edit, play  # noqa: F401

__all__ = ["edit", "play"]

warnings.warn(
    "babyrobot_marl.notebook moved to babyrobot_marl.play.notebook; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
