"""Deprecated: ``babyrobot_marl.animation`` moved to ``babyrobot_marl.play.screen``; this path goes in 0.3."""

import warnings

from .play.screen import (  # noqa: F401
    CLEAR_BELOW,
    CLEAR_SCREEN,
    CLEAR_TO_EOL,
    CURSOR_HOME,
    DEFAULT_DELAY,
    HIDE_CURSOR,
    SHOW_CURSOR,
    Display,
    animate,
    isatty,
)

warnings.warn(
    "babyrobot_marl.animation moved to babyrobot_marl.play.screen; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
