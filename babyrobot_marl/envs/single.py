"""BabyRobot-v0: one robot finds the exit. A thin Gymnasium shell over the shared grid core."""

from __future__ import annotations

from collections.abc import Mapping
from functools import cached_property
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..core.actions import N_ACTIONS, Action
from ..core.batch import BatchRace
from ..core.checks import check_action, check_count, check_seed
from ..core.engine import OUTCOMES, STAYED, move
from ..core.level import Cell, Level
from ..core.model import Transition, frozenlake_P
from ..core.outcomes import START
from ..core.rng import SLOTS, new_key
from ..core.rules import Rules, resolve_rules
from ..core.table import compile_level
from ..levels.resolve import resolve_level
from ..render.ansi import frame
from ..render.checks import check_animation_frames, check_cell_size, check_fps
from ..render.rgb import Theme, resolve_theme
from ..render.scene import Scene
from .checks import check_options, check_render_mode, check_start
from .drawing import EnvDrawing, OverlayMethods
from .encodings import Encoder
from .scenes import single_scene
from .spec import StepLimitSpec

_ARGS = (
    "level", "rules", "max_steps", "start", "render_mode", "cell_size", "theme", "animation_frames", "render_fps", "obs_encoding"
)


def default_max_steps(level: Level) -> int:
    """Four steps per cell, and at least 100: room for a random walk on small levels."""
    return max(100, 4 * level.n_cells)


