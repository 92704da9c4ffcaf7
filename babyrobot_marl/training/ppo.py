"""PPO stepped on the batch engine's arrays: one robot, or a race with one policy shared by every robot.

A CleanRL-style single file, read top to bottom: configuration, observation encoding, the
actor-critic network, then ``train_ppo``: rollout, advantages, update, evaluation. The algorithm
and its knobs are Stable-Baselines3's PPO (``n_steps`` per env, ``batch_size``, ``n_epochs``,
``gamma``, ``gae_lambda``, ``clip_range``, ``ent_coef``, ``vf_coef``, ``max_grad_norm``,
``learning_rate``, ``net_arch``; advantages normalised per minibatch, truncated episodes
bootstrapped from their last observation, Adam with ``eps=1e-5``, orthogonal initialisation).
What is different is where the time goes:

* The environment is ``core.batch.BatchRace``: a step of every env and robot is a few numpy
  calls, with no Gymnasium, SB3 or per-env Python in the loop.
* Inputs repeat, so the net runs once per distinct input, not once per robot-step. A robot's
  input is the one-hot of its cell and, in a race, one bit for each cell within ``near_radius``
  steps (default 1: the four cells next to it) saying whether a racing robot stands there
  (``Inputs``: one integer key per robot-step). Robots further off cannot touch its next step;
  leaving them out gives a few hundred distinct inputs per rollout of 65,536 robot-steps on
  race-4 (a policy that reads every robot's cell sees ~88% distinct ones: as slow as SB3), and a
  policy that races with any number of robots.
* During a rollout (fixed weights) the policy is a table over the inputs: one forward pass per
  rollout (or per step, for the distinct inputs of that step, when the possible inputs are many).
  In an update, the net runs once per distinct input of the rollout, and the samples' gradients
  are summed per (input, action, sign of the advantage) before they reach the net: a sample's
  probability ratio depends only on its input and action.
* The first layer, a ``Linear`` on the one-hot, is a look-up of weight rows: the same function
  and gradient as a dense layer, without building the one-hot of every sample.
* A race robot that has finished is parked until its race ends (``finished="freeze"``): its
  parked steps are no decisions and are left out of the update (SB3 through SuperSuit trains on
  them, reward 0).

Determinism: ``torch.manual_seed(seed)``, numpy generators seeded from ``seed``, env ``i``
seeded ``seed + i`` and a fixed number of torch threads (``threads``, default 1) during
training: torch's CPU kernels used here are deterministic at a fixed thread count, so the same
seed on the same machine gives the same learning curve. One thread also keeps training from
stalling when the machine is busy (torch's OpenMP threads spin and wait on each other when other
processes hold the cores); ``threads=None`` leaves torch's own setting.
"""

from __future__ import annotations

import contextlib
import functools
import math
import time
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass, field, fields
from typing import Any, NamedTuple

import numpy as np

from ..checks import check_int, check_real
from ..core.actions import N_ACTIONS
from ..core.batch import BatchRace
from ..core.level import Level
from ..envs.common import resolve_level

# ---------------------------------------------------------------------------- configuration
START_CHOICES = ("random", "level")


