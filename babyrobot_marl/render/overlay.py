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
| ``names`` | ``{robot: str}`` (robot number or agent name) | names in the race legend (e.g. the policies) |
| ``label`` | ``str`` | the colour bar's name (default ``value``, or ``action value``) |

The colour bar of the values is drawn in the panel whenever values or action values are shown,
with ticks and the overlay's label. All numbers of one overlay share one format, chosen from
its range (``Scale.format``): whole numbers from 10 up, else one decimal, two below 1; and with
state values one decimal where two values that differ would otherwise print alike.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np

from ..core.actions import N_ACTIONS
from ..core.checks import as_int
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
    names: Mapping[int, str] = field(default_factory=dict)
    label: str = ""

    @cached_property
    def scale(self) -> Scale | None:
        """The range the colour map spans (the finite state values', else the action values'),
        its label and the number format; None without numbers (computed once: the overlay is frozen)."""
        parts = [a for a in (self.values, None if self.q_values is None else self.q_values[:, :, 1:]) if a is not None]
        finite = [a[np.isfinite(a)] for a in parts]
        for arr, name in zip(finite, ("value", "action value") if self.values is not None else ("action value",)):
            if arr.size:
                digits = decimals(np.concatenate(finite), distinct=self.values is not None)
                return Scale(float(arr.min()), float(arr.max()), self.label or name, digits)
        return None

    @property
    def has_cells(self) -> bool:
        """Anything drawn in the cells (values, action values, arrows, text)."""
        return self.values is not None or self.q_values is not None or self.arrows is not None or bool(self.text)

    @property
    def empty(self) -> bool:
        return not self.has_cells and not self.panel and not self.names


def update_overlay(
    current: Overlay,
    level: Level,
    values: Any = KEEP,
    q_values: Any = KEEP,
    arrows: Any = KEEP,
    text: Any = KEEP,
    panel: Any = KEEP,
    names: Any = KEEP,
    n_robots: int = 1,
    label: Any = KEEP,
) -> Overlay:
    """``current`` with the given parts replaced (``None`` clears a part); ValueError naming a bad one."""
    h, w = level.height, level.width
    parts = {
        "values": current.values if values is KEEP else _values(values, (h, w)),
        "q_values": current.q_values if q_values is KEEP else _q_values(q_values, h, w),
        "arrows": current.arrows if arrows is KEEP else _arrows(arrows, h, w),
        "text": current.text if text is KEEP else _text(text, level),
        "panel": current.panel if panel is KEEP else _panel(panel),
        "names": current.names if names is KEEP else _names(names, n_robots),
        "label": current.label if label is KEEP else _label(label),
    }
    return Overlay(**parts)


def _numbers(arg: Any, name: str) -> np.ndarray:
    try:
        raw = np.asarray(arg)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected an array of real numbers, got {type(arg).__name__}") from None
    if raw.dtype == np.bool_:
        raise ValueError(f"{name}: expected numbers, got booleans")
    if raw.dtype.kind not in "iuf":  # strings, complex numbers, objects: not silently converted
        raise ValueError(f"{name}: expected an array of real numbers (int or float), got dtype {raw.dtype}")
    arr = raw.astype(np.float64)
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


def _names(arg: Any, n_robots: int) -> dict[int, str]:
    if arg is None:
        return {}
    if isinstance(arg, Sequence) and not isinstance(arg, str):
        arg = dict(enumerate(arg))
    if not isinstance(arg, Mapping):
        raise ValueError(f"names: expected a dict {{robot: name}} or a list of names, got {type(arg).__name__}")
    out = {}
    for key, s in arg.items():
        i = int(key.rsplit("_", 1)[1]) if isinstance(key, str) and key.startswith("robot_") and key[6:].isdigit() else key
        i = as_int(i)
        if i is None or not 0 <= i < n_robots:
            raise ValueError(f"names: keys are robot numbers 0..{n_robots - 1} or agent names robot_0.., got {key!r}")
        if not isinstance(s, str):
            raise ValueError(f"names: the name of robot {i} must be a str, got {type(s).__name__}")
        out[int(i)] = s
    return out


def _label(arg: Any) -> str:
    if arg is None:
        return ""
    if not isinstance(arg, str) or "\n" in arg:
        raise ValueError(f"label: expected one line of text (the colour bar's name), got {arg!r:.40}")
    return arg


def _panel(arg: Any) -> tuple[str, ...]:
    if arg is None:
        return ()
    if isinstance(arg, str):
        return tuple(arg.splitlines())
    if not isinstance(arg, Sequence) or not all(isinstance(s, str) for s in arg):
        raise ValueError(f"panel: expected a str or a list of str, got {type(arg).__name__}")
    return tuple(line for s in arg for line in (s.splitlines() or [""]))


# ---------------------------------------------------------------------- shared by both renderers
class Scale(NamedTuple):
    """What the colour bar shows: the range, its label, and the decimals every number of the overlay is written with."""

    lo: float
    hi: float
    label: str
    digits: int

    def format(self, v: float) -> str:
        return format_value(v, self.digits)


MAX_DIGITS = 1  # values that agree to this many decimals count as equal in a picture (as numpy prints them)


def decimals(values: np.ndarray, distinct: bool = True) -> int:
    """One format for all of an overlay's numbers: whole numbers when they all are or the largest
    is 10 or more, else one decimal, two when all are below 1; then, if ``distinct`` (a picture
    of state values, one number a cell), one decimal (``MAX_DIGITS``) if two values that differ
    would otherwise print as the same text (-8.8 and -9 as ``-9``). Action values alone keep
    the range's format: four share a cell, and wider numbers would not fit it."""
    big = float(np.abs(values).max()) if values.size else 0.0
    digits = 0 if big >= 10 or np.all(values == np.round(values)) else 1 if big >= 1 else 2
    if not distinct or big >= 1e15:  # (no decimal shows at this size)
        return digits
    apart = np.unique(np.round(values, MAX_DIGITS))
    while digits < MAX_DIGITS and len({format_value(float(v), digits) for v in apart}) < len(apart):
        digits += 1
    return digits


def format_value(v: float, digits: int = 0) -> str:
    """``v`` with ``digits`` decimals (no ``-0``)."""
    s = f"{v:.{digits}f}"
    return s[1:] if s.startswith("-") and float(s) == 0 else s
