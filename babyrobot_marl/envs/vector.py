"""Vector envs on the batch engine: many Baby Robots stepped as numpy arrays, no Python loop per env.

Three shells over one ``core.batch.BatchRace``:

* ``BabyRobotVectorEnv``: ``num_envs`` copies of ``BabyRobot-v0`` as a ``gymnasium.vector.VectorEnv``;
  ``gymnasium.make_vec("babyrobot_marl/BabyRobot-v0", num_envs=N, vectorization_mode="vector_entry_point")``.
* ``RaceVectorEnv``: ``n_envs`` races of ``n_robots`` as one ``VectorEnv`` of ``n_envs * n_robots`` slots
  for parameter sharing (one policy drives every robot), the race in ``race_v0``'s ``finished="freeze"`` view.
* ``sb3_vec_env(...)``: either of them as a Stable-Baselines3 ``VecEnv`` (same-step auto-reset).

Env ``i`` of a vector env plays exactly the episodes of a single env (``BabyRobotEnv`` /
``race_v0.parallel_env(finished="freeze")``) reset with seed ``seed + i`` and given the same actions,
across auto-resets: same observations, rewards, terminations and truncations.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import batch_space

from ..core.actions import N_ACTIONS
from ..core.batch import BatchRace
from ..core.engine import OUTCOMES, STAYED
from ..core.level import Cell, Level
from ..core.rules import Rules
from ..render.ansi import frame
from ..render.rgb import Theme
from .common import ACTION_HELP, check_options, check_positive_int, check_render_mode
from .race import RaceEnv
from .single import BabyRobotEnv

if TYPE_CHECKING:
    from stable_baselines3.common.vec_env import VecEnv

try:  # gymnasium >= 1.1 names its autoreset modes; 1.0 only has next-step
    from gymnasium.vector import AutoresetMode

    _AUTORESET: dict[str, Any] = {"autoreset_mode": AutoresetMode.NEXT_STEP}
except ImportError:  # pragma: no cover - gymnasium 1.0
    _AUTORESET = {}

__all__ = ["BabyRobotVectorEnv", "RaceVectorEnv", "sb3_vec_env"]

# outcome names by engine code; code -1 (a parked robot) reads the last entry
_OUTCOME_NAMES = np.array([*OUTCOMES, "finished"], dtype=object)
_INTENDED = np.array([code <= STAYED for code in range(len(OUTCOMES))] + [False])  # by code; -1 reads the last
_RENDER_MODES = ["rgb_array", "ansi"]


class _BatchVectorEnv(gym.vector.VectorEnv):
    """What both Gymnasium vector envs share: seeding, resets, action checks, next-step auto-reset.

    The batch has ``n_envs`` envs of ``n_robots`` robots; the vector env has
    ``num_envs = n_envs * n_robots`` slots, slot ``env * n_robots + robot``.
    """

    metadata: dict[str, Any] = {"render_modes": _RENDER_MODES, "render_fps": 4, **_AUTORESET}

    _ref: BabyRobotEnv | RaceEnv  # a single env holding the resolved level, rules and renderer
    _batch: BatchRace

    def _setup(self, ref: BabyRobotEnv | RaceEnv, batch: BatchRace, render_mode: str | None) -> None:
        self._ref, self._batch, self.table = ref, batch, ref.table
        self.n_envs, self.n_robots = batch.n_envs, batch.n_robots
        self.num_envs = self.n_envs * self.n_robots
        self.metadata = dict(type(self).metadata)  # an instance's own copy, as SyncVectorEnv keeps
        self.render_mode = check_render_mode(render_mode, self.metadata["render_modes"])
        self.single_action_space = spaces.Discrete(N_ACTIONS)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        if isinstance(ref, RaceEnv):
            self.single_observation_space = ref.observation_space(ref.possible_agents[0])
        else:
            self.single_observation_space = ref.observation_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._autoreset = np.zeros(self.n_envs, dtype=bool)  # envs whose episode ended on the last step
        self._all_slots = np.ones(self.num_envs, dtype=bool)
        self._started = False
        self._level, self._xy = ref.level, [ref.table.cell_xy(c) for c in range(ref.table.n_cells)]

    # ------------------------------------------------------------------------ Gymnasium API
    def reset(
        self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start new episodes in every env (or the envs of ``options["reset_mask"]``).

        ``seed``: ``None``, an int (env ``i`` gets ``seed + i``, as ``SyncVectorEnv`` does) or a
        list of ``n_envs`` ints or ``None`` (``None``: the env keeps its generator).
        ``options``: passed to every env as to the single env; ``"reset_mask"``, a bool array of
        shape ``(num_envs,)``, resets only the masked envs (the others keep their state).
        """
        opts = dict(check_options(options))
        envs = self._mask_envs(opts.pop("reset_mask", None))
        seeds = self._seed_list(seed)
        start = self._start_option(opts)
        self._seed_envs([(i, seeds[i]) for i in envs])
        self._restart(envs, [start] * len(envs))
        self._autoreset[envs] = False
        self._started = True
        mask = np.zeros(self.n_envs, dtype=bool)
        mask[envs] = True
        return self._observations(), self._reset_infos(np.repeat(mask, self.n_robots))

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Step every env; an env whose episode ended on the previous step is reset instead.

        The reset env's slots return the first observation of the new episode, reward 0,
        ``terminated`` and ``truncated`` False, and its action is ignored (Gymnasium's
        next-step auto-reset, ``AutoresetMode.NEXT_STEP``).
        """
        acts = self._check_actions(actions)
        if not self._started:
            raise RuntimeError("step: call reset() before the first step()")
        b, reset = self._batch, self._autoreset
        rewards, _, blocked, outcome, over = b.step(acts)
        if np.count_nonzero(reset):
            # the envs stepped above are restarted; their new episode starts from their own generators
            self._restart(np.flatnonzero(reset), None)
            rewards[reset] = 0.0
            over = over & ~reset
        obs = self._observations()
        ended = over[:, None]
        terminated = (ended & ~b.racing).reshape(-1)
        truncated = (ended & b.racing).reshape(-1)
        self._autoreset = over
        infos = self._step_infos(obs, outcome, blocked, reset if self.n_robots == 1 else np.repeat(reset, self.n_robots))
        return obs, rewards.reshape(-1), terminated, truncated, infos

    def render(self) -> tuple[Any, ...] | None:
        """One frame per env (not per slot), as ``SyncVectorEnv.render`` returns one per env.

        ``"rgb_array"``: each env's robots drawn where they stand by the single env's renderer
        (the batch keeps no step history: no poses, no race legend); ``"ansi"``: each a text
        frame with the env's step count.
        """
        if self.render_mode is None:
            gym.logger.warn("render() called with render_mode=None; pass render_mode='rgb_array' or 'ansi'")
            return None
        robots = [self._robots(i) for i in range(self.n_envs)]
        if self.render_mode == "rgb_array":
            renderer = self._ref.rgb_renderer
            return tuple(renderer.frame(r) for r in robots)
        t, limit = self._batch.t, self._batch.max_steps
        return tuple(frame(self._level, r, f"env {i}  step {t[i]}/{limit}") for i, r in enumerate(robots))

    # ------------------------------------------------------------------------ shared helpers
    def _observations(self) -> np.ndarray:
        return self._batch.observations().reshape(self.num_envs, -1)

    def _check_actions(self, actions: Any) -> np.ndarray:
        """``(n_envs, n_robots)`` actions, or a ``ValueError`` naming ``actions`` (nothing changes)."""
        a = np.asarray(actions)
        if a.shape != (self.num_envs,):
            raise ValueError(f"actions: expected an array of shape ({self.num_envs},), one action per env, got shape {a.shape}")
        if a.dtype.kind not in "iu":
            raise ValueError(f"actions: expected integer actions ({ACTION_HELP}), got dtype {a.dtype}")
        # one comparison: as unsigned, negative actions are huge
        if np.count_nonzero(a.view(np.uint64) >= N_ACTIONS if a.dtype == np.int64 else (a < 0) | (a >= N_ACTIONS)):
            k = int(np.flatnonzero((a < 0) | (a >= N_ACTIONS))[0])
            raise ValueError(f"actions: must be integers in 0..{N_ACTIONS - 1} ({ACTION_HELP}), got {a[k]} at index {k}")
        return a.astype(np.intp, copy=False).reshape(self.n_envs, self.n_robots)

    def _seed_list(self, seed: object) -> list[int | None]:
        """One seed (or None) per env from ``reset``'s ``seed`` argument."""
        n = self.n_envs
        if seed is None:
            return [None] * n
        if isinstance(seed, (int, np.integer)) and not isinstance(seed, (bool, np.bool_)):
            if seed < 0:
                raise ValueError(f"seed: must be a non-negative integer, got {seed}")
            return [int(seed) + i for i in range(n)]
        if isinstance(seed, (str, bytes)) or not isinstance(seed, Sequence):
            raise ValueError(f"seed: expected None, an int or a list of {n} ints, got {type(seed).__name__}")
        if len(seed) != n:
            raise ValueError(f"seed: a list of seeds needs one per env ({n}), got {len(seed)}")
        out: list[int | None] = []
        for s in seed:
            if s is not None and (isinstance(s, (bool, np.bool_)) or not isinstance(s, (int, np.integer)) or s < 0):
                raise ValueError(f"seed: each seed must be None or a non-negative integer, got {s!r}")
            out.append(None if s is None else int(s))
        return out

    def _seed_envs(self, seeds: Sequence[tuple[int, int | None]]) -> None:
        """Give env ``i`` the generator ``reset(seed=s)`` gives a single env (``None``: keep it)."""
        for i, s in seeds:
            if s is not None:
                self._batch.generators[i] = np.random.default_rng(s)

    def _mask_envs(self, reset_mask: object) -> np.ndarray:
        """The envs to reset: all, or those of ``options["reset_mask"]`` (checked as ``SyncVectorEnv`` does)."""
        if reset_mask is None:
            return np.arange(self.n_envs)
        if not isinstance(reset_mask, np.ndarray):
            raise TypeError(f"options['reset_mask']: must be a numpy array, got {type(reset_mask).__name__}")
        if reset_mask.shape != (self.num_envs,):
            raise ValueError(f"options['reset_mask']: must have shape ({self.num_envs},), got {reset_mask.shape}")
        if reset_mask.dtype != np.bool_:
            raise TypeError(f"options['reset_mask']: must have dtype bool, got {reset_mask.dtype}")
        if not reset_mask.any():
            raise ValueError("options['reset_mask']: must contain at least one True value")
        per_env = reset_mask.reshape(self.n_envs, self.n_robots)
        if not (per_env == per_env[:, :1]).all():
            raise ValueError("options['reset_mask']: the slots of one race are reset together; mask all or none of them")
        return np.flatnonzero(per_env[:, 0])

    def _start_option(self, options: Mapping[str, Any]) -> int | None:
        """A start cell id from ``options`` (single robot only); None: the usual start."""
        return None

    def _restart(self, envs: np.ndarray | Sequence[int], starts: Sequence[int | None] | None) -> None:
        """New episodes in ``envs``; ``starts[k]``, when given, is env ``envs[k]``'s start cell.

        A given start draws only the episode key, as ``BabyRobotEnv.reset(options={"start": ...})``
        does: the batch is briefly told to use that cell as a fixed level start.
        """
        b = self._batch
        if starts is None or all(s is None for s in starts):
            b.reset_envs(envs)
            return
        envs = np.asarray(envs)
        starts_arr = np.array([-1 if s is None else s for s in starts])
        for s in np.unique(starts_arr).tolist():
            group = envs[starts_arr == s]
            if s < 0:
                b.reset_envs(group)
                continue
            saved = b.start, b.fixed
            b.start, b.fixed = "level", np.array([s], dtype=np.int64)
            try:
                b.reset_envs(group)
            finally:
                b.start, b.fixed = saved

    def _robots(self, i: int) -> list[Cell | None]:
        raise NotImplementedError

    def _reset_infos(self, slots: np.ndarray) -> dict[str, Any]:
        raise NotImplementedError

    def _step_infos(self, obs: np.ndarray, outcome: np.ndarray, blocked: np.ndarray, reset: np.ndarray) -> dict[str, Any]:
        raise NotImplementedError


