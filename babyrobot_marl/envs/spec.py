"""``env.spec`` with the env's own step limit: a data descriptor the Gymnasium envs hold.

``gymnasium.make`` sets ``env.unwrapped.spec`` after building the env, always with
``max_episode_steps=None`` (gymnasium 1.2.2 and 1.4.0: its own ``TimeLimit``, if any, wraps outside);
this fills in the env's own limit (``env.own_step_limit``, the step at which the env truncates
itself), so ``TimeAwareObservation`` and ``TimeLimit(env, env.spec.max_episode_steps)`` read it.
The registry keeps None: the limit depends on ``level=``, and a ``TimeLimit`` from the registry
would cut larger levels short.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from gymnasium.envs.registration import EnvSpec


class StepLimitSpec:
    """``spec = StepLimitSpec()`` in an env's class body; the value is kept in ``env._spec``.

    Through plain attributes, never ``env.__dict__``: on CPython 3.11+ touching an instance's
    ``__dict__`` turns off the fast path for every attribute of that instance (``step`` ran 40%
    slower once ``gymnasium.make`` had set the spec)."""

    def __get__(self, env: Any, owner: type | None = None) -> Any:
        if env is None:
            return self
        return getattr(env, "_spec", None)

    def __set__(self, env: Any, spec: EnvSpec | None) -> None:
        if spec is not None and spec.max_episode_steps is None:
            spec = dataclasses.replace(spec, max_episode_steps=env.own_step_limit)
        env._spec = spec
