"""``train_ppo``: one loop, read top to bottom as CleanRL's ``ppo.py``: set-up, then per rollout: the rollout
(``Sampler``), advantages (``gae``), the update (``ppo_gradients`` over minibatches), evaluation.

The pieces it calls are the modules beside it: ``config`` (``PPOConfig``), ``inputs`` (``Inputs``: a
robot-step's key), ``net`` (the actor-critic), ``sampler`` (the policy as a table while the weights stay
fixed), ``update`` (GAE and the PPO gradient), ``result`` (``TrainResult``, ``EvalPoint``).
"""

from __future__ import annotations

import contextlib
import math
import time
from collections import deque
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from ...core.batch import BatchRace
from ...core.checks import check_int
from ...core.level import Level
from ...levels.resolve import resolve_level
from ...levels.sources import TRAIN_MAZE_SEEDS, level_source, parse_level_family
from ..checks import CELL_NAMES, check_finite
from ..deps import torch_module, torch_threads  # torch_threads: also training.ppo.torch_threads, as before
from .config import PPOConfig, known_settings
from .form import NO_ACTION
from .inputs import make_inputs
from .net import log_softmax, make_net
from .recurrent import Recurrence, make_recurrent_net
from .result import EvalPoint, TrainResult, evaluate_now, trained_env
from .sampler import PerKey, Sampler, distinct_below, distinct_rows
from .trail import Trails
from .update import Samples, clip_grad_norm, gae, grads_of, ppo_gradients
from .window import Family


@contextlib.contextmanager
def _deterministic(seed: int) -> Iterator[None]:
    torch = torch_module()
    # torch's CPU kernels used here are deterministic at a fixed thread count; only the generator
    # needs seeding (torch.use_deterministic_algorithms would import torch's compiler: 3 s)
    torch.manual_seed(seed)
    yield


def _hidden(net: Any) -> int | None:
    """A recurrent net's hidden units (None: feed-forward)."""
    return getattr(net, "hidden", None) if getattr(net, "recurrent", False) else None


def _cell(net: Any) -> str:
    return "" if _hidden(net) is None else f" and {CELL_NAMES[net.cell]} of {_hidden(net)} units"


def make_batch(level: Level, n_robots: int, n_envs: int, start: str, seed: int, **env_kwargs: Any) -> BatchRace:
    """``n_envs`` envs of ``level`` on the batch engine (one robot: ``BabyRobot-v0``; more: ``race_v0``
    with ``finished="freeze"``), env ``i`` seeded ``seed + i``, every episode started."""
    from ...envs.race import RaceEnv
    from ...envs.single import BabyRobotEnv

    if n_robots == 1:
        batch = BabyRobotEnv(level=level, start="random" if start == "random" else None, **env_kwargs).batch(n_envs)
    else:
        batch = RaceEnv(level=level, n_robots=n_robots, start=start, finished="freeze", **env_kwargs).batch(n_envs)
    batch.seed([seed + i for i in range(n_envs)])
    batch.reset_envs(np.arange(n_envs))
    return batch