class BabyRobotVectorEnv(_BatchVectorEnv):
    """``num_envs`` copies of ``BabyRobot-v0`` stepped together by the batch engine.

    Made by ``gymnasium.make_vec("babyrobot_marl/BabyRobot-v0", num_envs=N, level=...)``
    (``vectorization_mode="vector_entry_point"``, the default for this id; pass
    ``vectorization_mode="sync"`` for a ``SyncVectorEnv`` of single envs instead), or directly.

    ## Action space

    ``MultiDiscrete([5] * num_envs)``: one ``babyrobot_marl.Action`` (0 STAY, 1 NORTH, 2 EAST,
    3 SOUTH, 4 WEST) per env, an integer array of shape ``(num_envs,)``. Anything else (another
    shape, floats, bools, values outside 0..4) is a ``ValueError`` naming ``actions``, raised
    before anything changes. ``single_action_space`` is ``Discrete(5)``.

    ## Observation space

    ``MultiDiscrete`` of shape ``(num_envs, 2)``: row ``i`` is env ``i``'s robot ``[x, y]``,
    int64. ``single_observation_space`` is ``MultiDiscrete([width, height])``.

    ## Rewards, dynamics, episode end

    As ``BabyRobotEnv``: rewards float64 of shape ``(num_envs,)``, ``terminated`` when the robot
    reaches an exit, ``truncated`` after ``max_steps`` steps (never both).

    ## Auto-reset

    Gymnasium's next-step mode (``metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP``): the
    ``step`` after an env terminates or truncates resets it, ignoring its action, and returns the
    new episode's first observation with reward 0 and ``terminated = truncated = False``. The new
    episode draws from the env's own generator, as a single env's ``reset()`` without a seed.

    ## Seeding

    ``reset(seed=s)`` gives env ``i`` the seed ``s + i``; ``reset(seed=[s0, s1, ...])`` one each.
    Env ``i`` then plays exactly the episodes of ``BabyRobotEnv(...)`` reset with that seed and
    stepped with the same actions (a ``SyncVectorEnv`` of them gives the same arrays).

    ## Info

    Gymnasium's vector convention, arrays with a ``"_key"`` mask of the envs that have the key:
    ``"cell"``, an int64 array ``(num_envs, 2)`` of ``[x, y]`` (every env); after a step,
    ``"outcome"`` (object array of ``"moved"``, ``"stayed"``, ``"bumped"``, ``"skidded"``,
    ``"glass"``) and ``"intended"`` (bool), masked off for envs reset in that step, as a
    ``SyncVectorEnv`` reports them (whose ``"cell"`` is an object array of tuples instead).

    ## Arguments

    ``num_envs``, then exactly ``BabyRobotEnv``'s: ``level``, ``rules``, ``max_steps``, ``start``,
    ``render_mode`` (``None``, ``"rgb_array"`` or ``"ansi"``: ``render()`` returns one frame per
    env), ``cell_size``, ``theme``, and rule overrides (``glass_pass_prob=0.9``).
    ``reset(options={"start": (x, y)})`` starts every reset env at that cell; ``options["reset_mask"]``
    resets only some envs.
    """

    def __init__(
        self,
        num_envs: int = 1,
        level: str | Level = "default",
        rules: Rules | Mapping[str, Any] | None = None,
        max_steps: int | None = None,
        start: str | None = None,
        render_mode: str | None = None,
        cell_size: int | None = None,
        theme: str | Theme = "light",
        **rule_overrides: Any,
    ):
        n = check_positive_int(num_envs, "num_envs")
        ref = BabyRobotEnv(
            level=level, rules=rules, max_steps=max_steps, start=start, cell_size=cell_size, theme=theme, **rule_overrides
        )
        self._setup(ref, ref.batch(n), render_mode)
        self.level, self.rules, self.max_steps = ref.level, ref.rules, ref.max_steps

    def _start_option(self, options: Mapping[str, Any]) -> int | None:
        start = options.get("start")
        return None if start is None else self._ref._check_start(start)

    def _robots(self, i: int) -> list[Cell | None]:
        return [self._xy[int(self._batch.cells[i, 0])]] if self._started else []

    def _reset_infos(self, slots: np.ndarray) -> dict[str, Any]:
        return {"cell": self._observations(), "_cell": slots}

    def _step_infos(self, obs: np.ndarray, outcome: np.ndarray, blocked: np.ndarray, reset: np.ndarray) -> dict[str, Any]:
        code = outcome[:, 0]
        names = _OUTCOME_NAMES.take(code)
        stepped = ~reset
        intended = _INTENDED.take(code)
        if np.count_nonzero(reset):
            names[reset] = None
            intended &= stepped
        return {
            "cell": obs.copy(),
            "_cell": self._all_slots.copy(),
            "outcome": names,
            "_outcome": stepped,
            "intended": intended,
            "_intended": stepped.copy(),
        }


