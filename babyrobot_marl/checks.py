"""Deprecated: ``babyrobot_marl.checks`` moved to ``babyrobot_marl.core.checks`` (the frame limits to
``babyrobot_marl.render.checks``); this path goes in 0.3."""

import warnings

from .cli.checks import MAX_RACES  # noqa: F401
from .core.checks import (  # noqa: F401
    ACTION_HELP,
    MAX_BATCH_ENVS,
    MAX_BATCH_OBS,
    MAX_BATCH_ROBOTS,
    MAX_DENSE_STATES,
    MAX_LEVEL_CELLS,
    MAX_LEVEL_TEXT_CHARS,
    MAX_NEAREST_K,
    as_int,
    check_action,
    check_batch,
    check_choice,
    check_count,
    check_dense_states,
    check_global_view,
    check_int,
    check_level_size,
    check_nearest_k,
    check_real,
    check_seed,
    check_view_numbers,
    check_view_radius,
    real_array,
    shown,
)
from .render.checks import MAX_FRAME_PIXELS, check_frame_pixels, max_cell_size  # noqa: F401

warnings.warn(
    "babyrobot_marl.checks moved to babyrobot_marl.core.checks (frame limits: babyrobot_marl.render.checks); "
    "the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
