"""Play it yourself: drive Baby Robot from the keyboard, race the scripted robots, build levels.

- ``keys``: which key does what (terminal, browser, ``gymnasium.utils.play``);
- ``game``: one key, one step, over a ``BabyRobotEnv`` or a ``RaceEnv`` (shared by terminal and notebook);
- ``terminal``: ``babyrobot-marl play --policy keys`` and ``race --human N``;
- ``watch``: the pace of a watched race (full speed where places are decided, fast forward elsewhere);
- ``editor``: the level editor's state as pure functions over a grid of characters;
- ``notebook``: the notebook player and level editor (``babyrobot_marl.notebook.play`` / ``.edit``),
  which need the ``notebook`` extra.

Nothing here is imported by ``import babyrobot_marl``.
"""