class RaceVectorEnv(_BatchVectorEnv):
    """``n_envs`` races of ``n_robots`` robots as one vector env of ``n_envs * n_robots`` slots.

    For parameter sharing: one policy acts for every robot of every race. Slot
    ``k = env * n_robots + robot`` is robot ``robot`` of race ``env``; ``num_envs`` is the number
    of slots. Each race is ``race_v0.parallel_env(..., finished="freeze")``.

    ## Action space

    ``MultiDiscrete([5] * num_envs)``: one action per slot (0 STAY, 1 NORTH, 2 EAST, 3 SOUTH,
    4 WEST), an integer array of shape ``(num_envs,)``; a parked (finished) robot's action is
    ignored. Bad actions are a ``ValueError`` naming ``actions``; nothing changes.

    ## Observation space

    Slot ``k``'s row is the ``race_v0`` observation of its robot: its own ``[x, y]``, then
    ``[x, y, finished]`` of the next robots in turn. ``single_observation_space`` is
    ``MultiDiscrete([W, H] + [W, H, 2] * (n_robots - 1))``.

    ## Rewards

    As ``race_v0``: the cell's reward, ``win_bonus`` for finishing first, 0 for parked robots.

    ## Episode end

    A race ends when all its robots have finished or after ``max_cycles`` steps. All its slots
    are then done together: ``terminated`` for the robots that finished, ``truncated`` for the
    others. Until then a finished robot's slot is parked (reward 0, not done), as in
    ``finished="freeze"``.

    ## Auto-reset

    Next-step (``AutoresetMode.NEXT_STEP``), race by race: the step after a race ends restarts
    it; its slots return the new race's first observations, reward 0, not done.

    ## Seeding

    ``reset(seed=s)`` gives race ``i`` the seed ``s + i``; a list gives one seed per race
    (``n_envs`` entries, not one per slot).

    ## Info

    Per slot, Gymnasium's vector convention: ``"cell"`` (int64 ``(num_envs, 2)``), ``"outcome"``
    (object: ``"moved"`` ... ``"glass"``, ``"finished"`` once parked, ``"start"`` after a reset),
    ``"blocked"`` (another robot stopped it this step), ``"finished"`` and ``"rank"`` (int, with
    ``"_rank"`` True only for finished robots), as ``race_v0``'s infos.

    ## Arguments

    ``n_envs`` (races), then ``race_v0.parallel_env``'s: ``level``, ``n_robots``, ``collisions``,
    ``max_cycles``, ``start``, ``rules``, ``render_mode`` (``None``, ``"rgb_array"``, ``"ansi"``:
    one frame per race), ``cell_size``, ``theme``, rule overrides. ``finished`` is always ``"freeze"``.
    """

    def __init__(
        self,
        n_envs: int = 1,
        level: str | Level = "race-2",
        n_robots: int = 2,
        collisions: str | None = None,
        max_cycles: int | None = None,
        start: str = "level",
        rules: Rules | Mapping[str, Any] | None = None,
        render_mode: str | None = None,
        cell_size: int | None = None,
        theme: str | Theme = "light",
        **rule_overrides: Any,
    ):
        n = check_positive_int(n_envs, "n_envs")
        if rule_overrides.pop("finished", "freeze") != "freeze":
            raise ValueError("finished: a vector race keeps finished robots parked until the race ends ('freeze')")
        ref = RaceEnv(
            level=level,
            n_robots=n_robots,
            collisions=collisions,
            max_cycles=max_cycles,
            start=start,
            finished="freeze",
            rules=rules,
            cell_size=cell_size,
            theme=theme,
            **rule_overrides,
        )
        self._setup(ref, ref.batch(n), render_mode)
        self.level, self.rules, self.max_cycles, self.collisions = ref.level, ref.rules, ref.max_cycles, ref.collisions

    def _robots(self, i: int) -> list[Cell | None]:
        if not self._started:
            return []
        b = self._batch
        return [self._xy[c] if r else None for c, r in zip(b.cells[i].tolist(), b.racing[i].tolist())]

    def _reset_infos(self, slots: np.ndarray) -> dict[str, Any]:
        obs, n = self._observations(), self.num_envs
        return {
            "cell": obs[:, :2].copy(),
            "_cell": slots,
            "outcome": np.where(slots, "start", None).astype(object),
            "_outcome": slots.copy(),
            "blocked": np.zeros(n, dtype=bool),
            "_blocked": slots.copy(),
            "finished": np.zeros(n, dtype=bool),
            "_finished": slots.copy(),
        }

    def _step_infos(self, obs: np.ndarray, outcome: np.ndarray, blocked: np.ndarray, reset: np.ndarray) -> dict[str, Any]:
        b, n = self._batch, self.num_envs
        names = _OUTCOME_NAMES[outcome.reshape(-1)]
        names[reset] = "start"
        rank = b.rank.reshape(-1).astype(np.int64)
        every = np.ones(n, dtype=bool)
        return {
            "cell": obs[:, :2].copy(),
            "_cell": every,
            "outcome": names,
            "_outcome": every.copy(),
            "blocked": blocked.reshape(-1) & ~reset,
            "_blocked": every.copy(),
            "finished": ~b.racing.reshape(-1),
            "_finished": every.copy(),
            "rank": rank,
            "_rank": rank > 0,
        }