class BabyRobotEnv(OverlayMethods, gym.Env):
    """Baby Robot looks for the exit of a grid of walls, glass walls, puddles and blocked cells.

    ## Action space

    ``Discrete(5)``, the ``babyrobot_marl.Action`` enum:

    | value | name  | effect                 |
    |-------|-------|------------------------|
    | 0     | STAY  | stay in place          |
    | 1     | NORTH | move up (``y - 1``)    |
    | 2     | EAST  | move right (``x + 1``) |
    | 3     | SOUTH | move down (``y + 1``)  |
    | 4     | WEST  | move left (``x - 1``)  |

    ## Observation space

    ``MultiDiscrete([width, height])``: the robot's cell ``np.array([x, y], dtype=np.int64)``,
    ``x`` the column from the left, ``y`` the row from the top. ``obs_encoding="box"``: the same
    two numbers as a float32 ``Box``; ``"onehot"``: a float32 ``Box`` of ``width + height``
    entries, a 1 at ``x`` and at ``width + y`` (``babyrobot_marl.encodings``).

    ## Rewards

    For the cell the step ends in (``Rules``): floor -1, small puddle -2, large puddle -4, an
    exit 0, or a custom reward set on the level. A move into a wall, a blocked cell or the
    border, or a failed pass through a glass wall, leaves the robot in place and pays its cell.

    ## Dynamics

    A move out of a puddle skids with probability 0.4 (small) / 0.6 (large) to one of the other
    open neighbours, uniformly (stays with none). Glass walls let a move through with
    probability 0.5. All randomness comes from ``self.np_random``: same seed, same episode.

    ## Episode end

    Terminated when the robot reaches an exit. Truncated after ``max_steps`` steps
    (default ``max(100, 4 * width * height)``); ``truncated`` is False on a terminating step.

    ## Info

    The same keys after ``reset`` and every ``step``, numbers only (tensor libraries stack them):

    | key          | type                     | meaning                                                       |
    |--------------|--------------------------|---------------------------------------------------------------|
    | ``cell``     | int64 array ``[x, y]``   | the robot's cell                                              |
    | ``outcome``  | int                      | code into ``babyrobot_marl.OUTCOME_NAMES``: 0 moved, 1 stayed, |
    |              |                          | 2 bumped, 3 skidded, 4 glass; 5 start (after ``reset``)        |
    | ``intended`` | bool                     | the robot ended where its action aimed (moved, or STAY)       |

    ## Arguments

    ``level``: a built-in name (``babyrobot_marl.levels.names()``, or ``"maze-WxH[-sSEED]"``),
    a level text or a ``Level``. ``rules``: a ``Rules`` or dict; any ``Rules`` field may also
    be given as a keyword (``glass_pass_prob=0.9``). ``max_steps``. ``start``: ``None`` (the
    level's start, or a random free cell if it has none) or ``"random"`` (a random free cell
    each episode). ``reset(options={"start": (x, y)})`` starts one episode at a given cell (a bad
    cell is a ``ValueError``; any other option key is ignored with a ``UserWarning``).
    ``obs_encoding``: ``"multidiscrete"`` (default), ``"box"`` or ``"onehot"`` (above).
    ``render_mode``: ``"ansi"`` (text frame), ``"rgb_array"`` (``uint8[H * cell_size, W * cell_size, 3]``,
    pure numpy) or ``"human"`` (in Jupyter with the ``notebook`` extra: a live ipycanvas canvas in
    the cell, the robot gliding over ``animation_frames`` frames per step, 0: jumping, at
    ``render_fps`` steps per second, default ``metadata["render_fps"]`` = 4, 0: unpaced; elsewhere
    the text frame printed each step). ``cell_size`` (pixels, default 32) and ``theme``
    (``"light"``, ``"dark"``, ``"mono"`` or a ``render.Theme``) style both.
    ``env.unwrapped.set_overlay(values=..., q_values=..., arrows=..., text=..., panel=...)`` draws
    over the grid (``clear_overlay()`` removes it); ``env.unwrapped.canvas`` is the live canvas.

    ## Registered configurations

    ``babyrobot_marl/BabyRobot-v0`` (``level="default"``); pass ``level=`` to ``gymnasium.make``
    for any other level, e.g. ``gymnasium.make("babyrobot_marl/BabyRobot-v0", level="maze-8x8")``.
    The made env's ``spec.max_episode_steps`` is its ``max_steps`` (the env truncates itself
    there), so ``TimeAwareObservation`` and ``TimeLimit(env, env.spec.max_episode_steps)`` read it.
    """

    metadata = {"render_modes": ["ansi", "rgb_array", "human"], "render_fps": 4}
    spec = StepLimitSpec()  # its max_episode_steps: this env's own step limit (spec.py)

    def __init__(
        self,
        level: str | Level = "default",
        rules: Rules | Mapping[str, Any] | None = None,
        max_steps: int | None = None,
        start: str | None = None,
        render_mode: str | None = None,
        cell_size: int | None = None,
        theme: str | Theme = "light",
        animation_frames: int = 4,
        render_fps: float | None = None,
        obs_encoding: str = "multidiscrete",
        **rule_overrides: Any,
    ):
        self.level = resolve_level(level)
        self.rules = resolve_rules(rules, rule_overrides, "BabyRobotEnv", _ARGS)
        self.table = compile_level(self.level, self.rules)
        self.max_steps = default_max_steps(self.level) if max_steps is None else check_count(max_steps, "max_steps")
        if start not in (None, "random"):
            raise ValueError(f"start: must be None (the level's start) or 'random', got {start!r}")
        self._free = list(self.table.free_cells)
        self.random_start = start == "random" or not self.level.starts
        if self.random_start and not self._free:
            raise ValueError(f"level: {self.level!r} has no free cell to start a robot on")
        self.render_mode = check_render_mode(render_mode, self.metadata["render_modes"])
        self.cell_size, self.theme = check_cell_size(cell_size, self.level), resolve_theme(theme)
        self.animation_frames = check_animation_frames(animation_frames)
        if render_fps is not None:  # this env's own metadata: the class's stays as it is
            self.metadata = {**type(self).metadata, "render_fps": check_fps(render_fps)}
        self.drawing = EnvDrawing(self.level, self.cell_size, self.theme, self.animation_frames, fit=cell_size is None)

        w, h = self.level.width, self.level.height
        self.action_space = spaces.Discrete(N_ACTIONS)
        self.encoder = Encoder([w, h], obs_encoding)
        self.observation_space = self.encoder.space
        self._lists = self.table.lists
        # every cell's observation, encoded once: a step only copies one
        self._obs = [self.encoder(np.array(self.table.cell_xy(c), dtype=np.int64)) for c in range(self.table.n_cells)]
        self._cells = [np.array(self.table.cell_xy(c), dtype=np.int64) for c in range(self.table.n_cells)]
        self._xy = [self.table.cell_xy(c) for c in range(self.table.n_cells)]
        self._cell = -1  # no episode yet
        self._t = 0
        self._key = 0
        self._done = True
        self._return = 0.0
        self._last_step: tuple[int, int, int] | None = None  # (cell before, action, outcome)

    # ------------------------------------------------------------------------ Gymnasium API
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        start = check_options(options, ("start",)).get("start")
        if start is not None:
            start = check_start(self.table, start)
        super().reset(seed=check_seed(seed))
        self._key = new_key(self.np_random)
        if start is not None:
            self._cell = start
        elif self.random_start:
            self._cell = self._free[int(self.np_random.integers(len(self._free)))]
        else:
            self._cell = self.table.cell_id(self.level.starts[0])
        self._t = 0
        self._done = False
        self._return = 0.0
        self._last_step = None
        if self.render_mode == "human":
            self._render_human(animate=False)
        return self._obs[self._cell].copy(), {"cell": self._cells[self._cell].copy(), "outcome": START, "intended": False}

    def step(self, action):
        a = check_action(action)
        if self._done:
            if self._cell < 0:
                raise RuntimeError("step: call reset() before the first step()")
            raise RuntimeError("step: the episode has ended (terminated or truncated); call reset() first")
        cell, outcome = move(self._lists, self._cell, a, self._key, self._t * SLOTS)
        self._last_step = (self._cell, a, outcome)
        self._cell = cell
        self._t += 1
        reward = self._lists.reward[cell]
        terminated = self._lists.is_exit[cell]
        truncated = not terminated and self._t >= self.max_steps
        self._done = terminated or truncated
        self._return += reward
        if self.render_mode == "human":
            self._render_human()
        info = {"cell": self._cells[cell].copy(), "outcome": outcome, "intended": outcome <= STAYED}
        return self._obs[cell].copy(), reward, terminated, truncated, info

    def render(self) -> str | None:
        if self.render_mode is None:
            gym.logger.warn("render() called with render_mode=None; pass render_mode='ansi' or 'human'")
            return None
        if self.render_mode == "ansi":
            return self._frame()
        if self.render_mode == "rgb_array":
            return self.drawing.frame(self._scene())
        self._render_human()
        return None

    def get_keys_to_action(self) -> dict[tuple[int, ...], int]:
        """Keys for ``gymnasium.utils.play.play(env)`` (render_mode="rgb_array"): arrows and WASD, space stays."""
        from .keys import keys_to_action

        return keys_to_action()

    # ------------------------------------------------------------------------ helpers
    @property
    def own_step_limit(self) -> int:
        """``max_steps``: ``env.spec.max_episode_steps`` after ``gymnasium.make``."""
        return self.max_steps

    @property
    def robot_cell(self) -> Cell | None:
        """The robot's ``(x, y)``, or None before the first reset."""
        return self._xy[self._cell] if self._cell >= 0 else None

    @property
    def elapsed_steps(self) -> int:
        return self._t

    def batch(self, n_envs: int) -> BatchRace:
        """``n_envs`` copies of this env as one batch engine: env ``i`` plays exactly the episodes
        of this env seeded the same way (``BatchRace.seed``, then ``reset_envs``)."""
        fixed = [] if self.random_start else [self.table.cell_id(self.level.starts[0])]
        start = "single" if self.random_start else "level"
        return BatchRace(self.table, n_envs, 1, self.max_steps, fixed, self._free, start, win_bonus=0.0)

    @cached_property
    def P(self) -> dict[int, dict[int, list[Transition]]]:
        """FrozenLake-style model: ``P[s][a] == [(prob, next_s, reward, terminated), ...]``.

        States are cell ids ``s = y * width + x``; built from the same tables as ``step``.
        """
        return frozenlake_P(self.table)

    def _frame(self, colour: bool = False) -> str:
        robots = [self.robot_cell] if self._cell >= 0 else []
        last = f"  {Action(self._last_step[1]).name} -> {OUTCOMES[self._last_step[2]]}" if self._last_step else ""
        status = f"step {self._t}/{self.max_steps}  return {self._return:g}{last}"
        return frame(self.level, robots, status, colour=colour)

    def _render_human(self, animate: bool = True) -> None:
        self.drawing.show(self._scene, self._frame, animate, self.metadata["render_fps"])

    def _scene(self) -> Scene:
        return single_scene(self)
