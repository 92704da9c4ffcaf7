"""Bridges to training frameworks, each imported on its own (``babyrobot_marl.integrations.rllib``).

Nothing here is imported by ``import babyrobot_marl``: a bridge needs its framework installed
(``pip install -e ".[rllib]"`` for Ray RLlib).
"""
