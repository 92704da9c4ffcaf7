"""Saving episodes: ``rgb_array`` frames to GIF or MP4 with imageio (the ``video`` extra, imported lazily)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np


def _imageio() -> Any:
    try:
        import imageio.v3 as iio
    except ImportError:
        raise ImportError("saving GIF/MP4 needs imageio: pip install 'babyrobot_marl[video]'") from None
    return iio


def _check_frames(frames: Sequence[np.ndarray]) -> np.ndarray:
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


def _check_fps(fps: object) -> float:
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not 0 < fps <= 100:
        raise ValueError(f"fps: must be a number in (0, 100], got {fps!r}")
    return float(fps)


def save_gif(frames: Sequence[np.ndarray], path: str | Path, fps: float = 4) -> Path:
    """Write ``frames`` as an endlessly looping GIF at ``fps`` frames per second; returns the path."""
    stack, fps = _check_frames(frames), _check_fps(fps)
    path = Path(path)
    _imageio().imwrite(path, stack, extension=".gif", duration=1000.0 / fps, loop=0)
    return path


def save_video(frames: Sequence[np.ndarray], path: str | Path, fps: float = 8) -> Path:
    """Write ``frames`` as a video (MP4 by the path's suffix; needs imageio-ffmpeg); returns the path."""
    stack, fps = _check_frames(frames), _check_fps(fps)
    if stack.shape[1] % 2 or stack.shape[2] % 2:  # H.264 wants even sizes: pad with the last row/column
        stack = np.pad(stack, ((0, 0), (0, stack.shape[1] % 2), (0, stack.shape[2] % 2), (0, 0)), mode="edge")
    path = Path(path)
    _imageio().imwrite(path, stack, fps=fps)
    return path
