"""The ``babyrobot-marl`` command: list and show levels, watch an episode in the terminal.

::

    babyrobot-marl levels                      # the built-in levels: size, starts, exits, features
    babyrobot-marl levels maze-8x8             # one level's text (also: --show NAME, or a file path)
    babyrobot-marl play --level walls --policy shortest --seed 0
    babyrobot-marl race --level race-4 --robots 4 --policies shortest,shortest,random,random
    python -m babyrobot_marl play --level default --policy random --no-delay
    babyrobot-marl solve --level puddles       # value iteration: the value grid and the policy arrows
    babyrobot-marl train --level maze-8x8 --steps 3000000 --save ppo.pt  # PPO (the 'train' extra)
    babyrobot-marl play --level maze-8x8 --policy ppo.pt       # replay a saved policy

Each command is a module of this package (``levels``, ``play``, ``race``, ``solve``, ``train``) with
``add_parser(sub)``, which registers its arguments, and ``run(args, out)``, its handler; ``main``
builds the parser from them. The shared pieces (``--level``, ``--seed``, the display options;
``play.screen.animate`` shows the frames) are in ``common``, so that further commands reuse them.

Bad input (an unknown level or policy, a negative seed, a bad delay, a broken level file, a
directory or FIFO or device given as a level, a level past the size limits) ends with exit
status 2 and one line on stderr, ``babyrobot-marl: error: ...``, never a traceback. Argument
types and the checks across arguments live in ``cli.checks``, level loading (bounded file reads) in
``levels.files``.
"""

from .entry import build_parser, main

__all__ = ["build_parser", "main"]
