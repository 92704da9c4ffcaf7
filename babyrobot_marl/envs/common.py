"""Deprecated: ``babyrobot_marl.envs.common`` was split (outcome codes to ``core.outcomes``, the argument
rules to ``core.checks``, ``resolve_rules`` to ``core.rules``, ``resolve_level`` to ``levels.resolve``, the
envs' own checks to ``envs.checks``, the spec to ``envs.spec``); this path goes in 0.3."""

import warnings

from ..core.checks import ACTION_HELP, check_action, check_seed, unexpected_keyword  # noqa: F401
from ..core.checks import check_count as check_positive_int  # noqa: F401
from ..core.outcomes import FINISHED, OUTCOME_NAMES, START  # noqa: F401
from ..core.rules import known_args, resolve_rules  # noqa: F401
from ..levels.resolve import resolve_level  # noqa: F401
from .checks import check_options, check_render_mode  # noqa: F401
from .spec import StepLimitSpec as OwnStepLimitSpec  # noqa: F401

warnings.warn(
    "babyrobot_marl.envs.common moved to babyrobot_marl.core.outcomes, core.checks, core.rules, levels.resolve, "
    "envs.checks and envs.spec; the old path goes in 0.3",
    DeprecationWarning,
    stacklevel=2,
)