# ---------------------------------------------------------------------------- Stable-Baselines3
def sb3_vec_env(level: str | Level | None = None, n_envs: int = 1, n_robots: int = 1, **kwargs: Any) -> VecEnv:
    """A Stable-Baselines3 ``VecEnv`` over the batch engine.

    ``n_robots == 1``: ``n_envs`` copies of ``BabyRobot-v0``; ``kwargs`` are ``BabyRobotEnv``'s
    (``rules``, ``max_steps``, ``start``, ``render_mode``, rule overrides); ``level`` defaults
    to ``"default"``. ``n_robots > 1``: ``n_envs`` races sharing one policy, ``num_envs =
    n_envs * n_robots`` (slot ``env * n_robots + robot``); ``kwargs`` are ``race_v0``'s
    (``collisions``, ``max_cycles``, ``start``, ...); ``level`` defaults to ``"race-2"``.

    SB3 semantics: ``step`` returns ``(obs, rewards, dones, infos)`` with rewards float32; an env
    that ends is reset in the same step (all slots of a race together), its last observation in
    ``infos[k]["terminal_observation"]``; ``infos[k]["TimeLimit.truncated"]`` is True when the
    slot was truncated (``max_steps`` / ``max_cycles``) rather than terminated, on every step as
    ``DummyVecEnv`` does. ``seed(s)`` seeds the next ``reset()``: env (race) ``i`` gets ``s + i``,
    the episodes a single env reset with that seed plays; it returns the seed of each slot.
    ``set_options({"start": (x, y)})`` applies to the next ``reset()`` (single robot).

    Needs ``stable-baselines3`` (``pip install "babyrobot_marl[train]"``).
    """
    cls = _sb3_class()
    if check_positive_int(n_robots, "n_robots") == 1:
        venv: _BatchVectorEnv = BabyRobotVectorEnv(n_envs, **({"level": level} if level is not None else {}), **kwargs)
    else:
        venv = RaceVectorEnv(n_envs, **({"level": level} if level is not None else {}), n_robots=n_robots, **kwargs)
    return cls(venv)


