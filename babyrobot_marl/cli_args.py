"""Deprecated: the command line's argument types moved to ``babyrobot_marl.cli.checks``; this path goes in 0.3."""

import warnings

from .cli.checks import (
    MAX_RACES,
    int_at_least,
    int_in,
    non_negative_float,
    non_negative_int,
    output_path,
    policy_list,
    policy_spec,
    positive_float,
    positive_int,
    probability,
    race_count,
    seconds,
    unit_real,
)

warnings.warn("babyrobot_marl.cli_args moved to babyrobot_marl.cli.checks; the old path goes in 0.3",
              DeprecationWarning, stacklevel=2)

__all__ = ["MAX_RACES", "int_at_least", "int_in", "non_negative_float", "non_negative_int", "output_path", "policy_list",
           "policy_spec", "positive_float", "positive_int", "probability", "race_count", "seconds", "unit_real"]
