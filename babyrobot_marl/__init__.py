"""Baby Robot: a grid world for learning and researching RL, alone or with many robots.

``import babyrobot_marl`` registers ``babyrobot_marl/BabyRobot-v0`` with Gymnasium.
"""

from __future__ import annotations

import gymnasium

from . import levels
from .core import Action, Level, Rules, compile_level
from .core.outcomes import OUTCOME_NAMES
from .envs import encodings
from .envs.encodings import ENCODINGS
from .envs.race_gym import BabyRobotRaceEnv
from .envs.single import BabyRobotEnv
from .envs.vector import sb3_vec_env

__version__ = "0.1.0"


def _register() -> None:
    gym_ids = {
        "babyrobot_marl/BabyRobot-v0": "babyrobot_marl.envs.single:BabyRobotEnv",
        "babyrobot_marl/BabyRobotRace-v0": "babyrobot_marl.envs.race_gym:BabyRobotRaceEnv",
    }
    vector_ids = {"babyrobot_marl/BabyRobot-v0": "babyrobot_marl.envs.vector:BabyRobotVectorEnv"}
    for env_id, entry_point in gym_ids.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point, vector_entry_point=vector_ids.get(env_id))
    try:  # PettingZoo >= 1.26 has a registry; older versions have none
        import pettingzoo
    except ImportError:
        return
    if hasattr(pettingzoo, "register") and "babyrobot_marl/Race-v0" not in pettingzoo.parallel_registry:
        pettingzoo.register("parallel", "babyrobot_marl/Race-v0", entry_point="babyrobot_marl.race_v0:parallel_env")
        pettingzoo.register("aec", "babyrobot_marl/Race-v0", entry_point="babyrobot_marl.race_v0:env")


_register()

from . import race_v0  # noqa: E402  (after registering: babyrobot_marl.race_v0 is an attribute, as PettingZoo modules are)

__all__ = [
    "Action",
    "BabyRobotEnv",
    "BabyRobotRaceEnv",
    "ENCODINGS",
    "Level",
    "OUTCOME_NAMES",
    "Rules",
    "__version__",
    "compile_level",
    "encodings",
    "levels",
    "race_v0",
    "sb3_vec_env",
]
