"""Outcome codes: what happened to a robot in a step (``info["outcome"]``).

The engine's five come first (MOVED and STAYED first: "intended" is ``<= STAYED``), then the two
the envs add. Ints, so that tensor libraries can stack infos; the names by code are
``OUTCOME_NAMES`` (exported as ``babyrobot_marl.OUTCOME_NAMES``).
"""

from __future__ import annotations

MOVED, STAYED, BUMPED, SKIDDED, GLASS = range(5)
OUTCOMES = ("moved", "stayed", "bumped", "skidded", "glass")

OUTCOME_NAMES = (*OUTCOMES, "start", "finished")
START, FINISHED = OUTCOME_NAMES.index("start"), OUTCOME_NAMES.index("finished")
