"""``train_imitation``: a crowd of own goals that learns what the planner PIBT does (``PPOConfig.imitate="pibt"``),
read top to bottom: per round, episodes on mazes of the family with PIBT labelling every robot's step, then
supervised learning on minibatches drawn from every labelled step so far.

This is DAgger (Ross, Gordon and Bagnell, 2011), the way MAPF-GPT learns from LaCAM: a learner trained on
the planner's own episodes has never seen the jams its own mistakes make, so after the first rounds the
learner drives and the planner only says what it would have done. In the first ``EXPERT_ROUNDS`` rounds
the planner still drives a share of the steps (all, then two thirds, then a third). Every robot reads its
window, its target channel, the hint and its last action, as a PPO crowd does, and what the robots near it
intend (``intents.py``): what PIBT decides for a robot hangs on what they want.

Each robot also reads which of the robots near it go before it (PIBT's priorities, kept by the robots as
PIBT keeps them and told to their neighbours: ``intents.Ranks``), and the robots decide in turns, each
reading what the near robots before it chose this step (``turns.py``; in a labelled step, what PIBT chose
for them). What PIBT sees and the learner does not: the robots beyond its near cells. The learner acts
sampled (a greedy crowd waits on itself).

The two halves of a round run side by side on two threads: the next round's episodes (Python: the env,
PIBT) are driven by a copy of the net as it was when they began, while the net learns from the steps so far
(torch's products, which release the interpreter). The learner is one round behind, as in asynchronous
DAgger; which thread runs when never changes what is computed (same seed, same weights).
"""

from __future__ import annotations

import copy
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..checks import check_finite, check_imitation
from ..deps import torch_module
from .form import NO_ACTION
from .intents import Ranks, env_crowd
from .net import actor_probs, make_net
from .result import EvalPoint, TrainResult, evaluate_now, trained_env
from .sampler import sample_actions
from .turns import decide_in_turns, turn_rows
from .window import Family

EPISODES_PER_ROUND = 16
EXPERT_ROUNDS = 3  # rounds in which PIBT still drives a share of the steps: 1, 2/3, 1/3
MEMORY = 2 << 30  # bytes of labelled rows kept (2.7M robot-steps of a 7x7 window): the newest, beyond it


def row_dtype(form: Any) -> type:
    """The narrowest integer type a row's indices fit (a million rows of ~400 int16 indices: 0.8 GB)."""
    return np.int16 if form.n_in < np.iinfo(np.int16).max else np.int32


