"""Rules: the rewards and probabilities of a step, separate from the map they apply to."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields, replace
from typing import Any

from .checks import check_choice, check_real, unexpected_keyword

COLLISION_MODES = ("block", "bounce", "pass", "soft")

_PROBABILITIES = ("small_puddle_move_prob", "large_puddle_move_prob", "glass_pass_prob")


@dataclass(frozen=True)
class Rules:
    """Rewards per cell kind and the probabilities of skids and glass walls.

    =========================  =======  ===================================================
    field                      default  meaning
    =========================  =======  ===================================================
    ``floor_reward``           -1.0     entering (or staying in) a floor cell
    ``small_puddle_reward``    -2.0     entering (or staying in) a small puddle ``p``
    ``large_puddle_reward``    -4.0     entering (or staying in) a large puddle ``P``
    ``exit_reward``            0.0      the step that reaches an exit
    ``small_puddle_move_prob`` 0.6      a move out of a small puddle goes where intended
    ``large_puddle_move_prob`` 0.4      a move out of a large puddle goes where intended
    ``glass_pass_prob``        0.5      a move through a glass wall ``*`` gets through
    ``collisions``             "block"  race collision mode: "block", "bounce", "pass" or "soft"
    ``win_bonus``              10.0     race: added to the reward of the first finisher(s)
    =========================  =======  ===================================================

    A skid (probability ``1 - move_prob``) takes the robot to one of the *other* open
    neighbours of its puddle (open edge, no glass, not blocked), uniformly; with none it stays.
    """

    floor_reward: float = -1.0
    small_puddle_reward: float = -2.0
    large_puddle_reward: float = -4.0
    exit_reward: float = 0.0
    small_puddle_move_prob: float = 0.6
    large_puddle_move_prob: float = 0.4
    glass_pass_prob: float = 0.5
    collisions: str = "block"
    win_bonus: float = 10.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "collisions":
                check_choice(value, "collisions", COLLISION_MODES)
                continue
            value = check_real(value, f.name)  # 10**400 too: a ValueError naming the field, not OverflowError
            if f.name in _PROBABILITIES and not 0.0 <= value <= 1.0:
                raise ValueError(f"{f.name}: is a probability and must lie in [0, 1], got {value!r}")
            object.__setattr__(self, f.name, value)

    def replace(self, **overrides: Any) -> Rules:
        """A copy with some fields changed; unknown names are an error listing the known ones."""
        unknown = sorted(set(overrides) - RULE_NAMES)
        if unknown:
            raise TypeError(f"unknown rule {unknown[0]!r}; rules are: {', '.join(sorted(RULE_NAMES))}")
        return replace(self, **overrides)


RULE_NAMES = frozenset(f.name for f in fields(Rules))


def resolve_rules(
    rules: Rules | Mapping[str, Any] | None, overrides: Mapping[str, Any], owner: str = "", known: Sequence[str] = ()
) -> Rules:
    """``Rules`` from a ``Rules``, a dict or ``None`` (defaults), with keyword overrides on top.

    An override that is no rule is a ``TypeError`` in Python's own wording for ``owner``'s
    ``__init__`` (TorchRL's ``GymEnv`` matches on it to drop ``frameskip=``), then the known names.
    """
    if rules is None:
        base = Rules()
    elif isinstance(rules, Rules):
        base = rules
    elif isinstance(rules, Mapping):
        bad = [k for k in rules if not isinstance(k, str)]
        if bad:
            raise TypeError(f"rules: keys are rule names (str), got {bad[0]!r}; rules are: {', '.join(sorted(RULE_NAMES))}")
        base = Rules().replace(**rules)
    else:
        raise TypeError(f"rules: expected a Rules, a dict of rule values or None, got {type(rules).__name__}")
    unknown = sorted(set(overrides) - RULE_NAMES, key=str)
    if unknown:
        raise unexpected_keyword(owner, unknown[0], known, RULE_NAMES)
    return base.replace(**overrides) if overrides else base


def known_args(owner: str, kwargs: Mapping[str, Any], known: Sequence[str]) -> None:
    """Unknown keywords: Python's own ``TypeError`` naming ``owner`` (rule overrides and ``known`` names pass through)."""
    unknown = sorted(set(kwargs) - RULE_NAMES - set(known), key=str)
    if unknown:
        raise unexpected_keyword(owner, unknown[0], known, RULE_NAMES)
