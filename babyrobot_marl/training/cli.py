"""Deprecated: the ``train`` command moved to ``babyrobot_marl.cli.train`` (``add_train_parser`` is its
``add_parser``, ``cmd_train`` its ``run``); this path goes in 0.3."""

import warnings

from ..cli.train import BACKENDS, FAST_ROLLOUT, KNOBS, RACE_TARGET, SB3_RACE_ROLLOUT, SB3_ROLLOUT
from ..cli.train import add_parser as add_train_parser
from ..cli.train import run as cmd_train

warnings.warn("babyrobot_marl.training.cli moved to babyrobot_marl.cli.train; the old path goes in 0.3",
              DeprecationWarning, stacklevel=2)

__all__ = ["BACKENDS", "FAST_ROLLOUT", "KNOBS", "RACE_TARGET", "SB3_RACE_ROLLOUT", "SB3_ROLLOUT", "add_train_parser",
           "cmd_train"]
