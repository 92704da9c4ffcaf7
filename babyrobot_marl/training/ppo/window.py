"""An atlas of mazes for the batch engine, a level family of them, and playing a policy on them.

What a family's policy reads from its local window is ``form.py`` (``WindowForm``).

``Atlas``: K mazes stacked into one level (a blocked row between two mazes, blocked cells right of
a narrower maze), compiled as one table, so one flat ``BatchRace`` steps envs on different mazes;
each env's reset draws a maze (``pools``: each maze's free cells). An input's key is the id of its
window's level part (its pattern: terrain, walls, hint, the same on every maze where it repeats)
shifted past the robot bits: inputs still repeat across envs and mazes, and the net runs once per
distinct input, as on one level.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cached_property
from typing import Any

import numpy as np

from ...core.actions import N_ACTIONS
from ...core.batch import BatchRace
from ...core.checks import MAX_LEVEL_CELLS
from ...core.goals import GoalColumns, own_goal_table
from ...core.level import Level
from ...core.observe import LOCAL_FEATURES, local_observations, local_view
from ...core.rules import Rules
from ...core.table import Table, compile_level
from .form import _NVEC, N_HINT, NO_ACTION, WindowForm
from .goal_inputs import HINT_VALUES, AtlasDistances, target_units
from .intents import Ranks, intent_rows, near_robots
from .net import actor_probs
from .trail import TRAIL_VALUES
from .turns import decide_in_turns

PAIRWISE_ROBOTS = 16  # crowds up to which near codes compare every pair of robots (E R^2) instead of sorting cells

__all__ = ["NO_ACTION", "Atlas", "Family", "WindowForm", "play_atlas", "stack_levels", "window_form"]


def stack_levels(levels: Sequence[Level]) -> tuple[Level, np.ndarray]:
    """One level holding ``levels`` one below the other, a blocked row between two, blocked cells right of a
    narrower one; and each level's first row in it. A robot in one never reaches another."""
    width = max(lv.width for lv in levels)
    tops = np.cumsum([0] + [lv.height + 1 for lv in levels])[:-1]
    walls, glass, blocked, small, large, exits = set(), set(), set(), set(), set(), set()
    for lv, top in zip(levels, tops.tolist()):
        move = lambda c, top=top: (c[0], c[1] + top)  # noqa: E731
        walls |= {(move(a), move(b)) for a, b in lv.walls}
        glass |= {(move(a), move(b)) for a, b in lv.glass}
        blocked |= {move(c) for c in lv.blocked} | {(x, top + y) for y in range(lv.height) for x in range(lv.width, width)}
        small |= {move(c) for c in lv.small_puddles}
        large |= {move(c) for c in lv.large_puddles}
        exits |= {move(c) for c in lv.exits}
    height = int(tops[-1]) + levels[-1].height
    blocked |= {(x, int(top) - 1) for top in tops[1:] for x in range(width)}
    level = Level(width, height, walls=walls, glass=glass, blocked=blocked, small_puddles=small, large_puddles=large,
                  exits=exits, name=f"atlas of {len(levels)} levels")
    return level, tops


