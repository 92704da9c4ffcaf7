"""The renderer's argument checks and its size limits: frame pixels, cell sizes, frame rates, frames.

The rules for integers and reals are the core's (``core.checks``); this module only says what the
renderer allows and in which words.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..core.checks import check_int, check_real
from ..core.level import Level
from . import annotate
from .overlay import Overlay
from .panel import _wrapped, metrics, panel_height

MAX_FRAME_PIXELS = 4096 * 4096  # an rgb_array frame (48 MB of RGB): a 256x256 maze at 16-pixel cells
MIN_CELL_SIZE, MAX_CELL_SIZE = 8, 256
DEFAULT_MAX_CELL, COLUMN_WIDTH, COLUMN_HEIGHT = 64, 896, 768  # a notebook column
MAX_ANIMATION_FRAMES = 60


def check_frame_pixels(width: int, height: int, what: str = "cell_size", hint: str = "use a smaller cell_size") -> None:
    """An image of ``width x height`` pixels is within ``MAX_FRAME_PIXELS`` (checked before allocating it)."""
    if width * height > MAX_FRAME_PIXELS:
        raise ValueError(
            f"{what}: the frame would be {width}x{height} = {width * height:,} pixels, more than the limit of "
            f"{MAX_FRAME_PIXELS:,} ({3 * MAX_FRAME_PIXELS // 10**6} MB of RGB); {hint}"
        )


def max_cell_size(width_cells: int, height_cells: int, extra_height_px: int = 0) -> int:
    """The largest cell size (pixels) whose frame of ``width_cells x height_cells`` (plus a panel) fits the limit."""
    size = math.isqrt(MAX_FRAME_PIXELS // max(1, width_cells * height_cells))
    while size > 0 and size * width_cells * (size * height_cells + extra_height_px) > MAX_FRAME_PIXELS:
        size -= 1
    return size


def auto_cell_size(level: Level) -> int:
    """About 64-pixel cells, smaller for large levels so the grid fits a notebook column."""
    return int(np.clip(min(COLUMN_WIDTH // level.width, COLUMN_HEIGHT // level.height), MIN_CELL_SIZE, DEFAULT_MAX_CELL))


def check_cell_size(cell_size: object, level: Level | None = None) -> int | None:
    """``cell_size`` as an int in ``MIN_CELL_SIZE..MAX_CELL_SIZE`` (None: chosen for the level)."""
    if cell_size is None:
        return auto_cell_size(level) if level is not None else None
    cs = check_int(
        cell_size,
        "cell_size",
        MIN_CELL_SIZE,
        MAX_CELL_SIZE,
        message="{name}: must be None (about 64, fitted to the level) or an integer in {lo}..{hi} (pixels), got {value}",
    )
    if level is not None:
        check_frame_size(level, cs)
    return cs


def check_frame_size(level: Level, cs: int, lines: Sequence[str] = (), bar: bool = False, robots: int = 0) -> None:
    """The whole frame, the grid and the panel under it (``lines`` of text, the colour ``bar``, the
    legend of ``robots``), is within ``MAX_FRAME_PIXELS``; else a ``ValueError`` naming what to
    change: the panel's lines when the frame fits without them, else ``cell_size``. Checked from
    the sizes alone, before anything is drawn."""
    width, grid = level.width * cs, level.height * cs
    height = grid + panel_height(width, cs, lines, bar, robots)
    if width * height <= MAX_FRAME_PIXELS:
        return
    rest = grid + panel_height(width, cs, (), bar, robots)
    if lines and width * rest <= MAX_FRAME_PIXELS:
        line_h = metrics(cs).line_h
        room = (MAX_FRAME_PIXELS // width - rest) // line_h
        raise ValueError(
            f"panel: {len(lines):,} lines ({_wrapped_count(width, cs, lines):,} wrapped to the frame's width) make a "
            f"{width}x{height:,} frame, over the limit of {MAX_FRAME_PIXELS:,} pixels; at cell_size {cs} at most "
            f"{room:,} wrapped lines fit: show fewer or shorter lines"
        )
    below = [what for what, on in (("the colour bar", bar), (f"the legend of {robots:,} robots", robots)) if on]
    fit = _largest_fit(level, cs, bar, robots)
    way = f"use cell_size <= {fit} (or None)" if fit >= MIN_CELL_SIZE else (
        "no cell_size fits it (the legend is too wide a strip): use render_mode='ansi' or None")  # fmt: skip
    raise ValueError(
        f"cell_size: a {level.width}x{level.height} level at {cs} pixels a cell"
        + (f" with {' and '.join(below)} below" if below else "")
        + f" is a {width}x{height} frame, over the limit of {MAX_FRAME_PIXELS:,} pixels; {way}"
    )


def _largest_fit(level: Level, cs: int, bar: bool, robots: int) -> int:
    """The largest cell size below ``cs`` whose grid, bar and legend fit the limit (< MIN_CELL_SIZE: none)."""
    c = min(cs - 1, math.isqrt(MAX_FRAME_PIXELS // (level.width * level.height)))
    while c >= MIN_CELL_SIZE:
        w = level.width * c
        if w * (level.height * c + panel_height(w, c, (), bar, robots)) <= MAX_FRAME_PIXELS:
            break
        c -= 1
    return c


def _wrapped_count(width: int, cs: int, lines: Sequence[str]) -> int:
    m = metrics(cs)
    return len(_wrapped(tuple(lines), width - 2 * m.pad, m.size))


def check_overlay_frame(level: Level, cs: int, overlay: Overlay, robots: int = 0) -> None:
    """``check_frame_size`` for the frame of ``overlay`` (``robots``: a race's legend)."""
    check_frame_size(level, cs, overlay.panel, annotate.value_range(overlay) is not None, robots)


def check_animation_frames(n: object) -> int:
    return check_int(n, "animation_frames (0: no animation)", 0, MAX_ANIMATION_FRAMES)


def check_fps(fps: object, name: str = "render_fps") -> float:
    """Steps per second of the live canvas: a finite number >= 0 (0: no pacing)."""
    return check_real(fps, name, 0, message="{name}: must be a finite number >= 0 (steps per second; 0: no pacing), got {value}")


def check_video_fps(fps: object) -> float:
    """Frames per second of a GIF or video: a number in (0, 100]."""
    return check_real(fps, "fps", 0, 100, open_lo=True, message="{name}: must be a number in (0, 100], got {value}")


def check_frames(frames: Sequence[np.ndarray]) -> np.ndarray:
    """``uint8[n, H, W, 3]`` from a list of equal ``rgb_array`` frames; ValueError naming ``frames``."""
    if isinstance(frames, np.ndarray):
        frames = list(frames)
    if not isinstance(frames, Sequence) or len(frames) == 0:
        raise ValueError("frames: expected a non-empty list of rgb_array frames (uint8 H x W x 3)")
    first = np.asarray(frames[0])
    for k, f in enumerate(frames):
        f = np.asarray(f)
        if f.dtype != np.uint8 or f.ndim != 3 or f.shape[2] != 3:
            raise ValueError(f"frames: frame {k} is not an rgb_array frame (uint8 H x W x 3): dtype {f.dtype}, shape {f.shape}")
        if f.shape != first.shape:
            raise ValueError(f"frames: frame {k} has shape {f.shape}, frame 0 {first.shape}; all frames need one shape")
    return np.stack([np.asarray(f) for f in frames])
