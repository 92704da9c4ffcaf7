"""What is drawn over the grid: state values, action values, policy arrows, text, a panel.

``Overlay`` is a frozen value; ``update_overlay`` checks what a user passes to
``env.unwrapped.set_overlay(...)`` and returns the new overlay. Arguments not given keep
their overlay, ``None`` clears one. Both ``rgb_array`` and the live canvas draw an ``Overlay``.

| argument | accepts | drawn as |
|---|---|---|
| ``values`` | numbers ``[H, W]`` (NaN: nothing) | the cell tinted by its value, the value printed |
| ``q_values`` | numbers ``[H, W, 5]`` by ``Action`` (STAY not drawn) or ``[H, W, 4]`` (N, E, S, W) | four tinted triangles |
| ``arrows`` | ints ``[H, W]`` (one ``Action``, 0 or -1: none) or bools ``[H, W, 5]`` / ``[H, W, 4]`` | an arrow per direction |
| ``text`` | ``{(x, y): str}`` | the text in the cell |
| ``panel`` | ``str`` or list of ``str`` | lines below the grid |
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.level import Level, as_cell

KEEP: Any = object()  # "not given": the overlay keeps what it has


@dataclass(frozen=True, eq=False)
class Overlay:
    """Read-only arrays (``None``: not drawn)."""

    values: np.ndarray | None = None  # float64[H, W]
    q_values: np.ndarray | None = None  # float64[H, W, 5]
    arrows: np.ndarray | None = None  # bool[H, W, 5]
    text: Mapping[tuple[int, int], str] = field(default_factory=dict)
    panel: tuple[str, ...] = ()

    @property
    def empty(self) -> bool:
        return self.values is None and self.q_values is None and self.arrows is None and not self.text and not self.panel


def update_overlay(
    current: Overlay,
    level: Level,
    values: Any = KEEP,
    q_values: Any = KEEP,
    arrows: Any = KEEP,
    text: Any = KEEP,
    panel: Any = KEEP,
) -> Overlay:
    """``current`` with the given parts replaced (``None`` clears a part); ValueError naming a bad one."""
    h, w = level.height, level.width
    parts = {
        "values": current.values if values is KEEP else _values(values, (h, w)),
        "q_values": current.q_values if q_values is KEEP else _q_values(q_values, h, w),
        "arrows": current.arrows if arrows is KEEP else _arrows(arrows, h, w),
        "text": current.text if text is KEEP else _text(text, level),
        "panel": current.panel if panel is KEEP else _panel(panel),
    }
    return Overlay(**parts)


def _numbers(arg: Any, name: str) -> np.ndarray:
    try:
        arr = np.array(arg, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected an array of numbers, got {type(arg).__name__}") from None
    if np.asarray(arg).dtype == np.bool_:
        raise ValueError(f"{name}: expected numbers, got booleans")
    if np.isinf(arr).any():
        raise ValueError(f"{name}: values must be finite (NaN marks a cell with no value)")
    return arr


def _values(arg: Any, shape: tuple[int, int]) -> np.ndarray | None:
    if arg is None:
        return None
    arr = _numbers(arg, "values")
    if arr.shape != shape:
        raise ValueError(f"values: expected shape {shape} (height, width), got {arr.shape}")
    arr.setflags(write=False)
    return arr


def _q_values(arg: Any, h: int, w: int) -> np.ndarray | None:
    if arg is None:
        return None
    arr = _numbers(arg, "q_values")
    if arr.shape == (h, w, N_ACTIONS - 1):  # the four moves only: put STAY (not drawn) in front
        arr = np.concatenate([np.full((h, w, 1), np.nan), arr], axis=2)
    if arr.shape != (h, w, N_ACTIONS):
        raise ValueError(f"q_values: expected shape {(h, w, N_ACTIONS)} (by Action) or {(h, w, N_ACTIONS - 1)}, got {arr.shape}")
    arr.setflags(write=False)
    return arr


def _arrows(arg: Any, h: int, w: int) -> np.ndarray | None:
    if arg is None:
        return None
    arr = np.asarray(arg)
    if arr.dtype == np.bool_:
        if arr.shape == (h, w, N_ACTIONS - 1):
            arr = np.concatenate([np.zeros((h, w, 1), dtype=bool), arr], axis=2)
        if arr.shape != (h, w, N_ACTIONS):
            raise ValueError(
                f"arrows: booleans need shape {(h, w, N_ACTIONS)} (by Action) or {(h, w, N_ACTIONS - 1)}, got {arr.shape}"
            )
        out = arr.copy()
    elif arr.dtype.kind in "iu":
        if arr.shape != (h, w):
            raise ValueError(f"arrows: one action per cell needs shape {(h, w)}, got {arr.shape}")
        if ((arr < -1) | (arr >= N_ACTIONS)).any():
            raise ValueError(f"arrows: actions must be in -1..{N_ACTIONS - 1} (-1 or 0: no arrow)")
        out = np.zeros((h, w, N_ACTIONS), dtype=bool)
        ys, xs = np.nonzero(arr > 0)
        out[ys, xs, arr[ys, xs]] = True
    else:
        raise ValueError(f"arrows: expected integer actions [{h}, {w}] or booleans [{h}, {w}, 5], got dtype {arr.dtype}")
    out[:, :, 0] = False  # STAY has no arrow
    out.setflags(write=False)
    return out


def _text(arg: Any, level: Level) -> dict[tuple[int, int], str]:
    if arg is None:
        return {}
    if not isinstance(arg, Mapping):
        raise ValueError(f"text: expected a dict {{(x, y): str}}, got {type(arg).__name__}")
    out = {}
    for cell, s in arg.items():
        x, y = as_cell(cell, "text")
        if not (0 <= x < level.width and 0 <= y < level.height):
            raise ValueError(f"text: cell {(x, y)} is outside the {level.width}x{level.height} grid")
        if not isinstance(s, str):
            raise ValueError(f"text: the text of cell {(x, y)} must be a str, got {type(s).__name__}")
        out[(x, y)] = s
    return out


def _panel(arg: Any) -> tuple[str, ...]:
    if arg is None:
        return ()
    if isinstance(arg, str):
        return tuple(arg.splitlines())
    if not isinstance(arg, Sequence) or not all(isinstance(s, str) for s in arg):
        raise ValueError(f"panel: expected a str or a list of str, got {type(arg).__name__}")
    return tuple(line for s in arg for line in (s.splitlines() or [""]))


# ---------------------------------------------------------------------- shared by both renderers
def value_colours(values: np.ndarray, low: tuple[int, int, int], high: tuple[int, int, int]) -> np.ndarray:
    """``uint8[..., 3]``: each finite value placed between ``low`` (the minimum) and ``high``
    (the maximum) of the finite values; all equal: the middle colour."""
    finite = np.isfinite(values)
    lo = float(values[finite].min()) if finite.any() else 0.0
    hi = float(values[finite].max()) if finite.any() else 0.0
    t = np.full(values.shape, 0.5) if hi == lo else (np.where(finite, values, lo) - lo) / (hi - lo)
    a, b = np.array(low, dtype=np.float64), np.array(high, dtype=np.float64)
    return np.rint(a + (b - a) * t[..., None]).astype(np.uint8)


def format_value(v: float) -> str:
    """A value short enough for a cell: ``-12``, ``-3.5``, ``0.25``."""
    if abs(v) >= 100 or float(v).is_integer():
        return f"{v:.0f}"
    if abs(v) >= 10:
        return f"{v:.0f}"
    return f"{v:.1f}" if abs(v) >= 1 else f"{v:.2f}".replace("0.", ".", 1)
