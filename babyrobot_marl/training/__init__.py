"""Learning on Baby Robot: tabular TD control (numpy only) and deep RL with Stable-Baselines3.

``tabular`` needs nothing beyond numpy. ``single`` (PPO/DQN on BabyRobot-v0) and ``race`` (one
shared PPO policy for all robots through SuperSuit) need the ``train`` extra (GIFs of the
learnt policy: ``babyrobot_marl.render.video``, whose imageio the extra brings)
(``pip install 'babyrobot_marl[train]'``); they import it inside their functions, and
``require_train()`` says clearly what is missing.
"""

from .deps import MissingTrainExtraError, require_train
from .tabular import TabularResult, q_learning, sarsa

__all__ = ["MissingTrainExtraError", "TabularResult", "q_learning", "require_train", "sarsa"]
