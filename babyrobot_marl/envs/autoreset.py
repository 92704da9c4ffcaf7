"""Auto-reset modes of the batch vector envs, named as Gymnasium names them, and their infos.

Gymnasium >= 1.1 has ``gymnasium.vector.AutoresetMode`` (``NEXT_STEP``, ``SAME_STEP``,
``DISABLED``); ``autoreset_mode=`` takes the enum or its value string (``"NextStep"``,
``"SameStep"``, ``"Disabled"``), as ``SyncVectorEnv`` does, and also ``"next-step"``,
``"same-step"``, ``"disabled"``. On gymnasium 1.0 (no enum) the mode is kept as its value string.
"""

from __future__ import annotations

from typing import Any

import numpy as np

try:  # gymnasium >= 1.1
    from gymnasium.vector import AutoresetMode
except ImportError:  # pragma: no cover - gymnasium 1.0
    AutoresetMode = None  # type: ignore[assignment,misc]

NEXT_STEP, SAME_STEP, DISABLED = "NextStep", "SameStep", "Disabled"
_ALIASES = {
    "nextstep": NEXT_STEP,
    "next-step": NEXT_STEP,
    "next_step": NEXT_STEP,
    "samestep": SAME_STEP,
    "same-step": SAME_STEP,
    "same_step": SAME_STEP,
    "disabled": DISABLED,
}


def resolve_autoreset_mode(mode: object) -> tuple[Any, str]:
    """``(the mode as Gymnasium's enum where it exists, its value string)``; else a ``ValueError``."""
    value = getattr(mode, "value", mode)
    name = _ALIASES.get(value.lower()) if isinstance(value, str) else None
    if name is None:
        raise ValueError(
            f"autoreset_mode: must be an AutoresetMode or one of 'next-step', 'same-step', 'disabled', got {mode!r}"
        )
    return (AutoresetMode(name) if AutoresetMode is not None else name), name


def set_reset_values(infos: dict[str, np.ndarray], slots: np.ndarray, start_code: int) -> None:
    """Give ``slots`` the values a fresh episode reports (as a single env's ``reset`` info), in place."""
    if not np.count_nonzero(slots):
        return
    infos["outcome"][slots] = start_code
    for key in ("intended", "blocked", "finished"):
        if key in infos:
            infos[key][slots] = False
    if "rank" in infos:
        infos["rank"][slots] = 0


def with_masks(values: dict[str, np.ndarray], mask: np.ndarray) -> dict[str, np.ndarray]:
    """Gymnasium's vector info form: each key and ``"_key"``, the slots that have it."""
    out: dict[str, np.ndarray] = {}
    for key, value in values.items():
        out[key] = value
        out[_MASK_KEYS.get(key) or f"_{key}"] = mask.copy()
    return out


_MASK_KEYS = {k: f"_{k}" for k in ("cell", "outcome", "intended", "blocked", "finished", "rank")}  # built once


def final_infos(obs: np.ndarray, values: dict[str, np.ndarray], done: np.ndarray) -> dict[str, Any]:
    """Same-step auto-reset: ``final_obs`` (an object array, as ``SyncVectorEnv`` gives) and
    ``final_info`` of the slots whose episode ended, each with its mask."""
    final_obs = np.full(len(done), None, dtype=object)
    for k in np.flatnonzero(done).tolist():
        final_obs[k] = obs[k]
    final = {key: np.where(done.reshape(-1, *([1] * (v.ndim - 1))), v, np.zeros_like(v)) for key, v in values.items()}
    return {"final_obs": final_obs, "_final_obs": done.copy(), "final_info": with_masks(final, done), "_final_info": done.copy()}
