"""``python -m babyrobot_marl``: the same as the ``babyrobot-marl`` command."""

from .cli import main

raise SystemExit(main())
