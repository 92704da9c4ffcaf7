"""Learning on Baby Robot: tabular TD control (numpy only), the fast PPO trainer, and deep RL with
Stable-Baselines3.

``tabular`` needs nothing beyond numpy. ``ppo`` (PPO stepped on the batch engine, one robot or a
race with one shared policy; ``policy``: trained policies as robots, saved and loaded;
``evaluate``: races against scripted robots on the batch engine; ``checks``: the settings' and saved
policies' checks; the ``train`` command is ``babyrobot_marl.cli.train``),
``single`` (SB3 PPO/DQN on BabyRobot-v0) and ``race`` (one shared SB3 PPO policy for all robots
through SuperSuit) need the ``train`` extra, torch first from PyTorch's CPU index (plain PyPI's torch is
the ~3 GB CUDA build): ``pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu``, then
``pip install 'babyrobot_marl[train]'``. They import it inside their functions, and ``require_train()``
says clearly what is missing.
"""

from .deps import MissingTrainExtraError, require_train
from .tabular import TabularResult, q_learning, sarsa

__all__ = ["MissingTrainExtraError", "TabularResult", "q_learning", "require_train", "sarsa"]
