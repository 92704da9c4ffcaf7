"""Deprecated: ``babyrobot_marl.encodings`` moved to ``babyrobot_marl.envs.encodings``; this path goes in 0.3."""

import warnings

from .envs.checks import check_encoding  # noqa: F401
from .envs.encodings import ENCODINGS, Encoder  # noqa: F401

warnings.warn(
    "babyrobot_marl.encodings moved to babyrobot_marl.envs.encodings; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