def _sb3_class() -> type:
    try:
        import stable_baselines3  # noqa: F401
    except ImportError as err:
        raise ImportError('sb3_vec_env needs stable-baselines3: pip install "babyrobot_marl[train]" (the train extra)') from err
    return _make_sb3_class()


@functools.cache
def _make_sb3_class() -> type:
    from stable_baselines3.common.vec_env import VecEnv

    class BabyRobotSB3VecEnv(VecEnv):
        """A Stable-Baselines3 ``VecEnv`` over a Gymnasium batch vector env (see ``sb3_vec_env``)."""

        def __init__(self, venv: _BatchVectorEnv):
            self.venv_gym = venv
            self._actions: np.ndarray | None = None
            super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)

        def reset(self) -> np.ndarray:
            v, r = self.venv_gym, self.venv_gym.n_robots
            envs = np.arange(v.n_envs)
            seeds = [self._seeds[i * r] for i in envs]
            options = [self._options[i * r] or {} for i in envs]
            starts = [v._start_option(check_options(o)) for o in options]  # every option checked before any change
            v._seed_envs(list(zip(envs.tolist(), v._seed_list(seeds))))
            v._restart(envs, starts)
            v._autoreset[:] = False
            v._started = True
            self._reset_seeds()
            self._reset_options()
            self.reset_infos = [{} for _ in range(self.num_envs)]
            return v._observations()

        def seed(self, seed: int | None = None) -> list[int | None]:
            if seed is None:
                seed = int(np.random.randint(0, np.iinfo(np.uint32).max, dtype=np.uint32))
            r = self.venv_gym.n_robots
            self._seeds = [int(seed) + k // r for k in range(self.num_envs)]
            return list(self._seeds)

        def step_async(self, actions: np.ndarray) -> None:
            self._actions = actions

        def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
            v = self.venv_gym
            acts = v._check_actions(self._actions)
            if not v._started:
                raise RuntimeError("step: call reset() before the first step()")
            b = v._batch
            rewards, _, _, _, over = b.step(acts)
            obs = v._observations()
            dones = np.repeat(over, v.n_robots)
            truncated = (over[:, None] & b.racing).reshape(-1)
            infos: list[dict[str, Any]] = [{"TimeLimit.truncated": t} for t in truncated.tolist()]
            if over.any():
                for k in np.flatnonzero(dones).tolist():
                    infos[k]["terminal_observation"] = obs[k]
                b.reset_envs(np.flatnonzero(over))
                obs = v._observations()
            return obs, rewards.reshape(-1).astype(np.float32), dones, infos

        def close(self) -> None:
            self.venv_gym.close()

        def get_attr(self, attr_name: str, indices=None) -> list[Any]:
            """Attributes of the env each slot copies (``level``, ``render_mode``, ...): one value for all."""
            value = getattr(self.venv_gym, attr_name)
            return [value for _ in self._get_indices(indices)]

        def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
            raise NotImplementedError("set_attr: the envs share one batch engine; make a new env with other settings")

        def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list[Any]:
            raise NotImplementedError("env_method: the envs share one batch engine and have no env objects")

        def env_is_wrapped(self, wrapper_class: type, indices=None) -> list[bool]:
            return [False for _ in self._get_indices(indices)]

        def get_images(self) -> list[np.ndarray]:
            """Each slot's env frame (``render_mode="rgb_array"``)."""
            v = self.venv_gym
            if v.render_mode != "rgb_array":
                raise ValueError(f"get_images: needs render_mode='rgb_array', got {v.render_mode!r}")
            frames = v.render()
            return [frames[k // v.n_robots] for k in range(self.num_envs)]

    return BabyRobotSB3VecEnv
