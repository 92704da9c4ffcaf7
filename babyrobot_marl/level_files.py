"""Deprecated: ``babyrobot_marl.level_files`` moved to ``babyrobot_marl.levels.files``; this path goes in 0.3."""

import warnings

from .levels.checks import PATH_SHOWN  # noqa: F401
from .levels.files import load_level, read_level_file  # noqa: F401

warnings.warn(
    "babyrobot_marl.level_files moved to babyrobot_marl.levels.files; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
