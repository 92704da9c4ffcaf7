"""The race: a PettingZoo ``ParallelEnv`` shell over the shared core (``core.race.race_step``)."""

from __future__ import annotations

import operator
from collections.abc import Mapping, Sequence
from functools import partial
from itertools import compress
from typing import Any

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from ..core.actions import N_ACTIONS
from ..core.batch import BatchRace
from ..core.checks import check_action, check_choice, check_count, check_global_view, check_seed, check_view_numbers
from ..core.goals import GOAL_MODES, GoalColumns, channel_marks, goal_offsets, row_starts
from ..core.level import Cell, Level
from ..core.observe import global_gather, make_observer, with_hint
from ..core.outcomes import START
from ..core.race import race_step
from ..core.rng import new_key
from ..core.rules import COLLISION_MODES, Rules, resolve_rules
from ..levels.sources import LevelPicker
from ..planning.hint import optimal_actions
from ..render.checks import check_animation_frames, check_cell_size, check_fps, check_frame_size
from ..render.rgb import Theme, resolve_theme
from .checks import (
    check_cells,
    check_finished,
    check_hint,
    check_lifelong,
    check_no_goals,
    check_options,
    check_render_mode,
)
from .drawing import EnvDrawing, OverlayMethods
from .encodings import Encoder
from .race_goals import RaceGoals, next_goals, staying_outputs
from .race_levels import RaceLevels, cell_arrays
from .race_outputs import outputs_with_parked, racing_outputs
from .race_readouts import RaceReadouts
from .single import default_max_steps
from .starts import new_generator

START_MODES = ("level", "fill", "random")
FINISHED_MODES = ("remove", "freeze", "stay")  # "stay": own goals only (POGEMA's on_target="nothing")
# actions on the fast path: Python ints 0..4 (bools, numpy ints and the rest are checked one by one)
_ACTIONS, _INT = frozenset(range(N_ACTIONS)), frozenset({int})
_LAYOUTS, _LAYOUT_SIZE = 256, 4096  # gathers kept per env, and the largest kept (int indices)
_ARGS = (
    "level", "n_robots", "collisions", "max_cycles", "start", "finished", "rules", "render_mode", "cell_size", "theme",
    "animation_frames", "render_fps", "observe", "view_radius", "k", "obs_encoding", "hint", "goals", "lifelong",
)


