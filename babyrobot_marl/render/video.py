"""Saving episodes: ``rgb_array`` frames to GIF or MP4 with imageio (the ``video`` extra, imported lazily).

frames = episode_frames(env, policy, seed=0)   # env made with render_mode="rgb_array"
save_gif(frames, "episode.gif", fps=4)
save_video(frames, "episode.mp4", fps=8)       # needs imageio-ffmpeg
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..core.checks import check_int
from .checks import check_frames, check_video_fps


def _imageio() -> Any:
    try:
        import imageio.v3 as iio
    except ImportError:
        raise ImportError("saving GIF/MP4 needs imageio: pip install 'babyrobot_marl[video]'") from None
    return iio


def save_gif(frames: Sequence[np.ndarray], path: str | Path, fps: float = 4) -> Path:
    """Write ``frames`` as an endlessly looping GIF at ``fps`` frames per second; returns the path."""
    stack, fps = check_frames(frames), check_video_fps(fps)
    path = Path(path)
    _imageio().imwrite(path, stack, extension=".gif", duration=1000.0 / fps, loop=0)
    return path


def save_video(frames: Sequence[np.ndarray], path: str | Path, fps: float = 8) -> Path:
    """Write ``frames`` as a video (MP4 by the path's suffix; needs imageio-ffmpeg); returns the path."""
    stack, fps = check_frames(frames), check_video_fps(fps)
    if stack.shape[1] % 2 or stack.shape[2] % 2:  # H.264 wants even sizes: pad with the last row/column
        stack = np.pad(stack, ((0, 0), (0, stack.shape[1] % 2), (0, stack.shape[2] % 2), (0, 0)), mode="edge")
    path = Path(path)
    _imageio().imwrite(path, stack, fps=fps)
    return path


def episode_frames(
    env: Any,
    policy: Callable[[Any], Any] | Mapping[str, Callable[[Any], Any]],
    seed: int | None = None,
    max_steps: int = 10_000,
    animation_frames: int = 0,
) -> list[np.ndarray]:
    """Play one episode and return its ``rgb_array`` frames: the start, then one per step
    (with ``animation_frames`` = n > 0: n frames per step, the robots gliding from cell to cell
    as on the live canvas; the last of them is the step's ``render()``).

    ``env``: a Gymnasium env (``BabyRobotEnv``, ``gymnasium.make(...)``) or a PettingZoo
    parallel env (the race), made with ``render_mode="rgb_array"``. ``policy``: a function of
    an observation returning an action (for a race, called with each robot's observation), or
    for a race a dict of such functions by agent. The episode ends when it terminates or is
    truncated (a race: when no agent is left), or after ``max_steps`` steps.
    """
    if getattr(env, "render_mode", None) != "rgb_array":
        raise ValueError(f"env: needs render_mode='rgb_array' to give frames, got {getattr(env, 'render_mode', None)!r}")
    max_steps = check_int(max_steps, "max_steps", 0)
    race = hasattr(env, "possible_agents")
    if isinstance(policy, Mapping):
        if not race or set(policy) != set(env.possible_agents):
            raise ValueError("policy: a dict of policies needs a race and one policy for each of its agents")
    elif not callable(policy):
        raise ValueError(f"policy: expected a function of an observation or a dict of them by agent, got {type(policy).__name__}")
    animation_frames = check_int(animation_frames, "animation_frames", 0, 60)
    obs, _ = env.reset(seed=seed)
    frames = [env.render()]

    def step_frames() -> None:
        u = env.unwrapped
        if animation_frames > 1 and hasattr(u, "_scene"):
            scene, renderer = u._scene(), u.rgb_renderer
            frames.extend(renderer.frame(scene, u.overlay, k / animation_frames) for k in range(1, animation_frames))
        frames.append(env.render())

    for _ in range(max_steps):
        if race:
            if not env.agents:
                break
            obs, *_ = env.step({a: (policy[a] if isinstance(policy, Mapping) else policy)(obs[a]) for a in env.agents})
            step_frames()
        else:
            obs, _, terminated, truncated, _ = env.step(policy(obs))
            step_frames()
            if terminated or truncated:
                break
    return frames


class Gif:
    """A GIF file shown in a notebook cell: as ``image/gif`` and as HTML of the same image, so that
    nbconvert's HTML (which has no ``image/gif`` renderer), GitHub and JupyterLab all show it
    animated, at its own size. ``display(Gif(path))`` or a cell ending with ``Gif(path)``."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self.data = self.path.read_bytes()

    def _repr_mimebundle_(self, include: Any = None, exclude: Any = None) -> dict[str, str]:
        import base64
        import html

        b64 = base64.b64encode(self.data).decode("ascii")
        tag = f'<img src="data:image/gif;base64,{b64}" alt="{html.escape(self.path.name)}">'  # a file's name is text, not HTML
        return {"image/gif": b64, "text/html": tag, "text/plain": f"GIF {self.path.name}"}
