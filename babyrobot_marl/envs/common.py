"""Argument checks shared by the env adapters: levels, rules, actions, render modes."""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Collection, Mapping
from typing import Any

from gymnasium.envs.registration import EnvSpec

from ..core.checks import ACTION_HELP, check_action, check_count, check_seed, unexpected_keyword  # noqa: F401
from ..core.outcomes import FINISHED, OUTCOME_NAMES, START  # noqa: F401
from ..core.rules import known_args, resolve_rules  # noqa: F401
from ..levels.resolve import resolve_level  # noqa: F401

check_positive_int = check_count


def check_render_mode(render_mode: str | None, modes: list[str]) -> str | None:
    if render_mode is not None and render_mode not in modes:
        raise ValueError(f"render_mode: must be None or one of {', '.join(map(repr, modes))}, got {render_mode!r}")
    return render_mode


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