class RaceEnv(RaceGoals, RaceLevels, RaceReadouts, OverlayMethods, ParallelEnv):
    """Several Baby Robots race to the exit. See ``babyrobot_marl.race_v0`` for the full table."""

    metadata = {
        "render_modes": ["ansi", "rgb_array", "human"],
        "name": "babyrobot_race_v0",
        "is_parallelizable": True,
        "render_fps": 4,
    }

    def __init__(
        self,
        level: str | Level = "race-2",
        n_robots: int = 2,
        collisions: str | None = None,
        max_cycles: int | None = None,
        start: str = "level",
        finished: str = "remove",
        rules: Rules | Mapping[str, Any] | None = None,
        render_mode: str | None = None,
        cell_size: int | None = None,
        theme: str | Theme = "light",
        animation_frames: int = 4,
        render_fps: float | None = None,
        observe: str = "global",
        view_radius: int | None = None,
        k: int | None = None,
        obs_encoding: str = "multidiscrete",
        hint: bool = False,
        goals: str = "exit",
        lifelong: bool = False,
        **rule_overrides: Any,
    ):
        self.goals_mode = check_choice(goals, "goals", GOAL_MODES)
        self.lifelong = check_lifelong(lifelong, self.goals_mode)
        # level= a family or a callable: drawn per reset; with own goals a level needs no exit
        self.levels = LevelPicker(level, need_exit=self.goals_mode == "exit")
        self.level = self.levels.first
        if collisions is not None:
            if collisions not in COLLISION_MODES:
                raise ValueError(f"collisions: must be one of {', '.join(map(repr, COLLISION_MODES))}, got {collisions!r}")
            rule_overrides["collisions"] = collisions
        self.rules = resolve_rules(rules, rule_overrides, "RaceEnv", _ARGS)
        self.collisions = self.rules.collisions
        self.table = self._compile(self.level)
        self._observer_of = partial(make_observer, observe=observe, view_radius=view_radius, k=k)
        self.observe, self._observer = observe, self._observer_of(self.table)  # None: "global"
        self._first_observer, self.hint = self._observer, check_hint(hint, observe)
        own = self.goals_mode == "own"  # own goals: their columns (and hint) follow the observer's rows
        view = self._observer.view if self._observer is not None else None  # "local": the target channel's window
        self._goal_columns = GoalColumns(view and view.radius, self.hint, *self.levels.largest) if own else None
        if self.hint and not own:  # the goal hint: planned once per level (planning.hint, cached)
            self._observer = with_hint(self._observer, optimal_actions(self.level, self.rules))
        self.n_robots = n = check_count(n_robots, "n_robots")
        self.max_cycles = default_max_steps(self.level) if max_cycles is None else check_count(max_cycles, "max_cycles")
        if start not in START_MODES:
            raise ValueError(f"start: must be one of {', '.join(map(repr, START_MODES))}, got {start!r}")
        self.start, self.finished_mode = start, check_finished(finished, FINISHED_MODES, self.goals_mode, self.lifelong)
        self._fixed_starts, self._free = self._placement(n)
        self.render_mode = check_render_mode(render_mode, self.metadata["render_modes"])
        self.cell_size, self.theme = check_cell_size(cell_size, self.level), resolve_theme(theme)
        if self.render_mode in ("rgb_array", "human"):  # its frames show the legend: all of it within the limit
            check_frame_size(self.level, self.cell_size, robots=n)
        self.animation_frames = check_animation_frames(animation_frames)
        if render_fps is not None:  # this env's own metadata: the class's stays as it is
            self.metadata = {**type(self).metadata, "render_fps": check_fps(render_fps)}
        self.drawing = EnvDrawing(self.level, self.cell_size, self.theme, self.animation_frames, robots=n, fit=cell_size is None)
        self._np_random: np.random.Generator | None = None  # made at first use (np_random)

        w, h = self.level.width, self.level.height
        self.possible_agents = [f"robot_{i}" for i in range(n)]
        self._index = {a: i for i, a in enumerate(self.possible_agents)}
        # any observation mode's MultiDiscrete, encoded as obs_encoding asks (encodings.py)
        nvec = list(self._observer.nvec) if self._observer else [w, h] + [w, h, 2] * (n - 1)
        self.encoder = Encoder(nvec + (self._goal_columns.nvec if own else []), obs_encoding)
        self._obs_space = self.encoder.space
        self._act_space = spaces.Discrete(5)
        self.observation_spaces = dict.fromkeys(self.possible_agents, self._obs_space)
        self.action_spaces = dict.fromkeys(self.possible_agents, self._act_space)
        self._encode_state = Encoder([w, h, 2] * n, obs_encoding)
        self.state_space = (
            spaces.Box(0, np.array([w - 1, h - 1, 1] * n), shape=(3 * n,), dtype=np.int64)
            if self._encode_state.identity
            else self._encode_state.space
        )
        if self._observer is None:
            check_global_view(n)
        else:  # "local" or "nearest": rows of a bounded size, but n of them
            check_view_numbers(n, len(self._observer.nvec), "view_radius" if observe == "local" else "k")
        self._gather = global_gather(n if self._observer is None else 0)  # robot i sees i, i+1, ..., i-1: "global" only
        self._layouts: dict[tuple, np.ndarray] = {}  # _set_layout's gathers by robot numbers: races repeat finishing orders
        self._lists, self._sure_flat, self._reward_at, self._xy, self._cell_xy, self._xyf = cell_arrays(self.table)
        self._cell_key, self._channel = self._goal_tables()
        # The state: the racing robots (`_live`, robot numbers, ascending) and their cells, and the
        # finished ones (`_done`) with their `_xyf` rows (`_parked`). Steps work on the racing
        # robots only; observations gather from the rows of `_live_cells + _parked`.
        self._live: list[int] = []
        self._live_cells: Sequence[int] = []
        self._done: list[int] = []
        self._parked: list[int] = []
        self._set_agents([])
        self._all_racing = np.ones(n, dtype=bool)  # every robot's racing flag while nobody has finished
        self._all_racing.setflags(write=False)
        self._rank: list[int] = []
        self._returns: list[float] = []  # of the finished robots; the racing ones' in _live_returns
        self._live_returns: list[float] = []
        self._bumps: list[int] = []  # of the finished robots; the racing ones' in _live_bumps
        self._live_bumps: list[int] = []
        self._last_step: tuple | None = None  # what the last step did, for the pictures (drawing.py)
        self._t = 0
        self._key = 0
        self._n_finished = 0
        self._goal_of: list[int] | None = None  # own goals: each robot's target cell
        self._reached: list[int] = []  # own goals: targets each robot reached this episode
        self._started = False

    # ----------------------------------------------------------------------- PettingZoo API
    def observation_space(self, agent: str) -> spaces.MultiDiscrete:
        self._agent_index(agent)
        return self._obs_space

    def action_space(self, agent: str) -> spaces.Discrete:
        self._agent_index(agent)
        return self._act_space

    def reset(self, seed: int | None = None, options: dict | None = None):
        """A new race. ``options={"starts": [(x, y), ...]}``: one distinct open cell per robot;
        ``"goals"`` (``goals="own"``): one distinct target cell per robot, reachable from its start."""
        check_no_goals(options, self.goals_mode)
        opts = check_options(options, ("starts", "goals") if self.goals_mode == "own" else ("starts",))
        starts, goals = self._cell_options(opts)
        seed = check_seed(seed)
        if seed is not None:
            self.np_random = new_generator(seed)
        drawn = self.levels.draw(self.np_random, self.level)
        if drawn is not None:
            self._use_level(drawn)
            starts, goals = self._cell_options(opts)  # checked again on the level just drawn
        self._key = new_key(self.np_random)
        if starts is None:
            starts = self._draw_starts(goals)
        self._goal_of = self._goals_for(starts, goals)
        self._goal_arr = None if self._goal_of is None else np.array(self._goal_of, dtype=np.int64)
        self._reached = [0] * self.n_robots
        n = self.n_robots
        self._started = True
        self._live, self._live_cells = list(range(n)), starts
        self._done, self._parked = [], []
        self._rank = [0] * n
        self._returns = [0.0] * n
        self._live_returns = [0.0] * n
        self._bumps = [0] * n
        self._live_bumps = [0] * n
        self._last_step = None
        self._t = 0
        self._n_finished = 0
        self._set_agents(self._live)
        if self.render_mode == "human":
            self.render()
        obs = self._observations()
        infos = {
            a: {"cell": xy, "outcome": START, "blocked": False, "finished": False, "rank": 0}
            for a, xy in zip(self.possible_agents, self._cell_xy.take(self._live_cells, axis=0))
        }
        return dict(zip(self.possible_agents, obs)), infos

    def step(self, actions: Mapping[str, Any]):
        reported = self.agents
        if not reported:
            self._check_started("step")
            if actions:
                raise ValueError("actions: the race is over (no agents left); call reset() before stepping again")
            return {}, {}, {}, {}, {}
        # The common case: one int action 0..4 per racing robot, in `agents` order (a plain loop: few
        # robots); anything else is checked one by one by _check_actions, raising before anything changes.
        if type(actions) is dict and self._reported_live and list(actions) == reported:
            acts = list(actions.values())
            if not (_INT.issuperset(map(type, acts)) and _ACTIONS.issuperset(acts)):  # both in C, no loop here
                acts = self._check_actions(actions)
        else:
            acts = self._check_actions(actions)
        live, t = self._live, self._t
        cells, outcome, blocked, finishing = race_step(
            self._lists, self.collisions, self._live_cells, acts, self._key, t, live, self.n_robots, self._sure_flat
        )
        reached = marks = None
        # "local" and "nearest": the cells as an array, once (own goals, observations, infos)
        here = None if self._observer is None else np.fromiter(cells, np.int64, len(cells))
        if self._goal_of is not None:  # own goals: finished on its own target (the table has no exits)
            finishing, reached, marks = self._own_goals_step(live, cells, here, finishing)
        self._last_step = (live, self._live_cells, acts, outcome, blocked, finishing, t)
        self._live_cells = cells
        self._t = t = t + 1
        if True in blocked:
            self._live_bumps = list(map(operator.add, self._live_bumps, blocked))
        if True in finishing or t >= self.max_cycles or not self._reported_live or reached:
            if reached and self.finished_mode == "stay":  # robots on their targets: they stay, racing
                out, self._live_returns, over = staying_outputs(self, cells, here, outcome, blocked, reached, marks)
                if over:
                    self._set_agents([])
            else:
                rewards = list(map(self._reward_at.__getitem__, cells))
                if reached:  # lifelong: the target's step earns the exit reward
                    rewards = [self.rules.exit_reward if r else x for r, x in zip(reached, rewards)]
                out = self._step_general(cells, outcome, blocked, finishing, rewards)  # rarely: the cells change
        else:  # the common step: nobody finishes, the race goes on, the agents are the racing robots
            # the dicts by zip; infos fresh dicts, their cells rows of one fresh array (users keep and change them)
            rewards = dict(zip(reported, map(self._reward_at.__getitem__, cells)))
            self._live_returns = list(map(operator.add, self._live_returns, rewards.values()))
            infos = {
                a: {"cell": xy, "outcome": o, "blocked": b, "finished": False, "rank": 0}
                for a, xy, o, b in zip(reported, self._cell_xy.take(cells if here is None else here, axis=0), outcome, blocked)
            }
            no = self._none_done
            out = dict(zip(reported, self._observations(here, marks))), rewards, no.copy(), no.copy(), infos
        if self.render_mode == "human":
            self.render()
        return out

    def _step_general(
        self, cells: Sequence[int], outcome: Sequence[int], blocked: list[bool], finishing: list[bool], rewards: list[float]
    ):
        """The outputs of any step: robots finishing, the race ending, parked robots reported (freeze)."""
        live, all_racing, keep = self._live, self._reported_live, None  # before this step's finishers leave
        if True in finishing:  # ranks, and the bonus of the robots finishing first (no race with own goals)
            own, first = self._goal_of is not None, self._n_finished == 0
            rank = self._n_finished + 1
            for k in compress(range(len(live)), finishing):
                self._rank[live[k]] = rank
                self._n_finished += 1
                if own:  # reaching its target: the exit reward
                    rewards[k] = self.rules.exit_reward
                elif first:
                    rewards[k] += self.rules.win_bonus
        returns = list(map(operator.add, self._live_returns, rewards))
        if True in finishing:  # the finishers leave the board for their parking rows
            keep, n_cells = list(map(operator.not_, finishing)), self.table.n_cells
            for i, r, b in compress(zip(live, returns, self._live_bumps), finishing):
                self._returns[i], self._bumps[i] = r, b
            self._done = [*self._done, *compress(live, finishing)]
            self._parked = [*self._parked, *(n_cells + c for c in compress(cells, finishing))]
            self._live, self._live_cells = list(compress(live, keep)), list(compress(cells, keep))
            returns, self._live_bumps = list(compress(returns, keep)), list(compress(self._live_bumps, keep))
            self._set_layout()
        self._live_returns = returns
        over = self._t >= self.max_cycles or not self._live
        reported, ids, ranks = self.agents, self._agent_ids, self._rank
        # parked robots (freeze) are terminated only when the race ends: PettingZoo expects a
        # terminated agent to leave `agents` in the same step
        parked_done = over or self.finished_mode == "remove"
        if all_racing:  # every reported agent was racing (always with "remove"): the dicts by zip
            xy = self._cell_xy.take(cells, axis=0)  # infos' "cell": rows of one fresh array
            rows = self._finishing_rows(live, cells, keep) if keep else None  # the finishers' last rows too
            rows = self._observations() if rows is None else rows
            out = racing_outputs(reported, rows, rewards, outcome, blocked, finishing, xy, map(ranks.__getitem__, ids), over,
                                 parked_done)  # fmt: skip
        else:
            out = outputs_with_parked(self, live, outcome, blocked, rewards, over, parked_done)
        if over:
            self._set_agents([])
        elif self.finished_mode == "remove":
            self._set_agents(self._live)
        return out

    def _own_goals_step(self, live: list[int], cells: Sequence[int], here: np.ndarray | None, finishing: list[bool]) -> tuple:
        """After a step's moves, own goals: ``(finishing, reached, marks)``, the robots finishing on their
        targets (lifelong: ``reached`` them, new targets drawn, nobody finishing; ``finished="stay"``:
        ``reached`` the robots standing on their targets, nobody finishing) and, when nobody is on its
        target or robots stay, where the "local" rows' target channel has its 1s (``core.goals.channel_marks``).
        ``here``: ``cells`` as an array, if the step made one; ``finishing``: the moves' (none)."""
        keys = self._live_goal_keys
        if keys is None:  # kept until the racing robots or their targets change (_set_layout)
            keys = self._live_goal_keys = self._cell_key.take(self._racing_goals())
        offsets = goal_offsets(self._cell_key, cells if here is None else here, keys)  # 0: on its target
        nobody_on = np.count_nonzero(offsets) == len(offsets)
        if nobody_on or self.finished_mode == "stay":  # the common step, or robots that stay on their targets
            reached = None if nobody_on else (offsets == 0).tolist()
            if self._channel is None:
                return finishing, reached, None
            starts = self._channel_starts
            if starts is None:
                starts = self._channel_starts = row_starts(len(live), *self._channel[1:])
            return finishing, reached, channel_marks(offsets, self._channel[0], starts)
        finishing, reached = (offsets == 0).tolist(), None
        for i, f in zip(live, finishing):
            self._reached[i] += f
        if self.lifelong:  # a new target instead, and the robot keeps going
            reached, finishing = finishing, [False] * len(finishing)
            self._goal_arr = next_goals(self.np_random, self.table, self._goal_of, live, cells, reached)
            self._live_goals = self._live_goal_keys = None
        return finishing, reached, None

    def _racing_goals(self) -> np.ndarray:  # own goals: the racing robots' targets, kept until either changes
        if self._live_goals is None:
            self._live_goals = self._goal_arr if len(self._live) == self.n_robots else self._goal_arr[self._live]
        return self._live_goals

    def _set_agents(self, ids: list[int]) -> None:
        """The robots reported in ``agents``, by robot number, and what steps precompute for them."""
        self.agents = [self.possible_agents[i] for i in ids]
        self._agent_ids = ids
        self._none_done = dict.fromkeys(self.agents, False)
        self._set_layout()

    def _set_layout(self) -> None:
        """Observation rows of the reported agents, gathered from the rows of ``_live_cells + _parked`` (kept)."""
        key = (tuple(self._agent_ids), tuple(self._live), tuple(self._done))
        g = self._layouts.get(key)
        if g is None:
            place = np.empty(self.n_robots, dtype=np.intp)
            place[self._live + self._done] = np.arange(len(self._live) + len(self._done))
            g = self._gather[self._agent_ids] if self._observer is None else self._gather
            g = 3 * place[g // 3] + g % 3 if len(self._done) else g
            if g.size <= _LAYOUT_SIZE:
                if len(self._layouts) >= _LAYOUTS:
                    self._layouts.clear()
                self._layouts[key] = g
        self._gather_reported = g
        self._reported_live = self._agent_ids == self._live
        self._live_set = frozenset(self._live)
        self._live_goals = self._live_goal_keys = self._channel_starts = None  # own goals: kept per racing robots

    @property
    def _cells(self) -> list[int]:
        """Each robot's cell (a finished robot: the exit it took), in robot order."""
        cells = [0] * self.n_robots
        for i, c in zip(self._live, self._live_cells):
            cells[i] = c
        n_cells = self.table.n_cells
        for i, row in zip(self._done, self._parked):
            cells[i] = row - n_cells
        return cells

    @property
    def _racing(self) -> list[bool]:
        racing = [False] * self.n_robots
        for i in self._live:
            racing[i] = True
        return racing

    def batch(self, n_envs: int) -> BatchRace:
        """``n_envs`` copies of this race as one batch engine (the ``finished="freeze"`` view, or ``"stay"``'s):
        env ``i`` plays exactly the races of this env seeded the same way."""
        self.levels.check_one_level("the batch engine (and the vector envs)")
        return BatchRace(
            self.table, n_envs, self.n_robots, self.max_cycles, self._fixed_starts, self._free, self.start, self.rules.win_bonus,
            observer=self._observer, goal_columns=self._goal_columns, lifelong=self.lifelong, stay=self.finished_mode == "stay",
        )

    @property
    def np_random(self) -> np.random.Generator:
        """The race's generator, made unseeded at first use, as Gymnasium's ``Env`` does: copies of an
        env taken before its first reset (SuperSuit clones it with cloudpickle) draw different races."""
        if self._np_random is None:
            self._np_random = new_generator(None)
        return self._np_random

    @np_random.setter
    def np_random(self, value: np.random.Generator) -> None:
        self._np_random = value

    def set_cells(self, cells: list[Cell]) -> None:
        """Place the robots by hand (tests, tutorials): one distinct open cell per robot (after a
        reset; robots that have finished stay parked at their exits)."""
        self._check_started("set_cells")
        ids = check_cells(self.table, cells, self.n_robots, "cells", distinct=self.collisions != "pass")
        self._live_cells = [ids[i] for i in self._live]  # finished robots stay parked at their exits

    def _agent_index(self, agent: str) -> int:
        try:
            return self._index[agent]
        except (KeyError, TypeError):
            raise ValueError(f"agent: unknown agent {agent!r}; agents are {', '.join(self.possible_agents)}") from None

    def _check_actions(self, actions: Mapping[str, Any]) -> list[int]:
        """The racing robots' actions, in robot order; a ValueError (and nothing changed) if any is bad."""
        if type(actions) is not dict and not isinstance(actions, Mapping):  # the ABC check is slow
            raise ValueError(f"actions: expected a dict agent -> action, got {type(actions).__name__}")
        given: dict[int, int] = {}
        live = self._live_set
        for agent, action in actions.items():
            i = self._agent_index(agent)  # raises, naming the known agents
            if i not in live:  # finished: its action is checked and ignored (as PettingZoo's conversions do)
                check_action(action, f"actions[{agent!r}]")
                continue
            given[i] = check_action(action, f"actions[{agent!r}]")
        if len(given) < len(live):
            missing = [self.possible_agents[i] for i in self._live if i not in given]
            raise ValueError(
                f"actions: no action for {', '.join(map(repr, missing))}; every racing robot needs one "
                "(give 0 for STAY)"
            )
        return [given[i] for i in self._live]

    def _observations(self, here: np.ndarray | None = None, marks: np.ndarray | None = None) -> np.ndarray:
        """One row per reported agent, in ``agents`` order (a fresh array per step, rows never shared);
        ``here``: the racing robots' cells as an array, if the step made one (own goals: ``marks`` too)."""
        if self._goal_columns is not None:
            return self._goal_observations(here, marks)
        if self._observer is not None:
            if self._reported_live:  # the racing robots' rows alone: finished robots are in nobody's view
                here = np.array(self._live_cells) if here is None else here
                return self.encoder(self._observer(here, self._all_racing[: len(self._live)]))
            return self.encoder(self._observer(np.array(self._cells), np.array(self._racing))[self._agent_ids])
        rows = [*self._live_cells, *self._parked] if self._parked else self._live_cells
        obs = self._xyf.take(rows, axis=0).ravel()[self._gather_reported]
        return obs if self.encoder.identity else self.encoder(obs)

    def _use_level(self, level: Level) -> None:
        """Race on ``level`` (drawn at reset, the size of the last): everything that depends on it."""
        self.level, self.table = level, self._compile(level)
        self._observer = self._drawn_observer(self.table)
        self._fixed_starts, self._free = self._placement(self.n_robots)
        self.drawing.new_level(level)
        self._lists, self._sure_flat, self._reward_at, self._xy, self._cell_xy, self._xyf = cell_arrays(self.table)
        self._cell_key, self._channel = self._goal_tables()

    def _check_started(self, what: str) -> None:
        if not self._started:
            raise RuntimeError(f"{what}: the race has not started; call reset() first")
