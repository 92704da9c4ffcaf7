"""Play it yourself: drive Baby Robot from the keyboard, race the scripted robots, build levels.

- ``game``: one key, one step, over a ``BabyRobotEnv`` or a ``RaceEnv`` (shared by terminal and notebook);
- ``terminal``: ``babyrobot-marl play --policy keys`` and ``race --human N``;
- ``screen``: text frames redrawn in place on a terminal (``animate``, ``draw``);
- ``watch``: the pace of a watched race (full speed where places are decided, fast forward elsewhere);
- ``editor``: the level editor's state as pure functions over a grid of characters;
- ``notebook``: the notebook player and level editor (``from babyrobot_marl.play import notebook``;
  ``notebook.play`` / ``.edit``), which need the ``notebook`` extra;
- ``checks``: the play layer's argument checks.

Which key does what is ``babyrobot_marl.envs.keys`` (the envs' ``get_keys_to_action`` reads it).

Nothing here is imported by ``import babyrobot_marl``.
"""