@dataclass(frozen=True)
class PPOConfig:
    """PPO's knobs, named and defaulted as in Stable-Baselines3 where they exist there.

    One rollout is ``n_steps`` steps of ``n_envs`` envs (times ``n_robots`` robots in a race);
    it is learnt from in ``n_epochs`` passes of minibatches of ``batch_size``. ``start``:
    ``"random"`` (training episodes start on random free cells: exploring starts) or ``"level"``
    (the level's starts). ``near_radius``: a race robot sees the racing robots within this many
    steps of it (``Inputs``): 1, the four cells next to it, holds every robot it could bump into;
    2 also the robots that could contest its next cell (more distinct inputs: 0.6x the speed).
    ``threads``: torch threads while training (None: torch's setting).
    ``eval_every``: timesteps between evaluations (0: only at the end).
    """

    n_envs: int = 1024
    n_steps: int = 16
    batch_size: int = 16384
    n_epochs: int = 4
    learning_rate: float = 3e-3
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip_range: float = 0.2
    ent_coef: float = 0.01
    vf_coef: float = 0.5
    max_grad_norm: float = 0.5
    normalize_advantage: bool = True
    net_arch: tuple[int, ...] = (64, 64)
    near_radius: int = 1
    start: str = "random"
    threads: int | None = 1
    eval_every: int = 65536
    eval_episodes: int = 10

    def __post_init__(self) -> None:
        for name in ("n_envs", "n_steps", "batch_size", "n_epochs", "eval_episodes"):
            check_int(getattr(self, name), name, 1)
        check_int(self.eval_every, "eval_every", 0)
        check_int(self.near_radius, "near_radius", 0, MAX_NEAR_RADIUS)
        if self.threads is not None:
            check_int(self.threads, "threads", 1)
        for name in ("gamma", "gae_lambda"):
            check_real(getattr(self, name), name, 0, 1)
        for name in ("learning_rate", "clip_range", "max_grad_norm"):
            if check_real(getattr(self, name), name, 0) == 0:
                raise ValueError(f"{name}: must be a finite number > 0, got 0")
        for name in ("ent_coef", "vf_coef"):
            check_real(getattr(self, name), name, 0)
        arch = tuple(self.net_arch)
        for h in arch:
            check_int(h, "net_arch", 1)
        object.__setattr__(self, "net_arch", arch)
        if self.start not in START_CHOICES:
            raise ValueError(f"start: must be one of {', '.join(map(repr, START_CHOICES))}, got {self.start!r}")

    def replace(self, **changes: Any) -> PPOConfig:
        return PPOConfig(**{**asdict(self), **_known_settings(changes, "replace")})


def _known_settings(changes: dict[str, Any], caller: str) -> dict[str, Any]:
    """``changes`` if every key is a ``PPOConfig`` field, else Python's own ``TypeError`` and the known names."""
    known = {f.name for f in fields(PPOConfig)}
    unknown = sorted(set(changes) - known)
    if unknown:
        names = ", ".join(sorted(known))
        raise TypeError(f"{caller}() got an unexpected keyword argument {unknown[0]!r}; PPO settings are: {names}")
    return changes


# ---------------------------------------------------------------------------- observations
MAX_NEAR_RADIUS = 4  # 40 cells: a key (16 bits of cell, one bit per cell) stays within int64


def near_offsets(radius: int) -> tuple[tuple[int, int], ...]:
    """The cells a race robot watches for other robots: every ``(dx, dy)`` at 1 to ``radius`` steps
    (Manhattan distance), row by row. Radius 2 (12 cells) holds every robot that can contest the
    robot's next cell or stand in its way; robots further off cannot touch its next step."""
    return tuple((dx, dy) for dy in range(-radius, radius + 1) for dx in range(-radius, radius + 1)
                 if 0 < abs(dx) + abs(dy) <= radius)


