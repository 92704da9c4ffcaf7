"""A GIF of a policy playing: frames from the env's ``rgb_array`` render, written with imageio."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .deps import require_train


def episode_frames(env: Any, act: Callable[[Any], int], seed: int = 0, max_frames: int = 500) -> list[np.ndarray]:
    """Frames of one episode of ``env`` (``render_mode="rgb_array"``) with ``act(obs) -> action``."""
    if getattr(env, "render_mode", None) != "rgb_array":
        raise ValueError(f"env: needs render_mode='rgb_array', got {getattr(env, 'render_mode', None)!r}")
    obs, _ = env.reset(seed=seed)
    frames = [env.render()]
    done = False
    while not done and len(frames) < max_frames:
        obs, _, terminated, truncated, _ = env.step(act(obs))
        frames.append(env.render())
        done = terminated or truncated
    return frames


def write_gif(frames: list[np.ndarray], path: str | Path, fps: float = 4.0) -> Path:
    """Write ``frames`` (``uint8[H, W, 3]``) as a looping GIF at ``fps`` frames a second."""
    if not frames:
        raise ValueError("frames: need at least one frame")
    if not fps > 0:
        raise ValueError(f"fps: must be > 0, got {fps!r}")
    (imageio,) = require_train("imageio")
    import imageio.v3 as iio  # noqa: F401  (the v3 API of the module just checked)

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    iio.imwrite(path, np.stack(frames), duration=1000.0 / fps, loop=0)
    return path
