"""Deprecated: ``babyrobot_marl.level_sources`` moved to ``babyrobot_marl.levels.sources``; this path goes in 0.3."""

import warnings

from .levels.sources import FAMILY_SEEDS, LevelSource, level_source, maze_family  # noqa: F401

warnings.warn(
    "babyrobot_marl.level_sources moved to babyrobot_marl.levels.sources; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
