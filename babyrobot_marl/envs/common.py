"""Argument checks shared by the env adapters: levels, rules, actions, render modes."""

from __future__ import annotations

import dataclasses
import operator
import warnings
from collections.abc import Collection, Mapping, Sequence
from typing import Any

import numpy as np
from gymnasium.envs.registration import EnvSpec

from .. import levels
from ..checks import check_int
from ..core.actions import N_ACTIONS, Action
from ..core.engine import OUTCOMES
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


def unexpected_keyword(owner: str, name: object, known: Sequence[str], rule_names: Collection[str] = ()) -> TypeError:
    """Python's own ``TypeError`` for an unknown keyword argument, followed by the known ones."""
    where = f"{owner}.__init__()" if owner else "__init__()"
    text = f"{where} got an unexpected keyword argument {name!r}"
    if known:
        text += f"; arguments are {', '.join(known)}"
    if rule_names:
        text += f"; rule overrides are {', '.join(sorted(rule_names))}"
    return TypeError(text)


def known_args(owner: str, kwargs: Mapping[str, Any], known: Sequence[str]) -> None:
    """Unknown keywords: Python's own ``TypeError`` naming ``owner`` (rule overrides and ``known`` names pass through)."""
    unknown = sorted(set(kwargs) - RULE_NAMES - set(known), key=str)
    if unknown:
        raise unexpected_keyword(owner, unknown[0], known, RULE_NAMES)


def check_seed(seed: object, what: str = "seed") -> int | None:
    """``reset(seed=...)``: None or a non-negative integer (Python or numpy; bools and floats are not seeds).

    A local helper until the package-wide integer rule (``checks.check_int``) lands.
    """
    if seed is None:
        return None
    v: int | None = None
    if not isinstance(seed, (bool, np.bool_)):
        try:
            v = operator.index(seed)
        except TypeError:
            v = None
    if v is None or v < 0:
        raise ValueError(f"{what}: must be None or a non-negative integer, got {seed!r}")
    return v


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


def check_options(options: object, known: Collection[str] = ()) -> Mapping[str, Any]:
    """``reset(options=...)``: None or a dict; only the ``known`` keys are returned.

    An unknown key is a ``UserWarning`` naming the known ones, not an error: PettingZoo's and
    Gymnasium's own tests reset with arbitrary options (``{"options": 1}``). A known key's value
    is checked by the env.
    """
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise ValueError(f"options: expected a dict or None, got {type(options).__name__}")
    unknown = [k for k in options if k not in known]
    if not unknown:
        return options
    allowed = ", ".join(map(repr, known)) if known else "none"
    names = ", ".join(map(repr, unknown))
    # stacklevel 3: the line that called reset()
    warnings.warn(f"options: unknown option {names} ignored; known options are {allowed}", UserWarning, stacklevel=3)
    return {k: v for k, v in options.items() if k in known}


class OwnStepLimitSpec:
    """``env.spec.max_episode_steps`` is the step at which the env truncates itself.

    ``gymnasium.make`` sets ``env.unwrapped.spec`` after building the env, always with
    ``max_episode_steps=None`` (gymnasium 1.2.2 and 1.4.0: its own ``TimeLimit``, if any, wraps outside);
    this fills in the env's own limit, so ``TimeAwareObservation`` and
    ``TimeLimit(env, env.spec.max_episode_steps)`` read it. The registry keeps None: the limit
    depends on ``level=``, and a ``TimeLimit`` from the registry would cut larger levels short.
    """

    _spec: EnvSpec | None = None

    @property
    def own_step_limit(self) -> int:
        raise NotImplementedError

    @property
    def spec(self) -> EnvSpec | None:
        return self._spec

    @spec.setter
    def spec(self, spec: EnvSpec | None) -> None:
        if spec is not None and spec.max_episode_steps is None:
            spec = dataclasses.replace(spec, max_episode_steps=self.own_step_limit)
        self._spec = spec


# Info "outcome" codes: the engine's five, then the two the envs add. Ints so that tensor
# libraries can stack infos; names by code in OUTCOME_NAMES (exported as babyrobot_marl.OUTCOME_NAMES).
OUTCOME_NAMES = (*OUTCOMES, "start", "finished")
START, FINISHED = OUTCOME_NAMES.index("start"), OUTCOME_NAMES.index("finished")