def train_ppo(
    level: str | Level = "maze-8x8",
    n_robots: int = 1,
    timesteps: int = 100_000,
    seed: int = 0,
    config: PPOConfig | None = None,
    evaluate: Callable[[TrainResult], float] | None = None,
    target: float | None = None,
    stop_at_target: bool = False,
    max_seconds: float | None = None,
    on_update: Callable[[int, float, float], None] | None = None,
    on_eval: Callable[[EvalPoint], None] | None = None,
    on_trained: Callable[[TrainResult], None] | None = None,
    init: Any = None,
    env_kwargs: dict[str, Any] | None = None,
    **overrides: Any,
) -> TrainResult:
    """Train PPO for ``timesteps`` robot-steps (SB3's ``num_timesteps``: one per robot per step).

    ``config`` (default ``PPOConfig()``) with keyword ``overrides`` (``n_envs=16, ...``).
    ``evaluate(result) -> score`` runs every ``config.eval_every`` timesteps and at the end (its
    time is not training time); ``target``: the score to reach (``result.reached``), training
    stops there if ``stop_at_target``; ``max_seconds``: stop after this much training time.
    ``on_update(timesteps, seconds, mean_return)`` after each update, ``on_eval(point)`` after
    each evaluation; ``on_trained(result)`` once training has ended, before the final evaluation (to save
    the policy before anything that can still fail or take long). ``init``: a network (``make_net``
    layout) to start from, e.g. a loaded policy's.
    ``env_kwargs`` go to the env (``max_steps``/``max_cycles``, rules, ``collisions``).
    """
    torch = torch_module()
    cfg = config or PPOConfig()
    if overrides:
        cfg = cfg.replace(**known_settings(overrides, "train_ppo"))
    n = check_int(n_robots, "n_robots", 1)
    total = check_int(timesteps, "timesteps", 1)
    check_int(seed, "seed", 0)
    # a level family ("maze:8..16": its mazes from the training seeds): an atlas of its levels, the net reading local windows
    source = parse_level_family(level, TRAIN_MAZE_SEEDS) if isinstance(level, str) else None
    source = source or level_source(level)
    family = None if source is None else Family(source, n, cfg, seed, env_kwargs or {})
    for name, what in (("memory", "the last-action input"), ("trail", "the trail input"), ("recurrent", "a recurrent net")):
        if getattr(cfg, name) and family is None:
            raise ValueError(f"{name}: {what} is read by a level family's policy (level='maze:A..B'), "
                             f"got level {level if isinstance(level, str) else getattr(level, 'name', 'a Level')!r}")
    if family is None and (env_kwargs or {}).get("goals", "exit") != "exit":
        raise ValueError("goals: a policy of own goals reads its target in its local window: train it on a level "
                         "family ('maze:A..B') or with the level's windows (the CLI's --observe local)")
    if cfg.imitate is not None:  # a crowd that learns from a planner, not from rewards
        if family is None:
            raise ValueError("imitate: a crowd imitating a planner reads local windows: train it on a level family "
                             "('maze:A..B', 'gridmaze:A..B') or with the level's windows (the CLI's --observe local)")
        from .imitation import train_imitation

        with torch_threads(cfg.threads):
            return train_imitation(family, n, total, seed, cfg, env_kwargs or {}, evaluate, target, stop_at_target,
                                   max_seconds, on_update, on_eval, on_trained, init)
    if family is None:
        level = resolve_level(level)
        batch = make_batch(level, n, cfg.n_envs, cfg.start, seed, **(env_kwargs or {}))
        inputs: Any = make_inputs(level, n, cfg.near_radius)
    else:
        level = family.first
        inputs = family.atlas(cfg.atlas_size)
        batch = inputs.batch(cfg.n_envs, n, family.max_steps)
    E, T = cfg.n_envs, cfg.n_steps
    rng = np.random.default_rng(seed)  # actions
    reset_rng = np.random.default_rng([seed, 1])  # episodes' keys and starts: one generator, drawn per batch
    if family is not None:
        batch.reset_drawn(np.arange(E), reset_rng)
    # the robots' last actions (a family policy with memory reads them; NO_ACTION at an episode's start)
    last = np.full((E, n), NO_ACTION) if cfg.memory else None
    own = family is not None and family.goals == "own"
    trails = Trails(inputs, E, n) if cfg.trail else None  # where each robot has stood this episode

    def keys_now() -> np.ndarray:  # every robot's key now (a family's: own target, last action, trail too)
        if family is None:
            return inputs.keys(batch.cells, batch.racing)
        trail = trails.values(batch) if trails is not None else None
        return inputs.keys(batch.cells, batch.racing, last, batch.goals if own else None, trail)

    with torch_threads(cfg.threads), _deterministic(seed):
        if cfg.recurrent:
            net = make_recurrent_net(inputs.n_in, cfg.net_arch, cfg.hidden, cfg.cell)
        else:
            net = make_net(inputs.n_in, cfg.net_arch)
        # a recurrent net's hidden states, one per robot beside the batch engine's cells (None: feed-forward)
        rec = Recurrence(net, E * n, T, 1.0 / (1.0 - cfg.gamma)) if cfg.recurrent else None
        if init is not None:
            if init.n_in != net.n_in or tuple(init.net_arch) != cfg.net_arch or _cell(init) != _cell(net):
                raise ValueError(
                    f"init: the network has {init.n_in} inputs and layers {init.net_arch}{_cell(init)}; this run needs "
                    f"{net.n_in} inputs ({family.spec if family else f'{level.width}x{level.height}'}, {n} robot(s), near_radius "
                    f"{cfg.near_radius}) and layers {cfg.net_arch}{_cell(net)}"
                )
            net.load_state_dict(init.state_dict())
        params = list(net.parameters())
        optim = torch.optim.Adam(params, lr=cfg.learning_rate, eps=1e-5, fused=True)  # one kernel for all
        result = TrainResult(net, level, n, cfg, seed, family=None if family is None else family.spec,
                             env=trained_env(env_kwargs))
        order_gen = torch.Generator().manual_seed(seed)  # minibatch order

        # rollout storage: (T, E, R) per robot-step; an observation is its key (Inputs)
        key_buf = np.zeros((T, E, n), dtype=np.int64)
        act_buf = np.zeros((T, E, n), dtype=np.int64)
        rew_buf = np.zeros((T, E, n), dtype=np.float32)
        valid_buf = np.zeros((T, E, n), dtype=bool)  # a decision: the robot was racing
        done_buf = np.zeros((T, E, n), dtype=bool)  # the robot's episode ended at this step
        trunc_buf = np.zeros((T, E, n), dtype=bool)  # ... by the time limit: bootstrap from final_buf
        final_buf = np.zeros((T, E, n), dtype=np.int64)
        ep_return = np.zeros((E, n))
        recent: deque[float] = deque(maxlen=100)
        next_eval = cfg.eval_every if cfg.eval_every else math.inf
        t_train, c_train = time.perf_counter(), time.process_time()

        def run_evaluation() -> bool:
            nonlocal t_train, c_train
            train_return = float(np.mean(recent)) if recent else float("nan")
            t_train, c_train = evaluate_now(result, evaluate, on_eval, target, (t_train, c_train), train_return)
            return stop_at_target and result.reached is not None

        rollouts = 0
        while result.timesteps < total:
            if family is not None and rollouts and rollouts % cfg.atlas_every == 0:  # new mazes, every env restarted
                inputs = family.atlas(cfg.atlas_size)
                batch = inputs.batch(E, n, family.max_steps)
                batch.reset_drawn(np.arange(E), reset_rng)
                ep_return[:] = 0.0
                if trails is not None:
                    trails = Trails(inputs, E, n)
                if last is not None:
                    last[:] = NO_ACTION
                if rec is not None:
                    rec.restart()
            rollouts += 1
            # ---- rollout: n_steps steps of every env, actions sampled from the current policy
            with torch.no_grad():
                actor = Sampler(inputs, net) if rec is None else rec.start(inputs)  # weights fixed: once per distinct input
                for t in range(T):
                    keys = keys_now().reshape(-1)
                    actions = actor.sample(keys, rng)
                    racing = batch.racing.copy()
                    rewards, finishing, blocked, _, over = batch.step(actions.reshape(E, n))
                    if last is not None:
                        last[racing] = actions.reshape(E, n)[racing]
                    key_buf[t], act_buf[t], valid_buf[t] = keys.reshape(E, n), actions.reshape(E, n), racing
                    rew_buf[t] = rewards - cfg.blocked_cost * blocked if cfg.blocked_cost else rewards
                    ended = racing & (finishing | over[:, None])
                    done_buf[t] = ended | ~racing  # parked steps end nothing: isolated, masked out
                    if rec is not None:
                        rec.ended(done_buf[t])
                    trunc_buf[t] = racing & over[:, None] & ~finishing
                    ep_return += rewards
                    if np.count_nonzero(ended):
                        recent.extend(ep_return[ended].tolist())
                        ep_return[ended] = 0.0
                    if np.count_nonzero(over):
                        envs = np.flatnonzero(over)
                        if np.count_nonzero(trunc_buf[t]):
                            final_buf[t] = keys_now()
                            if rec is not None:
                                rec.truncated(final_buf[t], trunc_buf[t])
                        batch.reset_drawn(envs, reset_rng)
                        if trails is not None:
                            trails.restart(envs)
                        if last is not None:
                            last[envs] = NO_ACTION

                # ---- advantages (GAE), truncated episodes bootstrapped from their last observation
                rewards_b = rew_buf.copy()
                if rec is None:
                    critic = PerKey(inputs, lambda rows: net.critic(rows)[:, 0])
                    values = critic(key_buf)
                    if np.count_nonzero(trunc_buf):
                        rewards_b[trunc_buf] += cfg.gamma * critic(final_buf[trunc_buf])
                    next_value = critic(keys_now())
                else:
                    values = rec.value_buf.reshape(T, E, n)
                    rewards_b += cfg.gamma * rec.final_value.reshape(T, E, n) * trunc_buf
                    next_value = rec.next_value(keys_now())
                adv, returns = gae(rewards_b, values, next_value, done_buf, cfg.gamma, cfg.gae_lambda)

            # ---- update: n_epochs passes over the decisions of the rollout, in minibatches; the net
            # runs once per distinct input of the rollout (rows), sample i being row b_inv[i]
            net.train()
            if rec is not None:  # whole segments replayed from their first state (truncated BPTT)
                rec.update(inputs, key_buf, act_buf, adv, returns, valid_buf, cfg, optim, params, order_gen)
            else:
                keep = slice(None) if n == 1 else valid_buf  # one robot: every step is a decision
                rows, b_inv = distinct_rows(inputs, key_buf[keep].reshape(-1))
                b_act = torch.from_numpy(act_buf[keep].reshape(-1))
                b_adv = torch.from_numpy(adv[keep].reshape(-1))
                b_ret = torch.from_numpy(returns[keep].reshape(-1).astype(np.float32))
                with torch.no_grad():  # the rollout's policy, per row (the weights have not changed yet)
                    old_logp = log_softmax(net.actor(rows))
                samples = Samples.of(b_inv, b_act, b_adv, b_ret)
                size = b_act.shape[0]
                for _ in range(cfg.n_epochs):
                    # shuffled once per epoch, minibatches are then slices; one minibatch: order changes nothing
                    shuffled = samples.part(torch.randperm(size, generator=order_gen)) if size > cfg.batch_size else samples
                    for start in range(0, size, cfg.batch_size):
                        mb = shuffled.part(slice(start, start + cfg.batch_size))
                        mb_rows, mb_old = rows, old_logp
                        if rows.shape[0] > mb.inv.shape[0]:  # more inputs than samples: only the minibatch's
                            present, inv = map(torch.from_numpy, distinct_below(mb.inv.numpy(), rows.shape[0]))
                            mb_rows, mb_old = rows[present], old_logp[present]
                            mb = Samples.of(inv, mb.actions(), mb.adv, mb.ret_one[:, 0])
                        ppo_gradients(net, mb_rows, mb_old, mb, cfg)
                        clip_grad_norm(grads_of(params), cfg.max_grad_norm)
                        optim.step()
            check_finite(params, result.timesteps + T * E * n, cfg)

            result.timesteps += T * E * n
            elapsed = result.seconds + time.perf_counter() - t_train
            if on_update is not None:
                on_update(result.timesteps, elapsed, float(np.mean(recent)) if recent else float("nan"))
            if max_seconds is not None and elapsed >= max_seconds:
                break
            if result.timesteps >= next_eval and result.timesteps < total:
                next_eval += cfg.eval_every
                if run_evaluation():
                    break
        if on_trained is not None:
            net.eval()
            on_trained(result)
        if not result.history or result.history[-1].timesteps != result.timesteps:
            run_evaluation()
        else:
            result.seconds += time.perf_counter() - t_train
            result.cpu_seconds += time.process_time() - c_train
        net.eval()
    return result
