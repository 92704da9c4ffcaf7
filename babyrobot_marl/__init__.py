"""Baby Robot: a grid world for learning and researching RL, alone or with many robots.

``import babyrobot_marl`` registers ``babyrobot_marl/BabyRobot-v0`` with Gymnasium.
"""

from __future__ import annotations

import gymnasium

from . import levels
from .core import Action, Level, Rules, compile_level
from .envs.single import BabyRobotEnv

__version__ = "0.1.0"


def _register() -> None:
    if "babyrobot_marl/BabyRobot-v0" not in gymnasium.registry:
        gymnasium.register(id="babyrobot_marl/BabyRobot-v0", entry_point="babyrobot_marl.envs.single:BabyRobotEnv")


_register()

__all__ = ["Action", "BabyRobotEnv", "Level", "Rules", "__version__", "compile_level", "levels"]
