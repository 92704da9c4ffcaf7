"""The race: a PettingZoo ``ParallelEnv`` shell over the shared core (``core.race.race_step``)."""

from __future__ import annotations

import operator
from collections.abc import Mapping, Sequence
from functools import cached_property
from itertools import compress
from typing import Any

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from ..core.actions import N_ACTIONS
from ..core.batch import BatchRace
from ..core.engine import OUTCOMES
from ..core.level import Cell, Level, as_cell
from ..core.race import race_step
from ..core.rng import new_key
from ..core.rules import COLLISION_MODES, Rules
from ..core.table import compile_level
from ..render.ansi import frame, robot_glyph
from ..render.rgb import RgbRenderer, Theme, check_cell_size, resolve_theme
from .common import check_action, check_options, check_positive_int, check_render_mode, resolve_level, resolve_rules
from .single import default_max_steps

START_MODES = ("level", "fill", "random")
FINISHED_MODES = ("remove", "freeze")
_ARGS = "arguments are level, n_robots, collisions, max_cycles, start, finished, rules, render_mode, cell_size, theme"


class RaceEnv(ParallelEnv):
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
        cell_size: int = 32,
        theme: str | Theme = "light",
        **rule_overrides: Any,
    ):
        self.level = resolve_level(level)
        if collisions is not None:
            if collisions not in COLLISION_MODES:
                raise ValueError(f"collisions: must be one of {', '.join(map(repr, COLLISION_MODES))}, got {collisions!r}")
            rule_overrides["collisions"] = collisions
        self.rules = resolve_rules(rules, rule_overrides, known=_ARGS)
        self.collisions = self.rules.collisions
        self.table = compile_level(self.level, self.rules)
        self.n_robots = n = check_positive_int(n_robots, "n_robots")
        self.max_cycles = default_max_steps(self.level) if max_cycles is None else check_positive_int(max_cycles, "max_cycles")
        if start not in START_MODES:
            raise ValueError(f"start: must be one of {', '.join(map(repr, START_MODES))}, got {start!r}")
        if finished not in FINISHED_MODES:
            raise ValueError(f"finished: must be one of {', '.join(map(repr, FINISHED_MODES))}, got {finished!r}")
        self.start, self.finished_mode = start, finished
        self._fixed_starts, self._free = self._placement(n)
        self.render_mode = check_render_mode(render_mode, self.metadata["render_modes"])
        self.cell_size, self.theme = check_cell_size(cell_size), resolve_theme(theme)

        w, h = self.level.width, self.level.height
        self.possible_agents = [f"robot_{i}" for i in range(n)]
        self.agents: list[str] = []
        self._index = {a: i for i, a in enumerate(self.possible_agents)}
        self._obs_space = spaces.MultiDiscrete([w, h] + [w, h, 2] * (n - 1))
        self._act_space = spaces.Discrete(5)
        self.observation_spaces = dict.fromkeys(self.possible_agents, self._obs_space)
        self.action_spaces = dict.fromkeys(self.possible_agents, self._act_space)
        self.state_space = spaces.Box(0, np.array([w - 1, h - 1, 1] * n), shape=(3 * n,), dtype=np.int64)
        # the observer first, then the others in turn: robot i sees i, i+1, ..., i-1 (mod n);
        # observations gather from the flat state [x0, y0, finished0, x1, ...]
        self._gather = np.array(
            [[3 * i, 3 * i + 1] + [3 * ((i + k) % n) + f for k in range(1, n) for f in range(3)] for i in range(n)],
            dtype=np.intp,
        )
        self._lists = self.table.lists
        self._xy = [self.table.cell_xy(c) for c in range(self.table.n_cells)]
        self._reward_at = self._lists.reward.__getitem__
        self._xyf = {racing: [(*xy, 0 if racing else 1) for xy in self._xy] for racing in (True, False)}
        self._cells: list[int] = []
        self._racing: list[bool] = []
        self._rank: list[int] = []
        self._returns: list[float] = []
        self._bumps: list[int] = []
        self._t = 0
        self._key = 0
        self._n_finished = 0
        self.np_random, _ = _seeding(None)

    # ----------------------------------------------------------------------- PettingZoo API
    def observation_space(self, agent: str) -> spaces.MultiDiscrete:
        self._agent_index(agent)
        return self._obs_space

    def action_space(self, agent: str) -> spaces.Discrete:
        self._agent_index(agent)
        return self._act_space

    def reset(self, seed: int | None = None, options: dict | None = None):
        check_options(options)
        if seed is not None:
            self.np_random, _ = _seeding(seed)
        self._key = new_key(self.np_random)
        self._cells = self._draw_starts()
        n = self.n_robots
        self._racing = [True] * n
        self._rank = [0] * n
        self._returns = [0.0] * n
        self._bumps = [0] * n
        self._t = 0
        self._n_finished = 0
        self.agents = list(self.possible_agents)
        self._agent_ids = range(n)  # robot index of each entry of self.agents
        if self.render_mode == "human":
            self.render()
        obs = self._observations()
        infos = {
            a: {"cell": self._xy[c], "outcome": "start", "blocked": False, "finished": False}
            for a, c in zip(self.possible_agents, self._cells)
        }
        return {a: obs[i] for i, a in enumerate(self.possible_agents)}, infos

    def step(self, actions: Mapping[str, Any]):
        if not self.agents:
            if actions:
                raise ValueError("actions: the race is over (no agents left); call reset() before stepping again")
            return {}, {}, {}, {}, {}
        acts = self._check_actions(actions)  # raises before anything changes
        n, step, racing = self.n_robots, self._t, self._racing
        cells, outcome, blocked, finishing = race_step(
            self._lists, self.collisions, self._cells, racing, acts, self._key, step
        )
        self._cells = cells
        self._t = step + 1
        returns = self._returns
        rewards = list(map(self._reward_at, cells))
        if self._n_finished:
            for i in compress(range(n), map(operator.not_, racing)):
                rewards[i] = 0.0
        if True in blocked:
            self._bumps = [b + k for b, k in zip(self._bumps, blocked)]
        finished_now = True in finishing
        if finished_now:
            first = self._n_finished == 0
            rank = self._n_finished + 1
            for i in range(n):
                if finishing[i]:
                    self._rank[i] = rank
                    self._n_finished += 1
                    if first:
                        rewards[i] += self.rules.win_bonus
            self._racing = racing_now = [r and not f for r, f in zip(racing, finishing)]
        else:
            racing_now = racing
        self._returns = list(map(operator.add, returns, rewards))
        over = self._t >= self.max_cycles or True not in racing_now
        obs = self._observations()

        reported = self.agents
        index, xy, ranks = self._index, self._xy, self._rank
        ids = self._agent_ids
        all_reported = len(reported) == n
        # parked robots (freeze) are terminated only when the race ends: PettingZoo expects a
        # terminated agent to leave `agents` in the same step
        if over or finished_now:
            parked_done = over or self.finished_mode == "remove"
            terms = {a: not racing_now[i] and parked_done for a, i in zip(reported, ids)}
            truncs = {a: over and racing_now[i] for a, i in zip(reported, ids)}
        else:
            terms = dict.fromkeys(reported, False)
            truncs = terms.copy()
        if all_reported:
            rews = dict(zip(reported, rewards))
            observations = dict(zip(reported, obs))
        else:
            rews = dict(zip(reported, map(rewards.__getitem__, ids)))
            observations = dict(zip(reported, map(obs.__getitem__, ids)))
        if all_reported and not self._n_finished:  # the common case: everyone racing
            infos = {
                a: {"cell": xy[c], "outcome": OUTCOMES[o], "blocked": b, "finished": False}
                for a, c, o, b in zip(reported, cells, outcome, blocked)
            }
        elif not finished_now and self.finished_mode == "remove":  # only racing robots reported
            infos = {
                a: {"cell": xy[cells[i]], "outcome": OUTCOMES[outcome[i]], "blocked": blocked[i], "finished": False}
                for a, i in zip(reported, ids)
            }
        else:
            infos = {}
            for a, i in zip(reported, ids):
                info = {
                    "cell": xy[cells[i]],
                    "outcome": OUTCOMES[outcome[i]] if racing[i] else "finished",
                    "blocked": blocked[i],
                    "finished": not racing_now[i],
                }
                if ranks[i]:
                    info["rank"] = ranks[i]
                infos[a] = info
        if over:
            self.agents = []
        elif finished_now and self.finished_mode == "remove":
            self.agents = [a for a in reported if racing_now[index[a]]]
            self._agent_ids = [index[a] for a in self.agents]
        if self.render_mode == "human":
            self.render()
        return observations, rews, terms, truncs, infos

    def state(self) -> np.ndarray:
        """Every robot's ``[x, y, finished]`` in robot order (a global view for critics)."""
        flat: list[int] = []
        for c, r in zip(self._cells, self._racing):
            flat += self._xyf[r][c]
        return np.array(flat, dtype=np.int64)

    def render(self) -> str | None:
        if self.render_mode is None:
            import gymnasium

            gymnasium.logger.warn("render() called with render_mode=None; pass render_mode='ansi' or 'human'")
            return None
        if self.render_mode == "rgb_array":
            return self.rgb_renderer.frame([self._xy[c] if r else None for c, r in zip(self._cells, self._racing)])
        text = self.render_text()
        if self.render_mode == "ansi":
            return text
        print(text, flush=True)
        return None

    def batch(self, n_envs: int) -> BatchRace:
        """``n_envs`` copies of this race as one batch engine (the ``finished="freeze"`` view):
        env ``i`` plays exactly the races of this env seeded the same way."""
        return BatchRace(
            self.table, n_envs, self.n_robots, self.max_cycles, self._fixed_starts, self._free, self.start, self.rules.win_bonus
        )

    @cached_property
    def rgb_renderer(self) -> RgbRenderer:
        """Draws this level (made on first use: large levels make large images)."""
        return RgbRenderer(self.level, self.cell_size, self.theme)

    def close(self) -> None:
        pass

    # ----------------------------------------------------------------------- helpers
    def render_text(self, colour: bool = False) -> str:
        """The text frame: the level, racing robots as letters A, B, ..., and a status line."""
        robots: list[Cell | None] = [self._xy[c] if r else None for c, r in zip(self._cells, self._racing)]
        done = [f"{robot_glyph(i, self.n_robots)}#{r}" for i, r in enumerate(self._rank) if r]  # [] before reset
        status = f"step {self._t}/{self.max_cycles}" + (f"  finished: {' '.join(done)}" if done else "")
        return frame(self.level, robots, status, colour=colour)

    @property
    def robot_cells(self) -> list[Cell]:
        """Each robot's ``(x, y)`` (a finished robot: the exit it took)."""
        return [self._xy[c] for c in self._cells]

    @property
    def elapsed_steps(self) -> int:
        return self._t

    @property
    def ranks(self) -> list[int]:
        """Each robot's finishing rank (1 = first; robots finishing in one step share it), 0 if not finished."""
        return list(self._rank)

    @property
    def returns(self) -> list[float]:
        return list(self._returns)

    @property
    def collisions_count(self) -> list[int]:
        """How many steps each robot has been blocked by another robot this episode."""
        return list(self._bumps)

    def set_cells(self, cells: list[Cell]) -> None:
        """Place the robots by hand (tests, tutorials): one distinct open cell per robot."""
        if not isinstance(cells, Sequence) or isinstance(cells, str):
            raise ValueError(f"cells: expected a list of {self.n_robots} cells (x, y), got {cells!r}")
        if len(cells) != self.n_robots:
            raise ValueError(f"cells: expected {self.n_robots} cells, got {len(cells)}")
        ids = []
        for cell in cells:
            x, y = as_cell(cell, "cells")
            if not (0 <= x < self.level.width and 0 <= y < self.level.height):
                raise ValueError(f"cells: {cell} is outside the {self.level.width}x{self.level.height} grid")
            c = self.table.cell_id((x, y))
            if self.table.blocked[c] or self.table.is_exit[c]:
                raise ValueError(f"cells: {cell} is blocked or an exit")
            ids.append(c)
        if self.collisions != "pass" and len(set(ids)) < len(ids):
            raise ValueError(f"cells: two robots share a cell, which collisions={self.collisions!r} forbids")
        self._cells = ids

    def _agent_index(self, agent: str) -> int:
        try:
            return self._index[agent]
        except (KeyError, TypeError):
            raise ValueError(f"agent: unknown agent {agent!r}; agents are {', '.join(self.possible_agents)}") from None

    def _check_actions(self, actions: Mapping[str, Any]) -> list[int]:
        if type(actions) is not dict and not isinstance(actions, Mapping):  # the ABC check is slow
            raise ValueError(f"actions: expected a dict agent -> action, got {type(actions).__name__}")
        acts = [0] * self.n_robots
        index, racing = self._index, self._racing
        given = 0
        for agent, action in actions.items():
            i = index.get(agent) if type(agent) is str else None
            if i is None:
                i = self._agent_index(agent)  # a str subclass; else raises, naming the known agents
            if not racing[i]:
                if self.finished_mode == "freeze":
                    check_action(action, f"actions[{agent!r}]")
                    continue  # parked: its action is ignored
                raise ValueError(f"actions: {agent!r} has finished the race and takes no more actions")
            given += 1
            if type(action) is int and 0 <= action < N_ACTIONS:
                acts[i] = action
            else:
                acts[i] = check_action(action, f"actions[{agent!r}]")
        if given < self.n_robots - self._n_finished:
            missing = [a for a in self.agents if racing[index[a]] and a not in actions]
            raise ValueError(
                f"actions: no action for {', '.join(map(repr, missing))}; every racing robot needs one "
                "(give 0 for STAY)"
            )
        return acts

    def _observations(self) -> np.ndarray:
        """Row ``i`` is robot ``i``'s observation (one fresh array per step, rows never shared)."""
        xyf = self._xyf
        flat: list[int] = []
        for c, r in zip(self._cells, self._racing):
            flat += xyf[r][c]
        return np.array(flat, dtype=np.int64)[self._gather]

    def _placement(self, n: int) -> tuple[list[int], list[int]]:
        """Level starts used as they are, and the free cells random starts are drawn from."""
        starts = [self.table.cell_id(c) for c in self.level.starts]
        if self.start == "level":
            if len(starts) < n:
                raise ValueError(
                    f"n_robots: level {self.level.name or ''!r} has {len(starts)} numbered starts for {n} robots; "
                    "pass start='fill' (level starts, then random free cells) or start='random'"
                )
            return starts[:n], []
        fixed = starts[:n] if self.start == "fill" else []
        free = [c for c in (self.table.cell_id(c) for c in self.level.free_cells()) if c not in fixed]
        if len(fixed) + len(free) < n:
            raise ValueError(
                f"n_robots: {n} robots do not fit on level {self.level.name or ''!r}, "
                f"which has {len(fixed) + len(free)} free cells"
            )
        return fixed, free

    def _draw_starts(self) -> list[int]:
        need = self.n_robots - len(self._fixed_starts)
        if need == 0:
            return list(self._fixed_starts)
        picks = self.np_random.choice(len(self._free), size=need, replace=False)
        return list(self._fixed_starts) + [self._free[int(k)] for k in picks]


def _seeding(seed: int | None) -> tuple[np.random.Generator, Any]:
    from gymnasium.utils import seeding

    return seeding.np_random(seed)
