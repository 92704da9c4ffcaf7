"""Vector envs on the batch engine: many Baby Robots stepped as numpy arrays, no Python loop per env.

Three shells over one ``core.batch.BatchRace``:

* ``BabyRobotVectorEnv``: ``num_envs`` copies of ``BabyRobot-v0`` as a ``gymnasium.vector.VectorEnv``;
  ``gymnasium.make_vec("babyrobot_marl/BabyRobot-v0", num_envs=N, vectorization_mode="vector_entry_point")``.
* ``RaceVectorEnv``: ``n_envs`` races of ``n_robots`` as one ``VectorEnv`` of ``n_envs * n_robots`` slots
  for parameter sharing (one policy drives every robot), the race in ``race_v0``'s ``finished="freeze"`` view.
* ``sb3_vec_env(...)``: either of them as a Stable-Baselines3 ``VecEnv`` (same-step auto-reset; ``envs/sb3.py``).

Env ``i`` of a vector env plays exactly the episodes of a single env (``BabyRobotEnv`` /
``race_v0.parallel_env(finished="freeze")``) reset with seed ``seed + i`` and given the same actions,
across auto-resets: same observations, rewards, terminations and truncations.

Both Gymnasium vector envs take ``autoreset_mode=`` (``envs/autoreset.py``) and ``obs_encoding=``
(``babyrobot_marl.encodings``), and report infos as numbers with the same keys at every step.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import batch_space

from ..core.actions import N_ACTIONS
from ..core.batch import BatchRace
from ..core.checks import check_count
from ..core.engine import STAYED
from ..core.level import Cell, Level
from ..core.outcomes import FINISHED, START
from ..core.rules import Rules, known_args
from ..render.ansi import frame
from ..render.rgb import Theme
from .autoreset import DISABLED, NEXT_STEP, SAME_STEP, final_infos, resolve_autoreset_mode, set_reset_values, with_masks
from .checks import (
    check_actions,
    check_cells,
    check_envs,
    check_goal_cells,
    check_goals_reach,
    check_no_goals,
    check_options,
    check_render_mode,
    check_sb3_autoreset,
    check_start,
    mask_envs,
    seed_list,
)
from .encodings import Encoder
from .race import RaceEnv
from .single import BabyRobotEnv
from .vector_reset import restart, seed_envs

if TYPE_CHECKING:
    from stable_baselines3.common.vec_env import VecEnv

__all__ = ["BabyRobotVectorEnv", "RaceVectorEnv", "sb3_vec_env"]

_INTENDED = np.array([code <= STAYED for code in range(5)] + [False])  # by engine code; -1 (parked) reads the last
_RENDER_MODES = ["rgb_array", "ansi"]
SINGLE_ARGS = ("num_envs", "level", "rules", "max_steps", "start", "render_mode", "cell_size", "theme", "obs_encoding",
                "autoreset_mode")  # fmt: skip
RACE_ARGS = ("n_envs", "level", "n_robots", "collisions", "max_cycles", "start", "rules", "render_mode", "cell_size",
              "theme", "observe", "view_radius", "k", "obs_encoding", "autoreset_mode", "goals", "lifelong")  # fmt: skip


class _BatchVectorEnv(gym.vector.VectorEnv):
    """What both Gymnasium vector envs share: seeding, resets, action checks, the three auto-reset modes.

    The batch has ``n_envs`` envs of ``n_robots`` robots; the vector env has
    ``num_envs = n_envs * n_robots`` slots, slot ``env * n_robots + robot``.
    """

    metadata: dict[str, Any] = {"render_modes": _RENDER_MODES, "render_fps": 4}
    _options_known: tuple[str, ...] = ("reset_mask",)

    _ref: BabyRobotEnv | RaceEnv  # a single env holding the resolved level, rules and renderer
    _batch: BatchRace

    def _setup(self, ref: BabyRobotEnv | RaceEnv, batch: BatchRace, render_mode: str | None, autoreset_mode: object) -> None:
        self._ref, self._batch, self.table = ref, batch, ref.table
        self.n_envs, self.n_robots = batch.n_envs, batch.n_robots
        self.num_envs = self.n_envs * self.n_robots
        self.autoreset_mode, self._mode = resolve_autoreset_mode(autoreset_mode)
        # an instance's own copy, as SyncVectorEnv keeps, with the mode Gymnasium's wrappers read
        self.metadata = {**type(self).metadata, "autoreset_mode": self.autoreset_mode}
        self.render_mode = check_render_mode(render_mode, self.metadata["render_modes"])
        self.single_action_space = spaces.Discrete(N_ACTIONS)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.encoder: Encoder = ref.encoder
        self.single_observation_space = self.encoder.space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._autoreset = np.zeros(self.n_envs, dtype=bool)  # envs whose episode ended on the last step
        self._all_slots = np.ones(self.num_envs, dtype=bool)
        self._no_envs = np.zeros(self.n_envs, dtype=bool)  # no env to reset first (same-step, disabled)
        self._no_envs.setflags(write=False)
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
        opts = dict(check_options(options, self._options_known))
        envs = mask_envs(opts.pop("reset_mask", None), self.n_envs, self.n_robots)
        seeds = seed_list(seed, self.n_envs)
        start = self._start_option(opts)
        seed_envs(self._batch, [(i, seeds[i]) for i in envs])
        restart(self._batch, envs, [start] * len(envs))
        self._batch.given_goals = None  # given goals hold for this reset only, as given starts do
        self._autoreset[envs] = False
        self._started = True
        slots = np.zeros(self.n_envs, dtype=bool)
        slots[envs] = True
        slots = np.repeat(slots, self.n_robots)
        obs = self._observations()
        values = self._info_values(obs, np.full(self.num_envs, START), np.zeros(self.num_envs, dtype=bool))
        set_reset_values(values, slots, START)
        # as SyncVectorEnv: only the reset envs have the keys (their masks); the others read zeros
        values = {k: np.where(slots.reshape(-1, *([1] * (v.ndim - 1))), v, np.zeros_like(v)) for k, v in values.items()}
        return self._encoded(obs), with_masks(values, slots)

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Step every env; what happens to an env whose episode ended depends on ``autoreset_mode``.

        Next-step (default): the step after it ended resets it instead; its slots return the new
        episode's first observation, reward 0, not done, and its action is ignored. Same-step: it
        is reset in the step it ends; the observation is the new episode's, ``info["final_obs"]``
        and ``info["final_info"]`` hold the last ones. Disabled: stepping it is an error until
        ``reset(options={"reset_mask": ...})`` restarts it.
        """
        acts = check_actions(actions, self.n_envs, self.n_robots)
        if not self._started:
            raise RuntimeError("step: call reset() before the first step()")
        b, mode = self._batch, self._mode
        if mode == DISABLED and np.count_nonzero(self._autoreset):
            ended = np.flatnonzero(self._autoreset).tolist()
            raise RuntimeError(
                f"step: env(s) {ended} have ended and autoreset_mode is disabled; "
                "restart them with reset(options={'reset_mask': mask}) first"
            )
        reset = self._autoreset if mode == NEXT_STEP else self._no_envs
        rewards, finishing, blocked, outcome, over = b.step(acts)
        n_reset = np.count_nonzero(reset)
        if n_reset:
            # the envs stepped above are restarted; their new episode starts from their own generators
            restart(self._batch, np.flatnonzero(reset), None)
            rewards[reset] = 0.0
            over = over & ~reset
        obs = self._observations()
        if self.n_robots == 1:  # a lone robot's episode ends at the exit (terminated) or the step limit
            terminated = finishing.reshape(-1)
            truncated = over ^ terminated
        else:
            ended = over[:, None]
            truncated = ended & b.racing
            terminated = (truncated ^ ended).reshape(-1)  # ended and not racing
            truncated = truncated.reshape(-1)
        values = self._info_values(obs, outcome.reshape(-1), blocked.reshape(-1))
        if n_reset:
            set_reset_values(values, reset if self.n_robots == 1 else np.repeat(reset, self.n_robots), START)
        extra: dict[str, Any] = {}
        if mode == SAME_STEP and np.count_nonzero(over):
            done = np.repeat(over, self.n_robots)
            extra = final_infos(self._encoded(obs), {k: v.copy() for k, v in values.items()}, done)
            restart(self._batch, np.flatnonzero(over), None)
            obs = self._observations()
            values = self._info_values(obs, values["outcome"], values.get("blocked", np.zeros(self.num_envs, dtype=bool)))
            set_reset_values(values, done, START)
            over = np.zeros(self.n_envs, dtype=bool)
        self._autoreset = over
        infos = with_masks(values, self._all_slots)
        infos.update(extra)
        return obs if self.encoder.identity else self.encoder(obs), rewards.reshape(-1), terminated, truncated, infos

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
        """The raw ``MultiDiscrete`` rows, one per slot (infos read their ``[x, y]``)."""
        return self._batch.observations().reshape(self.num_envs, -1)

    def _encoded(self, obs: np.ndarray) -> np.ndarray:
        return self.encoder(obs)

    def _info_values(self, obs: np.ndarray, outcome: np.ndarray, blocked: np.ndarray) -> dict[str, np.ndarray]:
        raise NotImplementedError

    def _start_option(self, options: Mapping[str, Any]) -> tuple[int, ...] | None:
        """Start cell ids from ``options`` (one per robot); None: the usual starts."""
        return None

    def _robots(self, i: int) -> list[Cell | None]:
        if not self._started:
            return []
        b = self._batch
        return [self._xy[c] if r else None for c, r in zip(b.cells[i].tolist(), b.racing[i].tolist())]


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
    int64. ``single_observation_space`` is ``MultiDiscrete([width, height])``; with
    ``obs_encoding="box"`` or ``"onehot"`` the single env's float32 ``Box`` instead.

    ## Rewards, dynamics, episode end

    As ``BabyRobotEnv``: rewards float64 of shape ``(num_envs,)``, ``terminated`` when the robot
    reaches an exit, ``truncated`` after ``max_steps`` steps (never both).

    ## Auto-reset

    ``autoreset_mode=`` (``.autoreset_mode`` and ``metadata["autoreset_mode"]``, Gymnasium's
    ``AutoresetMode``): ``"next-step"`` (default), ``"same-step"`` or ``"disabled"``, each as
    ``SyncVectorEnv(..., autoreset_mode=...)`` (see ``step``). A new episode draws from the env's
    own generator, as a single env's ``reset()`` without a seed.

    ## Seeding

    ``reset(seed=s)`` gives env ``i`` the seed ``s + i``; ``reset(seed=[s0, s1, ...])`` one each.
    Env ``i`` then plays exactly the episodes of ``BabyRobotEnv(...)`` reset with that seed and
    stepped with the same actions (a ``SyncVectorEnv`` of them gives the same arrays).

    ## Info

    Gymnasium's vector convention, each key with a ``"_key"`` mask: the single env's keys as
    arrays, at every step for every env (masks all True; after a masked reset, the reset envs):
    ``"cell"`` int64 ``(num_envs, 2)``, ``"outcome"`` int64 codes (``babyrobot_marl.OUTCOME_NAMES``;
    5 start for an env reset in that step), ``"intended"`` bool. Same-step mode adds
    ``"final_obs"`` and ``"final_info"`` for the envs that ended.

    ## Arguments

    ``num_envs``, then exactly ``BabyRobotEnv``'s: ``level``, ``rules``, ``max_steps``, ``start``,
    ``render_mode`` (``None``, ``"rgb_array"`` or ``"ansi"``: ``render()`` returns one frame per
    env), ``cell_size``, ``theme``, ``obs_encoding``, and rule overrides (``glass_pass_prob=0.9``);
    and ``autoreset_mode``. ``reset(options={"start": (x, y)})`` starts every reset env at that
    cell; ``options["reset_mask"]`` resets only some envs.
    """

    _options_known = ("start", "reset_mask")

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
        obs_encoding: str = "multidiscrete",
        autoreset_mode: object = NEXT_STEP,
        **rule_overrides: Any,
    ):
        known_args("BabyRobotVectorEnv", rule_overrides, SINGLE_ARGS)
        n = check_envs(num_envs, "num_envs")
        ref = BabyRobotEnv(
            level=level,
            rules=rules,
            max_steps=max_steps,
            start=start,
            cell_size=cell_size,
            theme=theme,
            obs_encoding=obs_encoding,
            **rule_overrides,
        )
        self._setup(ref, ref.batch(n), render_mode, autoreset_mode)
        self.level, self.rules, self.max_steps = ref.level, ref.rules, ref.max_steps

    def _start_option(self, options: Mapping[str, Any]) -> tuple[int, ...] | None:
        start = options.get("start")
        return None if start is None else (check_start(self._ref.table, start),)

    def _robots(self, i: int) -> list[Cell | None]:
        return [self._xy[int(self._batch.cells[i, 0])]] if self._started else []  # at its exit too, as the single env draws it

    def _info_values(self, obs: np.ndarray, outcome: np.ndarray, blocked: np.ndarray) -> dict[str, np.ndarray]:
        code = outcome.astype(np.int64, copy=False)  # the batch's codes are a new array each step, held by nobody else
        return {"cell": obs.copy(), "outcome": code, "intended": _INTENDED.take(code)}


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
    ``MultiDiscrete([W, H] + [W, H, 2] * (n_robots - 1))``, or a float32 ``Box`` with
    ``obs_encoding="box"`` / ``"onehot"``.

    ## Rewards

    As ``race_v0``: the cell's reward, ``win_bonus`` for finishing first, 0 for parked robots.

    ## Episode end

    A race ends when all its robots have finished or after ``max_cycles`` steps. All its slots
    are then done together: ``terminated`` for the robots that finished, ``truncated`` for the
    others. Until then a finished robot's slot is parked (reward 0, not done), as in
    ``finished="freeze"``.

    ## Auto-reset

    ``autoreset_mode=``: ``"next-step"`` (default), ``"same-step"`` or ``"disabled"``, race by race,
    as ``BabyRobotVectorEnv``: next-step restarts a race in the step after it ended (its slots
    return the new race's first observations, reward 0, not done).

    ## Seeding

    ``reset(seed=s)`` gives race ``i`` the seed ``s + i``; a list gives one seed per race
    (``n_envs`` entries, not one per slot).

    ## Info

    Per slot, every key at every step (masks all True), as ``race_v0``'s infos: ``"cell"``
    (int64 ``(num_envs, 2)``), ``"outcome"`` (int64 codes into ``babyrobot_marl.OUTCOME_NAMES``:
    6 finished once parked, 5 start after a reset), ``"blocked"``, ``"finished"`` (bool) and
    ``"rank"`` (int64, 0 until the robot finishes).

    ## Arguments

    ``n_envs`` (races), then ``race_v0.parallel_env``'s: ``level``, ``n_robots``, ``collisions``,
    ``max_cycles``, ``start``, ``rules``, ``render_mode`` (``None``, ``"rgb_array"``, ``"ansi"``:
    one frame per race), ``cell_size``, ``theme``, ``obs_encoding``, rule overrides; and
    ``autoreset_mode``. ``finished`` is always ``"freeze"``. ``reset(options={"starts": [(x, y), ...]})``
    places the robots of every reset race.

    ``goals="own"``: each robot its own target, as in ``race_v0`` (drawn at each race's reset from
    its generator, after the starts: the single env's targets for the same seed), and rows end with
    the target's columns. ``reset(options={"goals": [(x, y), ...]})`` gives every reset race those
    targets for that reset (with ``"starts"``, or ``start="level"``: given targets are checked
    against known starts); auto-resets draw new ones. ``lifelong=True`` (with own goals): a robot on
    its target gets a new one and keeps going, as in ``race_v0``; races end at ``max_cycles``.
    """

    _options_known = ("starts", "reset_mask")

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
        obs_encoding: str = "multidiscrete",
        autoreset_mode: object = NEXT_STEP,
        **rule_overrides: Any,
    ):
        if rule_overrides.pop("finished", "freeze") != "freeze":
            raise ValueError("finished: a vector race keeps finished robots parked until the race ends ('freeze')")
        known_args("RaceVectorEnv", rule_overrides, RACE_ARGS)
        n = check_envs(n_envs, "n_envs", n_robots, rule_overrides.get("observe", "global"))
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
            obs_encoding=obs_encoding,
            **rule_overrides,
        )
        self._setup(ref, ref.batch(n), render_mode, autoreset_mode)
        self.level, self.rules, self.max_cycles, self.collisions = ref.level, ref.rules, ref.max_cycles, ref.collisions
        if ref.goals_mode == "own":
            self._options_known = ("starts", "goals", "reset_mask")

    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None):
        check_no_goals(options, self._ref.goals_mode)
        return super().reset(seed=seed, options=options)

    def _start_option(self, options: Mapping[str, Any]) -> tuple[int, ...] | None:
        starts = options.get("starts")
        starts = None if starts is None else tuple(check_cells(self.table, starts, self.n_robots, 'options["starts"]'))
        self._batch.given_goals = None if options.get("goals") is None else self._goal_option(options["goals"], starts)
        return starts

    def _goal_option(self, goals: object, starts: tuple[int, ...] | None) -> np.ndarray:
        """``options["goals"]`` as cell ids, checked against the starts: given ones, or the level's own (``start="level"``)."""
        ids = check_goal_cells(self.table, goals, self.n_robots, self._ref.goals_mode)
        if starts is None and self._ref.start != "level":
            raise ValueError('options["goals"]: a vector race takes given goals with known starts: pass "starts" too '
                             f"(or start='level'); this race draws its starts (start={self._ref.start!r})")
        check_goals_reach(self.table, ids, starts if starts is not None else self._batch.fixed.tolist())
        return np.array(ids, dtype=np.int64)

    def _info_values(self, obs: np.ndarray, outcome: np.ndarray, blocked: np.ndarray) -> dict[str, np.ndarray]:
        b = self._batch
        code = outcome.astype(np.int64)
        return {
            "cell": obs[:, :2].copy(),
            "outcome": np.where(code < 0, FINISHED, code),
            "blocked": blocked.copy(),
            "finished": ~b.racing.reshape(-1),
            "rank": b.rank.reshape(-1).astype(np.int64),
        }


