"""Argument checks shared by the env adapters: levels, rules, actions, render modes."""

from __future__ import annotations

import operator
from collections.abc import Mapping
from typing import Any

import numpy as np

from .. import levels
from ..checks import check_int
from ..core.actions import N_ACTIONS, Action
from ..core.level import Level, looks_like_level_text
from ..core.rules import RULE_NAMES, Rules

ACTION_HELP = ", ".join(f"{a.value}={a.name}" for a in Action)


def resolve_level(level: str | Level) -> Level:
    """A ``Level`` from a built-in name, a level text (several lines) or a ``Level``."""
    if isinstance(level, Level):
        return level
    if isinstance(level, str):
        return Level.from_ascii(level) if looks_like_level_text(level) else levels.get(level)
    raise TypeError(f"level: expected a level name, a level text or a Level, got {type(level).__name__}")


def resolve_rules(rules: Rules | Mapping[str, Any] | None, overrides: Mapping[str, Any], known: str = "") -> Rules:
    """``Rules`` from a ``Rules``, a dict or ``None`` (defaults), with keyword overrides on top."""
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
    unknown = sorted(set(overrides) - RULE_NAMES)
    if unknown:
        raise TypeError(
            f"unknown argument {unknown[0]!r}; {known + '; ' if known else ''}rule overrides are: {', '.join(sorted(RULE_NAMES))}"
        )
    return base.replace(**overrides) if overrides else base


def check_action(action: object, what: str = "action") -> int:
    """An action as a Python int in 0..4; anything else is a ``ValueError`` naming ``what``."""
    if type(action) is not int:
        if isinstance(action, (bool, np.bool_)) or getattr(getattr(action, "dtype", None), "kind", "") == "b":
            raise ValueError(f"{what}: expected an integer action ({ACTION_HELP}), got the bool {action!r}")
        try:
            action = operator.index(action)  # numpy integers and 0-d integer arrays
        except TypeError:
            raise ValueError(
                f"{what}: expected an integer action ({ACTION_HELP}), got {action!r} of type {type(action).__name__}"
            ) from None
    if not 0 <= action < N_ACTIONS:
        raise ValueError(f"{what}: must be an integer in 0..{N_ACTIONS - 1} ({ACTION_HELP}), got {action}")
    return action


def check_render_mode(render_mode: str | None, modes: list[str]) -> str | None:
    if render_mode is not None and render_mode not in modes:
        raise ValueError(f"render_mode: must be None or one of {', '.join(map(repr, modes))}, got {render_mode!r}")
    return render_mode


def check_positive_int(value: object, what: str) -> int:
    """A count such as ``max_steps``: an integer >= 1 (numpy integers too, bools not)."""
    return check_int(value, what, lo=1)


def check_options(options: object) -> Mapping[str, Any]:
    """``reset(options=...)``: None or a dict."""
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise ValueError(f"options: expected a dict or None, got {type(options).__name__}")
    return options
