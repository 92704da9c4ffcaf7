"""Deprecated: ``babyrobot_marl.play.keys`` moved to ``babyrobot_marl.envs.keys``; this path goes in 0.3."""

import warnings

from ..envs.keys import (  # noqa: F401
    BROWSER_KEYS,
    HELP,
    QUIT,
    RESTART,
    SDL_K_DOWN,
    SDL_K_LEFT,
    SDL_K_RIGHT,
    SDL_K_UP,
    SWITCH,
    TERMINAL_KEYS,
    Command,
    decode,
    keys_to_action,
)

warnings.warn(
    "babyrobot_marl.play.keys moved to babyrobot_marl.envs.keys; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
