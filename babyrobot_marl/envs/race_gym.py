"""BabyRobotRace-v0: one learning robot races scripted opponents, as a Gymnasium env."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import partial
from typing import Any

import gymnasium as gym
import numpy as np

from ..core.checks import check_action, check_seed
from ..core.level import Level
from ..core.rules import Rules, known_args
from ..policies import POLICY_NAMES, make
from ..render.rgb import Theme
from .checks import check_cells, check_goal_cells, check_no_goals, check_options
from .race import RaceEnv
from .race_goals import towards_own_goal
from .spec import StepLimitSpec

_ARGS = (
    "level", "opponents", "collisions", "max_cycles", "start", "rules", "render_mode", "cell_size", "theme",
    "animation_frames", "render_fps", "observe", "view_radius", "k", "obs_encoding", "hint", "goals", "lifelong",
)


class BabyRobotRaceEnv(gym.Env):
    """Robot 0 learns; robots 1.. are scripted (``"shortest"`` or ``"random"``) on the same level.

    Actions, observations, rewards and collision rules are robot 0's view of
    ``babyrobot_marl.race_v0`` (see its docstring): ``Discrete(5)`` actions, a
    ``MultiDiscrete`` observation beginning with its own ``[x, y]`` followed by
    ``[x, y, finished]`` of each opponent. The episode terminates when robot 0 reaches an exit
    (its reward includes ``win_bonus`` if it is first) and is truncated after ``max_cycles``
    steps. Opponents that finish are parked off the board.

    ``info``, the same keys after ``reset`` and every ``step``, numbers only: robot 0's race info
    (``cell`` int64 ``[x, y]``, ``outcome`` an int code into ``babyrobot_marl.OUTCOME_NAMES``,
    ``blocked``, ``finished``, ``rank``: 0 until it finishes) plus ``ranks``, an int64 array of
    every robot's rank (0: not finished).

    ``obs_encoding``: ``"multidiscrete"`` (default), ``"box"`` or ``"onehot"``
    (``babyrobot_marl.encodings``). ``reset(options={"starts": [(x, y), ...]})`` places every robot
    (other option keys are ignored with a ``UserWarning``).

    ``goals="own"``: every robot has its own target cell (``race_v0``'s own goals; the exits are
    floor): robot 0's episode terminates on its target, its observation ends with the target's
    ``[x, y]``, and ``"shortest"`` opponents walk a shortest path to their own targets.
    ``reset(options={"goals": [(x, y), ...]})`` gives the targets (one per robot). ``lifelong=True``:
    a robot on its target gets a new one and keeps going (robot 0 is truncated at ``max_cycles``).

    Registered as ``babyrobot_marl/BabyRobotRace-v0``: ``gymnasium.make(
    "babyrobot_marl/BabyRobotRace-v0", level="race-4", opponents=["shortest", "random", "random"])``;
    its ``spec.max_episode_steps`` is its ``max_cycles``.
    """

    metadata = {"render_modes": ["ansi", "rgb_array", "human"], "render_fps": 4}
    spec = StepLimitSpec()  # its max_episode_steps: this env's own step limit (spec.py)

    def __init__(
        self,
        level: str | Level = "race-2",
        opponents: Sequence[str] = ("shortest",),
        collisions: str | None = None,
        max_cycles: int | None = None,
        start: str = "level",
        rules: Rules | Mapping[str, Any] | None = None,
        render_mode: str | None = None,
        cell_size: int | None = None,
        theme: str | Theme = "light",
        animation_frames: int = 4,
        render_fps: float | None = None,
        obs_encoding: str = "multidiscrete",
        goals: str = "exit",
        lifelong: bool = False,
        **rule_overrides: Any,
    ):
        known_args("BabyRobotRaceEnv", rule_overrides, _ARGS)  # Python's wording, naming this class
        if isinstance(opponents, str) or not isinstance(opponents, Sequence) or not all(p in POLICY_NAMES for p in opponents):
            raise ValueError(f"opponents: expected a list of policy names from {POLICY_NAMES}, got {opponents!r}")
        self.race = RaceEnv(
            level=level,
            n_robots=1 + len(opponents),
            collisions=collisions,
            max_cycles=max_cycles,
            start=start,
            finished="freeze",
            rules=rules,
            render_mode=render_mode,
            cell_size=cell_size,
            theme=theme,
            animation_frames=animation_frames,
            render_fps=render_fps,
            obs_encoding=obs_encoding,
            goals=goals,
            lifelong=lifelong,
            **rule_overrides,
        )
        self.race.set_overlay(names=["learner", *opponents])  # the legend's names
        self.metadata = self.race.metadata  # render_fps: this env's own
        self.opponent_names = tuple(opponents)
        self.render_mode = render_mode
        self.observation_space = self.race.observation_space("robot_0")
        self.action_space = self.race.action_space("robot_0")
        self._opponents: list[Any] = []
        self._obs: dict[str, np.ndarray] = {}

    @property
    def level(self) -> Level:
        return self.race.level

    @property
    def own_step_limit(self) -> int:
        """``max_cycles``: ``env.spec.max_episode_steps`` after ``gymnasium.make``."""
        return self.race.max_cycles

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        # every argument checked before anything changes
        check_no_goals(options, self.race.goals_mode)
        known = check_options(options, ("starts", "goals") if self.race.goals_mode == "own" else ("starts",))  # warned once, here
        starts = known.get("starts")
        if starts is not None:
            check_cells(self.race.table, starts, self.race.n_robots, 'options["starts"]')
        if known.get("goals") is not None:
            check_goal_cells(self.race.table, known["goals"], self.race.n_robots, self.race.goals_mode)
        super().reset(seed=check_seed(seed))
        # the opponents' random moves and the race's own draws all come from self.np_random
        self._obs, infos = self.race.reset(seed=int(self.np_random.integers(2**63)), options=dict(known))
        # after the race's reset, which may draw a new level (making a policy draws no number)
        self._opponents = [self._opponent(name, k) for k, name in enumerate(self.opponent_names, start=1)]
        return self._obs["robot_0"].copy(), self._with_ranks(infos["robot_0"])

    def step(self, action):
        if not self.race.agents:
            raise RuntimeError("step: the episode has ended or not started; call reset() first")
        # check the learner's action before the random opponents draw theirs: a rejected step
        # must leave the generator, and so the rest of the episode, as it was
        actions = {"robot_0": check_action(action)}
        for k, policy in enumerate(self._opponents, start=1):
            agent = f"robot_{k}"
            actions[agent] = policy(self._obs[agent])
        obs, rewards, terms, truncs, infos = self.race.step(actions)
        self._obs = obs
        # parked robots are only marked terminated when the whole race ends
        terminated, truncated = bool(infos["robot_0"]["finished"]), bool(truncs["robot_0"])
        if terminated and self.race.agents:
            self.race.agents = []  # the learner's episode is over; the opponents' race with it
        return obs["robot_0"].copy(), float(rewards["robot_0"]), terminated, truncated, self._with_ranks(infos["robot_0"])

    def _opponent(self, name: str, k: int) -> Any:
        """Opponent ``k``'s policy; with own goals, ``"shortest"`` walks towards its own target."""
        if name == "shortest" and self.race.goals_mode == "own":
            return partial(towards_own_goal, self.race, k)
        return make(name, self.race.table, seed=self.np_random)

    def render(self) -> str | None:
        return self.race.render()

    def close(self) -> None:
        self.race.close()

    def _with_ranks(self, info: dict[str, Any]) -> dict[str, Any]:
        return {**info, "ranks": np.array(self.race.ranks, dtype=np.int64)}