@dataclass(frozen=True)
class Inputs:
    """What a robot's network sees, as one integer key per robot-step.

    The input is the one-hot of the robot's own cell (``n_cells`` wide) and, in a race, one bit per
    cell of ``near`` (offsets from ``near_offsets``): set when a racing robot stands there. Its key
    is ``cell << m | bits`` (``m = len(near)``). Far robots are left out on purpose: inputs repeat
    (about 350 distinct ones in a rollout of 65,536 robot-steps on race-4 at radius 1, 2,100 at
    radius 2), and the net runs
    once per distinct input, in rollouts and in updates. Such a policy races with any number of
    robots. One robot: ``near = ()``, the key is the cell.
    """

    width: int
    height: int
    near: tuple[tuple[int, int], ...] = ()

    @property
    def n_cells(self) -> int:
        return self.width * self.height

    @property
    def n_in(self) -> int:
        """Width of the one-hot input: the cells, then the near bits."""
        return self.n_cells + len(self.near)

    @property
    def n_keys(self) -> int:
        return self.n_cells << len(self.near)

    @functools.cached_property
    def neighbours(self) -> np.ndarray:
        """``(n_cells + 1, m)``: the cell at each near offset of each cell, ``n_cells`` off the grid
        (and for the padding cell ``n_cells``)."""
        xs, ys = np.arange(self.n_cells) % self.width, np.arange(self.n_cells) // self.width
        out = np.full((self.n_cells + 1, len(self.near)), self.n_cells, dtype=np.int64)
        for b, (dx, dy) in enumerate(self.near):
            x, y = xs + dx, ys + dy
            inside = (x >= 0) & (x < self.width) & (y >= 0) & (y < self.height)
            out[:-1, b] = np.where(inside, y * self.width + x, self.n_cells)
        return out

    def keys(self, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
        """Every robot's key from a batch's ``(n_envs, n_robots)`` cells and racing flags."""
        m = len(self.near)
        if not m:
            return cells.copy()
        e, stride = cells.shape[0], self.n_cells + 1  # per env: its cells, then one never occupied
        base = np.arange(e)[:, None] * stride
        occupied = np.zeros(e * stride, dtype=np.uint8)
        occupied[base + np.where(racing, cells, self.n_cells)] = 1
        occupied[self.n_cells :: stride] = 0
        bits = occupied.take(self.neighbours[cells] + base[:, :, None])  # (E, R, m)
        return (cells << m) | (bits.astype(np.int64) @ (1 << np.arange(m)))

    def key_of_observation(self, obs: Any) -> int:
        """One env's ``MultiDiscrete`` observation (``[x, y]``, then ``[x, y, finished]`` per other
        robot in a race) as its key: what ``keys`` gives for that robot in a batch."""
        o = np.asarray(obs, dtype=np.int64).reshape(-1)
        cell = int(o[1]) * self.width + int(o[0])
        if not self.near:
            return cell
        rest = o[2:].reshape(-1, 3)
        occupied = {int(y) * self.width + int(x) for x, y, finished in rest if not finished}
        bits = sum(1 << b for b, c in enumerate(self.neighbours[cell]) if int(c) in occupied)
        return (cell << len(self.near)) | bits

    def rows(self, keys: np.ndarray) -> np.ndarray:
        """The net's rows of input indices for ``keys``: ``(U, 1 + m)``, the cell, then ``n_cells + b``
        for each set bit ``b`` (the padding index ``n_in`` for the others)."""
        keys = np.asarray(keys, dtype=np.int64).reshape(-1)
        m = len(self.near)
        if not m:
            return keys[:, None]
        bits = (keys[:, None] >> np.arange(m)) & 1
        return np.concatenate([(keys >> m)[:, None], np.where(bits == 1, self.n_cells + np.arange(m), self.n_in)], axis=1)

    def one_hot(self, keys: np.ndarray) -> np.ndarray:
        """The dense float32 input that keys stand for, ``(..., n_in)``."""
        rows = self.rows(keys)
        dense = np.zeros((rows.shape[0], self.n_in + 1), dtype=np.float32)
        dense[np.arange(rows.shape[0])[:, None], rows] = 1.0
        return dense[:, : self.n_in].reshape(*np.shape(keys), self.n_in)


def make_inputs(level: Level, n_robots: int, near_radius: int) -> Inputs:
    """A race's ``Inputs`` (robots within ``near_radius`` steps), or one robot's (its cell only)."""
    return Inputs(level.width, level.height, near_offsets(near_radius) if n_robots > 1 else ())


# ---------------------------------------------------------------------------- the network
@functools.cache
def _torch() -> Any:
    from .deps import require_train

    (torch,) = require_train("torch")
    return torch


def make_net(n_in: int, net_arch: tuple[int, ...] = (64, 64)) -> Any:
    """SB3's ``MlpPolicy`` for a discrete action: separate actor and critic MLPs (tanh), orthogonal
    initialisation (gain sqrt(2), 0.01 for the action head, 1 for the value head).

    Each MLP's first layer is a ``Linear(n_in, width)`` on the one-hot of a row of indices, stored
    as its weight's rows (``first``, row ``n_in``: padding, kept zero). ``forward_cached`` and
    ``backward`` are the MLP's forward pass keeping its activations and its gradient written out:
    autograd took 1.6-2.5x as long per update on nets this small (``tests/test_ppo.py`` holds the two to
    the same gradients).
    """
    torch = _torch()
    nn = torch.nn
    one = torch.ones(())

    class MLP(nn.Module):
        def __init__(self, out: int, head_gain: float):
            super().__init__()
            sizes = [*net_arch, out]
            self.first = nn.Parameter(torch.empty(n_in + 1, sizes[0]))
            self.first_bias = nn.Parameter(torch.zeros(sizes[0]))
            self.layers = nn.ModuleList(nn.Linear(a, b) for a, b in zip(sizes[:-1], sizes[1:]))
            with torch.no_grad():
                w = torch.empty(sizes[0], n_in)
                nn.init.orthogonal_(w, math.sqrt(2) if net_arch else head_gain)  # as SB3 does the dense layer
                self.first[:n_in] = w.T
                self.first[n_in] = 0.0
                for k, layer in enumerate(self.layers):
                    nn.init.orthogonal_(layer.weight, head_gain if k == len(self.layers) - 1 else math.sqrt(2))
                    nn.init.zeros_(layer.bias)

        def forward(self, idx: Any) -> Any:
            return self.forward_cached(idx, dense_input(idx, n_in))[0]

        def forward_cached(self, idx: Any, dense: Any = None) -> tuple[Any, list[Any]]:
            """The output and the activations; ``dense``: the one-hot counts of ``idx`` (``dense_input``),
            faster than row look-ups for several indices per row."""
            b, k = idx.shape
            if dense is not None:
                h = torch.addmm(self.first_bias, dense, self.first)
            else:
                h = self.first.index_select(0, idx.reshape(-1))
                h = (h if k == 1 else h.view(b, k, -1).sum(1)) + self.first_bias
            acts = []
            for layer in self.layers:
                h = torch.tanh(h)
                acts.append(h)
                h = torch.addmm(layer.bias, h, layer.weight.T)
            return h, acts

        def backward(self, idx: Any, acts: list[Any], d: Any, dense: Any = None) -> None:
            """Set every parameter's ``.grad`` from ``d``, the loss's gradient at the output."""
            for layer, a in zip(reversed(self.layers), reversed(acts)):
                layer.weight.grad = d.T @ a
                layer.bias.grad = d.sum(0)
                d = (d @ layer.weight).mul_(torch.addcmul(one, a, a, value=-1.0))  # through tanh: 1 - a^2
            if dense is not None:
                grad = dense.T @ d
            else:
                k = idx.shape[1]
                grad = torch.zeros_like(self.first)
                grad.index_add_(0, idx.reshape(-1), d if k == 1 else d.repeat_interleave(k, 0))
            grad[n_in] = 0.0  # the padding row stays zero
            self.first.grad = grad
            self.first_bias.grad = d.sum(0)

    class ActorCritic(nn.Module):
        def __init__(self) -> None:
            super().__init__()
            self.n_in, self.net_arch = n_in, tuple(net_arch)
            self.actor = MLP(N_ACTIONS, 0.01)
            self.critic = MLP(1, 1.0)

        def forward(self, idx: Any) -> tuple[Any, Any]:
            return self.actor(idx), self.critic(idx).squeeze(-1)

    return ActorCritic()


def log_softmax(z: Any) -> Any:
    torch = _torch()
    s = z - z.amax(1, keepdim=True)  # torch.log_softmax is several times slower along a dim of 5
    return s - torch.log(torch.exp(s).sum(1, keepdim=True))


DENSE_LIMIT = 1024  # inputs up to which a race's one-hot is built densely in updates (faster than row look-ups)


def dense_input(rows: Any, n_in: int) -> Any:
    """The one-hot counts of rows of several indices, ``(B, n_in + 1)``; None for one index per row
    (a look-up is cheapest) or a wide input (the dense matrix would be large)."""
    if rows.shape[1] == 1 or n_in > DENSE_LIMIT:
        return None
    torch = _torch()
    return torch.zeros(rows.shape[0], n_in + 1).scatter_add_(1, rows, torch.ones(rows.shape))


TABLE_LIMIT = 4096  # inputs up to which the net runs on every possible key instead of searching for the distinct ones


class PerKey:
    """``fn`` (the critic's values, or a policy's probabilities, on rows of input indices) per key, the
    net run once per distinct key: while the weights stay fixed, inputs that repeat cost nothing."""

    def __init__(self, inputs: Inputs, fn: Callable[[Any], Any]):
        self.inputs, self.fn = inputs, fn
        self.table = None
        if inputs.n_keys <= TABLE_LIMIT:
            self.table = self.run(np.arange(inputs.n_keys))

    def run(self, keys: np.ndarray) -> np.ndarray:
        torch = _torch()
        with torch.no_grad():
            return self.fn(torch.from_numpy(self.inputs.rows(keys))).numpy()

    def __call__(self, keys: np.ndarray) -> np.ndarray:
        if self.table is not None:
            return self.table[keys]
        uniq, inv = np.unique(keys.reshape(-1), return_inverse=True)
        return self.run(uniq)[inv.reshape(keys.shape)]


class Sampler(PerKey):
    """Actions sampled from the actor's probabilities per key (a rollout)."""

    def __init__(self, inputs: Inputs, net: Any):
        super().__init__(inputs, lambda rows: log_softmax(net.actor(rows)))
        self.cdf = None if self.table is None else np.cumsum(np.exp(self.table), axis=1)

    def sample(self, keys: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """One action per key by inverse-CDF sampling (one uniform number each)."""
        if self.table is not None:
            cdf, at = self.cdf, keys
        else:
            uniq, at = np.unique(keys, return_inverse=True)
            cdf = np.cumsum(np.exp(self.run(uniq)), axis=1)
        u = rng.random((keys.size, 1))
        return np.minimum((u >= cdf[at]).sum(axis=1), N_ACTIONS - 1)


def distinct_rows(inputs: Inputs, keys: np.ndarray) -> tuple[Any, Any]:
    """The distinct inputs among ``keys`` as the net's rows, and each key's row."""
    torch = _torch()
    if inputs.n_keys <= 4 * keys.size + 65536:  # a map over every possible key: no sort
        present = np.zeros(inputs.n_keys, dtype=bool)
        present[keys] = True
        uniq = np.flatnonzero(present)
        inv = (np.cumsum(present) - 1)[keys]
    else:
        uniq, inv = np.unique(keys, return_inverse=True)
    return torch.from_numpy(inputs.rows(uniq)), torch.from_numpy(inv.reshape(-1))


def grads_of(params: list[Any]) -> list[Any]:
    return [p.grad for p in params]


def clip_grad_norm(grads: list[Any], max_norm: float) -> None:
    """``torch.nn.utils.clip_grad_norm_`` without its checks and grouping (a third of an update here)."""
    torch = _torch()
    total = torch.linalg.vector_norm(torch.stack(torch._foreach_norm(grads)))
    torch._foreach_mul_(grads, torch.clamp(max_norm / (total + 1e-6), max=1.0))


class Samples(NamedTuple):
    """Samples of an update as ``ppo_gradients`` reads them (torch tensors, one entry per sample)."""

    inv: Any  # the sample's row (its input among the distinct ones)
    pair: Any  # (row * 5 + action) * 2: where its advantage is summed
    adv: Any  # its advantage
    ret_one: Any  # (B, 2): its return, and 1 (summed per row: the row's returns and its count)

    @classmethod
    def of(cls, inv: Any, actions: Any, adv: Any, returns: Any) -> Samples:
        torch = _torch()
        return cls(inv, (inv * N_ACTIONS + actions) * 2, adv, torch.stack([returns, torch.ones_like(returns)], 1))

    def actions(self) -> Any:
        return self.pair // 2 - self.inv * N_ACTIONS

    def part(self, index: Any) -> Samples:
        """The samples at ``index`` (a slice, or a tensor of positions)."""
        if isinstance(index, slice):
            return Samples(*(x[index] for x in self))
        return Samples(*(x.index_select(0, index) for x in self))


def ppo_gradients(net: Any, rows: Any, old_logp: Any, samples: Samples, cfg: PPOConfig) -> None:
    """Set ``.grad`` of every parameter to the gradient of SB3's PPO loss on one minibatch.

    ``loss = -mean(min(A r, A clip(r, 1 - c, 1 + c))) - ent_coef * mean(entropy) + vf_coef * mean((v - R)^2)``
    with ``r = exp(logp - old_logp)`` and ``A`` the advantages, normalised over the minibatch.
    The net runs once per distinct observation: ``rows`` (U, K); ``old_logp`` (U, 5): the rollout
    policy's log-probabilities per row. A sample's ratio depends only on its row and action, and
    which term the min picks only on the sign of its advantage, so the samples' gradients are
    summed per (row, action, sign) first.
    """
    torch = _torch()
    B, U = samples.adv.shape[0], rows.shape[0]
    c = cfg.clip_range
    with torch.no_grad():
        dense = dense_input(rows, net.n_in)
        z, actor_acts = net.actor.forward_cached(rows, dense)
        v_rows, critic_acts = net.critic.forward_cached(rows, dense)
        logp_rows = log_softmax(z)
        p = torch.exp(logp_rows)
        entropy = -(p * logp_rows).sum(1, keepdim=True)
        a = samples.adv
        if cfg.normalize_advantage and B > 1:
            std, mean = torch.std_mean(a)
            a = (a - mean) / (std + 1e-8)
        # sums of the advantages per (row, action): [.., 0] the samples with A <= 0, [.., 1] with A > 0
        sums = torch.zeros(U * N_ACTIONS * 2, dtype=a.dtype).index_add_(0, samples.pair + (a > 0), a).view(U, N_ACTIONS, 2)
        ratio = torch.exp(logp_rows - old_logp)
        # the min picks the unclipped term (the one with a gradient) for A > 0 while r <= 1 + c, for A < 0 while r >= 1 - c
        g = sums[..., 1] * (ratio <= 1.0 + c) + sums[..., 0] * (ratio >= 1.0 - c)
        g *= ratio * (-1.0 / B)  # d loss / d logp, summed per (row, action)
        # per row: the sum of its returns and its count
        row_returns, count = torch.zeros(U, 2, dtype=a.dtype).index_add_(0, samples.inv, samples.ret_one).split(1, dim=1)
        # d logp_i / d z = onehot(a_i) - p;  d entropy / d z = -p (log p + entropy)
        dz = g - g.sum(1, keepdim=True) * p
        dz += (cfg.ent_coef / B) * count * p * (logp_rows + entropy)
        # d value loss / d v = 2 vf_coef / B * (v - R), summed per row: count * v - the row's returns
        dv = (count * v_rows).sub_(row_returns).mul_(2.0 * cfg.vf_coef / B)
        net.actor.backward(rows, actor_acts, dz, dense)
        net.critic.backward(rows, critic_acts, dv, dense)


# ---------------------------------------------------------------------------- training
@dataclass
class EvalPoint:
    """One evaluation: timesteps and training seconds so far, the mean training return of recent
    episodes, and the evaluation's score (one robot: mean greedy return; race: win rate)."""

    timesteps: int
    seconds: float
    train_return: float
    score: float


@dataclass
class TrainResult:
    """What ``train_ppo`` returns: the network, where it was trained, the curve and the totals.

    ``seconds`` is training time (rollouts and updates, evaluations excluded), wall-clock;
    ``cpu_seconds`` the process's CPU time over the same spans (on a busy machine wall time also
    counts the others); ``reached`` the first ``(timesteps, seconds)`` whose evaluation met
    ``target`` (None if never or no target).
    """

    net: Any
    level: Level
    n_robots: int
    config: PPOConfig
    seed: int
    timesteps: int = 0
    seconds: float = 0.0
    eval_seconds: float = 0.0
    cpu_seconds: float = 0.0
    history: list[EvalPoint] = field(default_factory=list)
    reached: tuple[int, float] | None = None

    @property
    def steps_per_second(self) -> float:
        """Timesteps per second of wall-clock training time."""
        return self.timesteps / self.seconds if self.seconds > 0 else float("nan")

    @property
    def steps_per_cpu_second(self) -> float:
        """Timesteps per second of the process's CPU time while training."""
        return self.timesteps / self.cpu_seconds if self.cpu_seconds > 0 else float("nan")

    def policy(self, deterministic: bool = True, seed: int | None = None) -> Any:
        """The trained policy with the scripted policies' interface (``policy(obs) -> action``)."""
        from .policy import TrainedPolicy

        inputs = make_inputs(self.level, self.n_robots, self.config.near_radius)
        return TrainedPolicy(self.net, inputs, self.n_robots, deterministic, seed)

    def save(self, path: str) -> str:
        """Write the network and what it was trained on to ``path`` exactly (a torch file); returns it."""
        from .policy import save_policy

        return save_policy(self, path)


class TrainingDivergedError(ValueError):
    """The loss or the weights became NaN or infinite (a learning rate too large, most often)."""


def check_finite(params: list[Any], timesteps: int, cfg: PPOConfig) -> None:
    """Raise ``TrainingDivergedError`` if any weight is not finite (a NaN or infinite loss or gradient
    makes the weights so at the optimizer's step). One norm per parameter: cheap once per update."""
    torch = _torch()
    if not bool(torch.isfinite(torch.stack(torch._foreach_norm(params))).all()):
        raise TrainingDivergedError(f"learning_rate: training diverged within {timesteps:,} timesteps (the loss or the weights "
                               f"are no longer finite numbers) at learning_rate {cfg.learning_rate:g}; try a smaller one")


@contextlib.contextmanager
def torch_threads(threads: int | None) -> Iterator[None]:
    """Run with ``threads`` torch threads (None: leave torch's setting), restored afterwards."""
    torch = _torch()
    before = torch.get_num_threads()
    if threads is not None:
        torch.set_num_threads(threads)
    try:
        yield
    finally:
        torch.set_num_threads(before)


@contextlib.contextmanager
def _deterministic(seed: int) -> Iterator[None]:
    torch = _torch()
    # torch's CPU kernels used here are deterministic at a fixed thread count; only the generator
    # needs seeding (torch.use_deterministic_algorithms would import torch's compiler: 3 s)
    torch.manual_seed(seed)
    yield


def make_batch(level: Level, n_robots: int, n_envs: int, start: str, seed: int, **env_kwargs: Any) -> BatchRace:
    """``n_envs`` envs of ``level`` on the batch engine (one robot: ``BabyRobot-v0``; more: ``race_v0``
    with ``finished="freeze"``), env ``i`` seeded ``seed + i``, every episode started."""
    from ..envs.race import RaceEnv
    from ..envs.single import BabyRobotEnv

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
    each evaluation. ``init``: a network (``make_net`` layout) to start from, e.g. a loaded policy's.
    ``env_kwargs`` go to the env (``max_steps``/``max_cycles``, rules, ``collisions``).
    """
    torch = _torch()
    cfg = config or PPOConfig()
    if overrides:
        cfg = cfg.replace(**_known_settings(overrides, "train_ppo"))
    level = resolve_level(level)
    n = check_int(n_robots, "n_robots", 1)
    total = check_int(timesteps, "timesteps", 1)
    check_int(seed, "seed", 0)
    batch = make_batch(level, n, cfg.n_envs, cfg.start, seed, **(env_kwargs or {}))
    inputs = make_inputs(level, n, cfg.near_radius)
    E, T = cfg.n_envs, cfg.n_steps
    rng = np.random.default_rng(seed)  # actions

    with torch_threads(cfg.threads), _deterministic(seed):
        net = make_net(inputs.n_in, cfg.net_arch)
        if init is not None:
            if init.n_in != net.n_in or tuple(init.net_arch) != cfg.net_arch:
                raise ValueError(
                    f"init: the network has {init.n_in} inputs and layers {init.net_arch}; this run needs "
                    f"{net.n_in} inputs ({level.width}x{level.height}, {n} robot(s), near_radius "
                    f"{cfg.near_radius}) and layers {cfg.net_arch}"
                )
            net.load_state_dict(init.state_dict())
        params = list(net.parameters())
        optim = torch.optim.Adam(params, lr=cfg.learning_rate, eps=1e-5, fused=True)  # one kernel for all
        result = TrainResult(net, level, n, cfg, seed)
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
            result.seconds += time.perf_counter() - t_train
            result.cpu_seconds += time.process_time() - c_train
            t0 = time.perf_counter()
            net.eval()
            score = float(evaluate(result)) if evaluate is not None else float("nan")
            point = EvalPoint(result.timesteps, result.seconds, float(np.mean(recent)) if recent else float("nan"), score)
            result.history.append(point)
            if target is not None and result.reached is None and score >= target:
                result.reached = (result.timesteps, result.seconds)
            result.eval_seconds += time.perf_counter() - t0
            if on_eval is not None:
                on_eval(point)
            t_train, c_train = time.perf_counter(), time.process_time()
            return stop_at_target and result.reached is not None

        while result.timesteps < total:
            # ---- rollout: n_steps steps of every env, actions sampled from the current policy
            with torch.no_grad():
                actor = Sampler(inputs, net)  # weights fixed: the net runs once per distinct input
                for t in range(T):
                    keys = inputs.keys(batch.cells, batch.racing).reshape(-1)
                    actions = actor.sample(keys, rng)
                    racing = batch.racing.copy()
                    rewards, finishing, _, _, over = batch.step(actions.reshape(E, n))
                    key_buf[t], act_buf[t], valid_buf[t] = keys.reshape(E, n), actions.reshape(E, n), racing
                    rew_buf[t] = rewards
                    ended = racing & (finishing | over[:, None])
                    done_buf[t] = ended | ~racing  # parked steps end nothing: isolated, masked out
                    trunc_buf[t] = racing & over[:, None] & ~finishing
                    ep_return += rewards
                    if np.count_nonzero(ended):
                        recent.extend(ep_return[ended].tolist())
                        ep_return[ended] = 0.0
                    if np.count_nonzero(over):
                        envs = np.flatnonzero(over)
                        if np.count_nonzero(trunc_buf[t]):
                            final_buf[t] = inputs.keys(batch.cells, batch.racing)
                        batch.reset_envs(envs)

                # ---- advantages (GAE), truncated episodes bootstrapped from their last observation
                critic = PerKey(inputs, lambda rows: net.critic(rows)[:, 0])
                values = critic(key_buf)
                rewards_b = rew_buf.copy()
                if np.count_nonzero(trunc_buf):
                    rewards_b[trunc_buf] += cfg.gamma * critic(final_buf[trunc_buf])
                next_value = critic(inputs.keys(batch.cells, batch.racing))
                adv = np.zeros((T, E, n), dtype=np.float32)
                last = np.zeros((E, n), dtype=np.float32)
                for t in reversed(range(T)):
                    nonterminal = 1.0 - done_buf[t]
                    nv = next_value if t == T - 1 else values[t + 1]
                    delta = rewards_b[t] + cfg.gamma * nv * nonterminal - values[t]
                    last = delta + cfg.gamma * cfg.gae_lambda * nonterminal * last
                    adv[t] = last
                returns = adv + values

            # ---- update: n_epochs passes over the decisions of the rollout, in minibatches; the net
            # runs once per distinct input of the rollout (rows), sample i being row b_inv[i]
            net.train()
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
                        present, inv = torch.unique(mb.inv, return_inverse=True)
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
        if not result.history or result.history[-1].timesteps != result.timesteps:
            run_evaluation()
        else:
            result.seconds += time.perf_counter() - t_train
            result.cpu_seconds += time.process_time() - c_train
        net.eval()
    return result