class Labelled:
    """The labelled rows a run learns from and their labels: every one so far, up to ``memory`` bytes of rows,
    then the newest that fit (each new row replaces the oldest). The arrays double until full, so a round
    copies its own rows only."""

    def __init__(self, dtype: type, memory: int = MEMORY) -> None:
        self.rows: np.ndarray = np.zeros((0, 0), dtype=dtype)
        self.labels = np.zeros(0, dtype=np.int8)
        self.memory, self.capacity = memory, 0  # rows kept at most (known at the first rows)
        self.n = self.added = self._last = 0  # rows held; rows ever added; rows added at the last ``fresh()``

    def add(self, rows: np.ndarray, labels: np.ndarray) -> None:
        if not self.capacity:
            self.capacity = max(len(rows), self.memory // (rows.shape[1] * self.rows.itemsize))
        need = min(self.capacity, self.added + len(rows))
        if need > len(self.rows):
            size = min(self.capacity, max(need, 2 * len(self.rows), 1024))
            grown = np.empty((size, rows.shape[1]), dtype=self.rows.dtype)
            if self.n:
                grown[: self.n] = self.rows[: self.n]
            self.rows, self.labels = grown, np.concatenate([self.labels[: self.n], np.empty(size - self.n, np.int8)])
        at = (self.added + np.arange(len(rows))) % self.capacity  # in order, then round over the oldest
        self.rows[at], self.labels[at] = rows, labels
        self.added += len(rows)
        self.n = min(self.added, self.capacity)

    def fresh(self) -> int:
        """The rows added since the last call."""
        fresh, self._last = self.added - self._last, self.added
        return fresh


@dataclass
class Round:
    """One round's labelled steps: each step's rows and PIBT's actions, and the share of robots on their
    targets at each episode's end."""

    rows: list[np.ndarray] = field(default_factory=list)
    labels: list[np.ndarray] = field(default_factory=list)
    arrived: list[float] = field(default_factory=list)


def collect_round(family: Family, n_robots: int, cfg: Any, env_kwargs: dict[str, Any], net: Any, beta: float,
                  seed: int, stop: threading.Event | None = None) -> Round:
    """``EPISODES_PER_ROUND`` episodes on mazes of the family with PIBT labelling every robot's step; PIBT
    drives a share ``beta`` of the steps, ``net`` (sampled) the rest. ``stop``: set, the round ends at once."""
    from ...envs.race import RaceEnv
    from ...planning.pibt import PIBT

    torch = torch_module()
    if cfg.threads:
        torch.set_num_threads(cfg.threads)  # OpenMP's setting is each thread's own
    rng = np.random.default_rng(seed)  # mazes, episodes, the planner's ties, who drives, the learner's actions
    form, got = family.form, Round()
    store = row_dtype(form)

    def probs(rows: np.ndarray) -> np.ndarray:
        return actor_probs(net, rows)

    def pick(p: np.ndarray) -> np.ndarray:
        return sample_actions(p, rng)

    for _ in range(EPISODES_PER_ROUND):
        level = family.source(rng)
        env = RaceEnv(level=level, n_robots=n_robots, start="random", observe="local", view_radius=cfg.view_radius,
                      hint=cfg.hint, max_cycles=family.max_steps, **env_kwargs)
        obs, _ = env.reset(seed=int(rng.integers(1 << 31)))
        agents = env.possible_agents
        planner = PIBT(level, [env.goals[a] for a in agents], seed=int(rng.integers(1 << 31)), rules=family.rules)
        planner.priority = Ranks(n_robots).ties.tolist()  # its ties as the robots keep theirs (env_intents' ranks)
        last = np.full(n_robots, NO_ACTION)
        while env.agents:
            if stop is not None and stop.is_set():
                return got
            intents, there, ranks, racing = env_crowd(env, form)
            rows = form.rows_of_observations(np.stack([obs[a] for a in agents]), last, None, intents)
            expert = np.array(planner.actions(env.robot_cells))
            told = turn_rows(there, ranks, expert[None], form.turns_first, form.n_in) if form.turns else rows[:, :0]
            got.rows.append(np.concatenate([rows, told], axis=1).astype(store))  # what PIBT chose for those before
            got.labels.append(expert)
            if rng.random() < beta:
                last = expert
            elif form.turns:  # the net's choices, turn by turn
                last = np.maximum(decide_in_turns(rows, there, ranks, racing, probs, pick, form.turns_first,
                                                  form.n_in)[0][0], 0)
            else:
                last = pick(probs(rows))
            obs, _, _, _, _ = env.step(dict(zip(agents, last.tolist())))
        got.arrived.append(float(np.mean([tuple(c) == tuple(env.goals[a]) for c, a in zip(env.robot_cells, agents)])))
    return got


def learn(net: Any, optim: Any, seen: Labelled, cfg: Any, order: Any) -> None:
    """``n_epochs`` passes' worth of the rows added since the last call, in minibatches drawn from every row so
    far (passes over all of them each round would make a run's cost grow with its rows squared)."""
    torch = torch_module()
    padding = net.actor.first.shape[0] - 1
    n_batches = -(-cfg.n_epochs * seen.fresh() // cfg.batch_size)
    for mb in torch.randint(seen.n, (n_batches, min(cfg.batch_size, seen.n)), generator=order).numpy():
        rows, labels = (torch.from_numpy(a[mb].astype(np.int64)) for a in (seen.rows, seen.labels))
        loss = torch.nn.functional.cross_entropy(net.actor(rows), labels)
        optim.zero_grad()
        loss.backward()
        net.actor.first.grad[padding] = 0.0  # the padding row stays zero (Adam never moves it)
        torch.nn.utils.clip_grad_norm_(optim.param_groups[0]["params"], cfg.max_grad_norm)
        optim.step()


def train_imitation(family: Family, n_robots: int, total: int, seed: int, cfg: Any, env_kwargs: dict[str, Any],
                    evaluate: Callable[[TrainResult], float] | None = None, target: float | None = None,
                    stop_at_target: bool = False, max_seconds: float | None = None,
                    on_update: Callable[[int, float, float], None] | None = None,
                    on_eval: Callable[[EvalPoint], None] | None = None,
                    on_trained: Callable[[TrainResult], None] | None = None, init: Any = None) -> TrainResult:
    """DAgger on PIBT for ``total`` robot-steps or ``max_seconds`` of training time; ``train_ppo``'s callbacks
    (``on_update``'s third figure: the share of robots on their targets at the ends of the round's episodes)."""
    check_imitation(family, n_robots, env_kwargs)
    torch = torch_module()
    torch.manual_seed(seed)
    form = family.form
    net = make_net(form.n_in, cfg.net_arch)
    if init is not None:
        net.load_state_dict(init.state_dict())
    params = list(net.actor.parameters())
    optim = torch.optim.Adam(params, lr=cfg.learning_rate, eps=1e-5)
    result = TrainResult(net, family.first, n_robots, cfg, seed, family=family.spec, env=trained_env(env_kwargs))
    rng = np.random.default_rng([seed, 3])  # each round's seed
    order = torch.Generator().manual_seed(seed)
    kwargs = {k: v for k, v in env_kwargs.items() if k != "max_cycles"}
    seen = Labelled(row_dtype(form))
    stop = threading.Event()
    next_eval = cfg.eval_every or float("inf")
    t0, c0 = time.perf_counter(), time.process_time()

    def collect(rounds: int) -> Future[Round]:  # on the other thread, with a copy of the net as it is now
        beta = max(0.0, 1.0 - rounds / EXPERT_ROUNDS)  # the share of steps PIBT drives
        return pool.submit(collect_round, family, n_robots, cfg, kwargs, copy.deepcopy(net), beta,
                           int(rng.integers(1 << 63)), stop)

    rounds = 0
    with ThreadPoolExecutor(1) as pool:
        pending: Future[Round] | None = collect(0)
        try:
            while pending is not None:
                got = pending.result()
                for rows, labels in zip(got.rows, got.labels):
                    seen.add(rows, labels)
                result.timesteps += n_robots * len(got.rows)
                rounds += 1
                if result.timesteps >= next_eval and result.timesteps < total:  # while no round is under way
                    next_eval += cfg.eval_every
                    t0, c0 = evaluate_now(result, evaluate, on_eval, target, (t0, c0), float(np.mean(got.arrived)))
                    if stop_at_target and result.reached is not None:
                        break
                elapsed = result.seconds + time.perf_counter() - t0
                more = result.timesteps < total and (max_seconds is None or elapsed < max_seconds)
                # the next round's episodes, driven by the net as it is, while the net learns this round's steps
                # (the episodes are Python, the learning torch's products, which let go of the interpreter)
                pending = collect(rounds) if more else None
                learn(net, optim, seen, cfg, order)
                check_finite(params, result.timesteps, cfg)
                if on_update is not None:
                    on_update(result.timesteps, result.seconds + time.perf_counter() - t0, float(np.mean(got.arrived)))
        finally:
            stop.set()  # an interrupted run: the round under way ends at its next step
    net.eval()
    if on_trained is not None:
        on_trained(result)
    evaluate_now(result, evaluate, on_eval, target, (t0, c0), float("nan"))
    return result
