"""``train_imitation``: a crowd of own goals that learns what the planner PIBT does (``PPOConfig.imitate="pibt"``),
read top to bottom: per round, episodes on mazes of the family with PIBT labelling every robot's step, then
passes of supervised learning over every labelled step so far.

This is DAgger (Ross, Gordon and Bagnell, 2011), the way MAPF-GPT learns from LaCAM: a learner trained on
the planner's own episodes has never seen the jams its own mistakes make, so after the first rounds the
learner drives and the planner only says what it would have done. In the first ``EXPERT_ROUNDS`` rounds
the planner still drives a share of the steps (all, then two thirds, then a third). Every robot reads its
window, its target channel, the hint and its last action, as a PPO crowd does, and what the robots near it
intend (``intents.py``): what PIBT decides for a robot hangs on what they want.

What PIBT sees and the learner does not: every robot's priority, and the robots beyond its near cells.
The learner acts for each robot alone, on its own row, sampled (a greedy crowd waits on itself).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from ..checks import check_finite, check_imitation
from ..deps import torch_module
from .intents import env_intents
from .net import make_net
from .result import EvalPoint, TrainResult, evaluate_now, trained_env
from .sampler import sample_actions
from .window import NO_ACTION, Family

EPISODES_PER_ROUND = 16
EXPERT_ROUNDS = 3  # rounds in which PIBT still drives a share of the steps: 1, 2/3, 1/3


def train_imitation(family: Family, n_robots: int, total: int, seed: int, cfg: Any, env_kwargs: dict[str, Any],
                    evaluate: Callable[[TrainResult], float] | None = None, target: float | None = None,
                    stop_at_target: bool = False, max_seconds: float | None = None,
                    on_update: Callable[[int, float, float], None] | None = None,
                    on_eval: Callable[[EvalPoint], None] | None = None,
                    on_trained: Callable[[TrainResult], None] | None = None, init: Any = None) -> TrainResult:
    """DAgger on PIBT for ``total`` robot-steps or ``max_seconds`` of training time; ``train_ppo``'s callbacks
    (``on_update``'s third figure: the share of robots on their targets at the ends of the round's episodes)."""
    from ...envs.race import RaceEnv
    from ...planning.pibt import PIBT

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
    rng = np.random.default_rng([seed, 3])  # mazes, episodes, the planner's ties, who drives, the learner's actions
    order = torch.Generator().manual_seed(seed)
    kwargs = {k: v for k, v in env_kwargs.items() if k != "max_cycles"}
    rows_seen: list[np.ndarray] = []
    labels: list[np.ndarray] = []
    store = np.int16 if form.n_in < np.iinfo(np.int16).max else np.int32  # a million rows of ~400 indices: 0.8 GB
    next_eval = cfg.eval_every or float("inf")
    t0, c0 = time.perf_counter(), time.process_time()

    def learner(rows: np.ndarray) -> np.ndarray:
        with torch.no_grad():
            return sample_actions(torch.softmax(net.actor(torch.from_numpy(rows)), 1).double().numpy(), rng)

    rounds = 0
    while result.timesteps < total:
        beta = max(0.0, 1.0 - rounds / EXPERT_ROUNDS)  # the share of steps PIBT drives
        arrived = []
        for _ in range(EPISODES_PER_ROUND):  # ---- collection: the planner labels, the learner (mostly) drives
            level = family.source(rng)
            env = RaceEnv(level=level, n_robots=n_robots, start="random", observe="local", view_radius=cfg.view_radius,
                          hint=cfg.hint, max_cycles=family.max_steps, **kwargs)
            obs, _ = env.reset(seed=int(rng.integers(1 << 31)))
            agents = env.possible_agents
            planner = PIBT(level, [env.goals[a] for a in agents], seed=int(rng.integers(1 << 31)), rules=family.rules)
            last = np.full(n_robots, NO_ACTION)
            while env.agents:
                rows = form.rows_of_observations(np.stack([obs[a] for a in agents]), last, None, env_intents(env, form))
                expert = np.array(planner.actions(env.robot_cells))
                rows_seen.append(rows.astype(store))
                labels.append(expert.astype(np.int8))
                last = expert if rng.random() < beta else learner(rows)
                obs, _, _, _, _ = env.step(dict(zip(agents, last.tolist())))
                result.timesteps += n_robots
            arrived.append(np.mean([tuple(c) == tuple(env.goals[a]) for c, a in zip(env.robot_cells, agents)]))
        # ---- learning: n_epochs passes over every labelled step so far, in minibatches
        rows_seen, labels = [np.concatenate(rows_seen)], [np.concatenate(labels)]  # kept small; a minibatch widened
        x, y = rows_seen[0], torch.from_numpy(labels[0].astype(np.int64))
        for _ in range(cfg.n_epochs):
            shuffled = torch.randperm(len(y), generator=order)
            for start in range(0, len(y), cfg.batch_size):
                mb = shuffled[start : start + cfg.batch_size]
                rows = torch.from_numpy(x[mb.numpy()].astype(np.int64))
                loss = torch.nn.functional.cross_entropy(net.actor(rows), y[mb])
                optim.zero_grad()
                loss.backward()
                net.actor.first.grad[form.n_in] = 0.0  # the padding row stays zero (Adam never moves it)
                torch.nn.utils.clip_grad_norm_(params, cfg.max_grad_norm)
                optim.step()
        check_finite(params, result.timesteps, cfg)
        rounds += 1
        elapsed = result.seconds + time.perf_counter() - t0
        if on_update is not None:
            on_update(result.timesteps, elapsed, float(np.mean(arrived)))
        if max_seconds is not None and elapsed >= max_seconds:
            break
        if result.timesteps >= next_eval and result.timesteps < total:
            next_eval += cfg.eval_every
            t0, c0 = evaluate_now(result, evaluate, on_eval, target, (t0, c0), float(np.mean(arrived)))
            if stop_at_target and result.reached is not None:
                break
    net.eval()
    if on_trained is not None:
        on_trained(result)
    evaluate_now(result, evaluate, on_eval, target, (t0, c0), float("nan"))
    return result