def unique_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(rows, axis=0, return_inverse=True)`` (the rows sorted, each row's number) for rows of small
    non-negative integers: each row as one string of big-endian 16-bit digits, whose byte order is the rows'
    order; 30x faster than sorting on every column."""
    if rows.size == 0 or rows.min() < 0 or rows.max() >= 1 << 16:
        uniq, inv = np.unique(rows, axis=0, return_inverse=True)
        return uniq, inv.reshape(-1)
    as_bytes = np.ascontiguousarray(rows.astype(">u2")).view(np.dtype((np.void, 2 * rows.shape[1]))).reshape(-1)
    _, first, inv = np.unique(as_bytes, return_index=True, return_inverse=True)
    return rows[first], inv.reshape(-1)


def _hint(level: Level, rules: Rules) -> np.ndarray:
    """The goal hint's bits of every cell, ``(n_cells, 5)``, as the env computes them."""
    from ...planning.hint import optimal_actions

    return optimal_actions(level, rules).reshape(level.n_cells, N_HINT)


class Atlas:
    """``levels`` stacked into one compiled table (``stack_levels``) with each level's window patterns and
    start pools: ``batch(...)`` steps envs on all of them, ``keys``/``rows`` are the trainer's inputs."""

    def __init__(self, levels: Sequence[Level], rules: Rules, form: WindowForm, lifelong: bool = False, stay: bool = False):
        self.levels, self.form, self.lifelong, self.stay = list(levels), form, lifelong, stay  # stay: finished="stay"
        self.level, self.tops = stack_levels(self.levels)  # each level's first row (the trainer's trails read it)
        compiled = own_goal_table if form.own else (lambda t: t)  # own goals: the exits are floor
        self.table: Table = compiled(compile_level(self.level, rules))
        w = self.level.width
        n = self.table.n_cells
        static = np.full((n, form.n_window * len(_NVEC) + (N_HINT if form.hint and not form.own else 0)), form.n_in,
                         dtype=np.int64)
        free, pools = [], []
        for lv, top in zip(self.levels, self.tops.tolist()):
            t = compiled(compile_level(lv, rules))
            ids = (top + np.arange(lv.n_cells) // lv.width) * w + np.arange(lv.n_cells) % lv.width
            cells = np.arange(lv.n_cells)
            feats = local_observations(local_view(t, form.radius), cells[:, None], np.zeros((lv.n_cells, 1), bool))
            feats = feats[:, 0, 2:].reshape(lv.n_cells, form.n_window, len(LOCAL_FEATURES))
            hint = _hint(lv, rules) if form.hint and not form.own else None
            static[ids] = form.static_rows(feats, hint)
            free.append(ids[list(t.free_cells)])
            pools.append(len(t.free_cells))
        self.free, self.pools = np.concatenate(free), pools
        # the hint toward own targets (a robot's own, or its neighbours' with intents)
        self.distances = AtlasDistances(self.table) if form.own and (form.hint or form.intents) else None
        # the patterns: distinct level parts of a window; a cell's key starts with its pattern's number
        self.patterns, self.pattern_of = unique_rows(static)
        m = len(form.near)
        xs, ys = np.arange(n) % w, np.arange(n) // w
        self.neighbours = np.full((n, m), n, dtype=np.int64)  # n: off the grid (never occupied)
        for b, (dx, dy) in enumerate(form.near):
            x, y = xs + dx, ys + dy
            inside = (x >= 0) & (x < w) & (y >= 0) & (y < self.level.height)
            self.neighbours[:, b] = np.where(inside, y * w + x, n)

    @property
    def n_in(self) -> int:
        return self.form.n_in

    @property
    def n_keys(self) -> int:
        f = self.form
        return ((len(self.patterns) << len(f.near)) * f.goal_values * (N_ACTIONS + 1 if f.memory else 1)
                * (TRAIL_VALUES if f.trail else 1))

    def batch(self, n_envs: int, n_robots: int, max_steps: int, start: str = "random") -> BatchRace:
        """``n_envs`` races of ``n_robots`` on the atlas (``finished="freeze"``, or ``"stay"``'s), each episode on a
        level drawn at its reset; own goals: each robot's target drawn after the starts, as ``race_v0`` draws them."""
        own = GoalColumns(None, False, self.level.width, self.level.height) if self.form.own else None
        return BatchRace(self.table, n_envs, n_robots, max_steps, (), self.free, "single" if n_robots == 1 else start,
                         self.table.rules.win_bonus if n_robots > 1 else 0.0, pools=self.pools, goal_columns=own,
                         lifelong=self.lifelong, stay=self.stay)

    def near_code(self, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
        """``(E, R)``: the near bits of each robot as one number (bit ``b``: a racing robot of the same env on near
        cell ``b``). A crowd of up to ``PAIRWISE_ROBOTS``: every pair's offset looked up (``E R^2`` small operations,
        no sort); larger ones: ``near_bits``."""
        e, r = cells.shape
        m = len(self.form.near)
        if not m or r == 1:
            return np.zeros((e, r), dtype=np.int64)
        if r > PAIRWISE_ROBOTS:
            return self.near_bits(cells, racing).astype(np.int64) @ (1 << np.arange(m))
        w, reach = self.level.width, self.near_reach
        side = 2 * reach + 1
        x, y = cells % w, cells // w
        dx, dy = x[:, None, :] - x[:, :, None], y[:, None, :] - y[:, :, None]  # (E, i, j): j seen from i
        inside = (np.abs(dx) <= reach) & (np.abs(dy) <= reach) & racing[:, None, :]
        slot = np.where(inside, (dy + reach) * side + dx + reach, side * side)  # side * side: not near
        return np.bitwise_or.reduce(self.near_bit_of[slot], axis=2)

    @cached_property
    def near_reach(self) -> int:
        return max((max(abs(dx), abs(dy)) for dx, dy in self.form.near), default=0)

    @cached_property
    def near_bit_of(self) -> np.ndarray:
        """Each offset's bit in a near code, over the square of ``near_reach`` (then a last 0: not near)."""
        side = 2 * self.near_reach + 1
        bits = np.zeros(side * side + 1, dtype=np.int64)
        for b, (dx, dy) in enumerate(self.form.near):
            bits[(dy + self.near_reach) * side + dx + self.near_reach] = 1 << b
        return bits

    def near_bits(self, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
        """``(E, R, m)``: a racing robot of the same env on each near cell of each robot."""
        e, r = cells.shape
        m, stride = len(self.form.near), self.table.n_cells + 1
        if not m or r == 1:
            return np.zeros((e, r, m), dtype=np.int64)
        base = (np.arange(e, dtype=np.int64) * stride)[:, None]
        occupied = np.sort((cells + base)[racing])
        want = self.neighbours[cells] + base[:, :, None]  # (E, R, m)
        at = np.minimum(np.searchsorted(occupied, want), max(occupied.size - 1, 0))
        return (occupied.size > 0) & (occupied[at] == want) if occupied.size else np.zeros(want.shape, dtype=bool)

    def intents(self, there: np.ndarray, cells: np.ndarray, goals: np.ndarray, ranks: np.ndarray | None = None) -> np.ndarray:
        """``(E * R, m * u)``: what the racing robots on each robot's near cells (``there``: ``near_robots``) intend
        (``intents.py``), and with ``ranks`` (``(E, R)``, ``Ranks.values``) whether each goes first."""
        hints = self.distances.hint_values(cells, goals)
        return intent_rows(there, cells, hints, goals, self.form.intents_first, self.form.n_in,
                           ranks if self.form.ranks else None)

    def near_robots(self, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
        """``(E, R, m)``: the racing robot on each robot's near cells, -1 for none (``intents.near_robots``)."""
        return near_robots(self.near_padded, cells, racing)

    @cached_property
    def near_padded(self) -> np.ndarray:
        """``neighbours`` with a last row for the off-grid cell (``near_robots`` looks every robot's cell up)."""
        return np.concatenate([self.neighbours, np.full((1, len(self.form.near)), self.table.n_cells)])

    def keys(self, cells: np.ndarray, racing: np.ndarray, last: np.ndarray | None = None,
             goals: np.ndarray | None = None, trail: np.ndarray | None = None) -> np.ndarray:
        """Every robot's key: its window pattern, then its near bits, then (own goals) where its ``goals`` cell
        lies and the hint toward it, then (``memory``) its ``last`` action, then (``trail``) its trail number."""
        m = len(self.form.near)
        key = self.pattern_of[cells]
        if m:
            key = (key << m) | self.near_code(cells, racing)
        if self.form.own:
            part = target_units(cells, goals, self.level.width, self.form.radius)
            if self.form.hint:
                part = part * HINT_VALUES + self.distances.hint_values(cells, goals)
            key = key * self.form.goal_values + part
        if self.form.memory:
            key = key * (N_ACTIONS + 1) + (np.full(np.shape(cells), NO_ACTION) if last is None else last)
        if self.form.trail:
            key = key * TRAIL_VALUES + (0 if trail is None else trail)
        return key

    def rows(self, keys: np.ndarray) -> np.ndarray:
        """The net's rows for ``keys``: the pattern's indices, then the near bits', then the last action's."""
        keys = np.asarray(keys, dtype=np.int64).reshape(-1)
        parts = []
        if self.form.trail:
            keys, trail = np.divmod(keys, TRAIL_VALUES)
            parts.append(self.form.trail_rows(trail))
        if self.form.memory:
            keys, last = np.divmod(keys, N_ACTIONS + 1)
            parts.insert(0, self.form.memory_rows(last))
        if self.form.own:
            keys, goal = np.divmod(keys, self.form.goal_values)
            parts.insert(0, self.form.goal_rows(goal))
        m = len(self.form.near)
        bits = (keys[:, None] >> np.arange(m)) & 1
        if self.form.own:  # the goal's units sit before the near bits'
            return np.concatenate([self.patterns[keys >> m], parts[0], self.form.robot_rows(bits), *parts[1:]], axis=1)
        return np.concatenate([self.patterns[keys >> m], self.form.robot_rows(bits), *parts], axis=1)


class Family:
    """A level family as the trainer steps it: atlases of levels drawn from ``source`` (a ``LevelSource``),
    under the rules and step limit its race envs have (checked by building one: ``collisions``,
    ``view_radius``, ``hint``), and the input its policy reads."""

    def __init__(self, source: Any, n_robots: int, cfg: Any, seed: int, env_kwargs: dict[str, Any]):
        from ...envs.race import RaceEnv
        from ...envs.single import default_max_steps

        self.source, self.n_robots = source, n_robots
        self.rng = np.random.default_rng([seed, 2])  # the atlases' levels
        first = source(np.random.default_rng(0))
        kwargs = dict(env_kwargs)
        max_cycles = kwargs.pop("max_cycles", None)
        hint = {"hint": True} if cfg.hint else {}
        probe = RaceEnv(level=first, n_robots=n_robots, start="random", observe="local", view_radius=cfg.view_radius, **hint,
                        **kwargs)
        self.rules = probe.rules
        w, h = getattr(source, "largest", (first.width, first.height))
        largest = Level(w, h, exits=[(0, 0)])  # the step limit of the family's envs: their largest level's
        self.max_steps = int(max_cycles) if max_cycles is not None else default_max_steps(largest)
        self.goals, self.lifelong, self.stay = probe.goals_mode, probe.lifelong, probe.finished_mode == "stay"
        if n_robots > 1 and cfg.near_radius > cfg.view_radius:
            raise ValueError(f"near_radius: a robot sees the robots within its window; near_radius {cfg.near_radius} "
                             f"exceeds view_radius {cfg.view_radius}")
        self.form = window_form(cfg, n_robots, self.goals)
        if _key_bound(self.form) >= 1 << 63:  # keys are int64: a wider input would wrap around, silently
            raise ValueError(f"near_radius: {cfg.near_radius} with a window of view_radius {cfg.view_radius} and these "
                             "inputs makes a robot's key wider than 64 bits; use a smaller near_radius")
        self.spec = str(getattr(source, "family", None) or first.name or "a level family")
        self.first = first

    @property
    def atlas_capacity(self) -> int:
        """The most levels of the family's largest size one atlas holds (its stacked level within
        ``MAX_LEVEL_CELLS``): one for a 256x256 maze."""
        return atlas_capacity(*getattr(self.source, "largest", (self.first.width, self.first.height)))

    def atlas(self, size: int) -> Atlas:
        """An atlas of ``size`` levels drawn from the family, at most ``atlas_capacity`` of them."""
        levels = [self.source(self.rng) for _ in range(min(size, self.atlas_capacity))]
        return Atlas(levels, self.rules, self.form, self.lifelong, self.stay)

    def play(self, net: Any, episodes: int, mazes: int, rng: np.random.Generator, deterministic: bool = True) -> dict[str, float]:
        """``play_atlas`` over ``episodes`` episodes on ``mazes`` levels drawn from the family: in chunks of
        atlases that fit (``atlas_capacity``), so any level size plays in bounded memory; the figures are
        the episodes' means over all chunks."""
        per = min(mazes, self.atlas_capacity)
        chunks = [len(c) for c in np.array_split(np.arange(episodes), -(-mazes // per)) if len(c)]
        scores = [(n, play_atlas(net, self.atlas(per), self.n_robots, n, self.max_steps, rng, deterministic)) for n in chunks]
        return {k: sum(n * s[k] for n, s in scores) / episodes for k in scores[0][1]}


def _key_bound(form: WindowForm) -> int:
    """An upper bound of an atlas's keys (``Atlas.n_keys``): at most one window pattern per cell of an atlas."""
    return ((MAX_LEVEL_CELLS << len(form.near)) * form.goal_values * (N_ACTIONS + 1 if form.memory else 1)
            * (TRAIL_VALUES if form.trail else 1))


def atlas_capacity(width: int, height: int) -> int:
    """How many levels of ``width x height`` one atlas stacks within ``MAX_LEVEL_CELLS`` (a blocked row
    between two): at least one, as a level itself is within the limit."""
    return max(1, (MAX_LEVEL_CELLS // width + 1) // (height + 1))


def play_atlas(net: Any, atlas: Atlas, n_robots: int, n_envs: int, max_steps: int, rng: np.random.Generator,
               deterministic: bool = True) -> dict[str, float]:
    """One episode in each of ``n_envs`` envs on ``atlas`` with the net's policy (greedy or sampled): the share
    of robots that reached the exit or their own target (``success_rate``; ``atlas.stay``: that stand on their
    target at the end), of episodes where all did, and the mean makespan; lifelong (``atlas.lifelong``), also
    ``throughput``: targets reached per step."""
    from ..deps import torch_module, torch_threads

    with torch_threads(1):  # on a busy machine torch's own threads wait on each other
        return _play(net, atlas, n_robots, n_envs, max_steps, rng, deterministic, torch_module())


def _play(net: Any, atlas: Atlas, n_robots: int, n_envs: int, max_steps: int, rng: np.random.Generator,
          deterministic: bool, torch: Any) -> dict[str, float]:
    from .sampler import PerKey, sample_actions
    from .trail import Trails

    batch = atlas.batch(n_envs, n_robots, max_steps)
    batch.reset_drawn(np.arange(n_envs), rng)
    trails = Trails(atlas, n_envs, n_robots) if atlas.form.trail else None
    recurrent = getattr(net, "recurrent", False)
    pick: Any = (lambda p: p.argmax(axis=1)) if deterministic else (lambda p: sample_actions(p, rng))  # noqa: E731
    ranks = Ranks(n_robots) if atlas.form.intents else None  # rows too many to number as keys: the net per distinct row
    probs = None if ranks else PerKey(atlas, net.gate_inputs if recurrent else lambda rows: torch.softmax(net.actor(rows), 1))
    h = net.initial_state(n_envs * n_robots) if recurrent else None  # one hidden state per robot, zero at the start
    done_at = np.full(n_envs, max_steps)
    last = np.full((n_envs, n_robots), NO_ACTION)
    while not batch.over.all():
        trail = trails.values(batch) if trails is not None else None
        keys = atlas.keys(batch.cells, batch.racing, last, batch.goals, trail).reshape(-1)
        if ranks is not None:
            actions = intent_actions(atlas, net, keys, batch, ranks, pick)
        else:
            p = probs(keys)
            if recurrent:
                with torch.no_grad():
                    h = net.step(torch.from_numpy(p), h)
                    p = torch.softmax(net.heads(h)[0], 1).numpy()
            actions = pick(p)
        was = batch.over.copy()
        last = np.where(batch.racing, actions.reshape(n_envs, n_robots), last)
        batch.step(actions.reshape(n_envs, n_robots))
        ended = batch.over & ~was
        done_at[ended] = batch.t[ended]
    reached = batch.cells == batch.goals if atlas.stay else batch.rank > 0  # staying robots may have left again
    score = {"success_rate": float(reached.mean()), "all_reached_rate": float(reached.all(axis=1).mean()),
             "makespan": float(done_at.mean())}
    if atlas.lifelong:
        score["throughput"] = float((batch.reached.sum(axis=1) / done_at).mean())
    return score


def intent_actions(atlas: Atlas, net: Any, keys: np.ndarray, batch: BatchRace, ranks: Ranks,
                   pick: Any) -> np.ndarray:
    """The actions (``pick``: probabilities to actions) of a crowd that reads its neighbours' intents: each robot's
    row is its key's row and the intents of the robots near it in ``batch`` (``Atlas.intents``; who goes first by
    ``ranks``, read at this step), the net once per distinct row; with ``turns``, chosen in turns (``turns.py``)."""
    form = atlas.form
    order = ranks.values(batch.cells, batch.goals, batch.t) if form.ranks else None
    there = atlas.near_robots(batch.cells, batch.racing)
    rows = np.concatenate([atlas.rows(keys), atlas.intents(there, batch.cells, batch.goals, order)], axis=1)

    def probs(rows: np.ndarray) -> np.ndarray:
        uniq, inv = unique_rows(rows)
        return actor_probs(net, uniq, None)[inv]  # float32, as the net computes them

    if not form.turns:
        return pick(probs(rows))
    chosen, _ = decide_in_turns(rows, there, order, batch.racing, probs, pick, form.turns_first, form.n_in)
    return np.maximum(chosen, 0).reshape(-1)  # robots not racing: any action


def window_form(cfg: Any, n_robots: int, goals: str = "exit") -> WindowForm:
    """The input a family policy of these settings reads (``goals``: the env's goals mode)."""
    from .inputs import near_offsets

    return WindowForm(cfg.view_radius, near_offsets(cfg.near_radius) if n_robots > 1 else (), cfg.hint, cfg.memory, goals,
                      cfg.trail, *[getattr(cfg, "imitate", None) is not None and n_robots > 1] * 3)  # intents, ranks, turns