# ---------------------------------------------------------------------------- Stable-Baselines3
def sb3_vec_env(level: str | Level | None = None, n_envs: int = 1, n_robots: int = 1, **kwargs: Any) -> VecEnv:
    """A Stable-Baselines3 ``VecEnv`` over the batch engine (it pickles with the standard ``pickle``).

    ``n_robots == 1``: ``n_envs`` copies of ``BabyRobot-v0``; ``kwargs`` are ``BabyRobotEnv``'s
    (``rules``, ``max_steps``, ``start``, ``render_mode``, ``obs_encoding``, rule overrides); ``level``
    defaults to ``"default"``. ``n_robots > 1``: ``n_envs`` races sharing one policy, ``num_envs =
    n_envs * n_robots`` (slot ``env * n_robots + robot``); ``kwargs`` are ``race_v0``'s
    (``collisions``, ``max_cycles``, ``start``, ...); ``level`` defaults to ``"race-2"``.

    SB3 semantics: ``step`` returns ``(obs, rewards, dones, infos)`` with rewards float32; an env
    that ends is reset in the same step (all slots of a race together), its last observation in
    ``infos[k]["terminal_observation"]``; ``infos[k]["TimeLimit.truncated"]`` is True when the
    slot was truncated (``max_steps`` / ``max_cycles``) rather than terminated, on every step as
    ``DummyVecEnv`` does. ``seed(s)`` seeds the next ``reset()``: env (race) ``i`` gets ``s + i``,
    the episodes a single env reset with that seed plays; it returns the seed of each slot.
    ``set_options({"start": (x, y)})`` (one robot) or ``{"starts": [...]}`` (a race) applies to the
    next ``reset()``. ``autoreset_mode`` may only be ``"same-step"``, the one SB3 has (its
    ``VecEnv`` always resets an env in the step it ends); any other is refused.

    Needs ``stable-baselines3``: ``pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu``,
    then ``pip install "babyrobot_marl[train]"`` (torch first: its CPU build, not the ~3 GB CUDA one).
    """
    try:
        import stable_baselines3  # noqa: F401
    except ImportError as err:
        raise ImportError(
            "sb3_vec_env needs stable-baselines3 (the train extra): pip install torch==2.13.0 --index-url "
            "https://download.pytorch.org/whl/cpu, then pip install 'babyrobot_marl[train]' (torch first: its CPU build, "
            "not the ~3 GB CUDA one)") from err
    from .sb3 import BabyRobotSB3VecEnv
    if "autoreset_mode" in kwargs:
        check_sb3_autoreset(kwargs["autoreset_mode"])
    if check_count(n_robots, "n_robots") == 1:
        venv: _BatchVectorEnv = BabyRobotVectorEnv(n_envs, **({"level": level} if level is not None else {}), **kwargs)
    else:
        venv = RaceVectorEnv(n_envs, **({"level": level} if level is not None else {}), n_robots=n_robots, **kwargs)
    return BabyRobotSB3VecEnv(venv)
