"""Learning from a rollout: advantages (GAE), then PPO's gradient summed per distinct input, and the gradient's clipping."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...core.actions import N_ACTIONS
from ..deps import torch_module
from .config import PPOConfig
from .net import dense_input, log_softmax


def gae(rewards: np.ndarray, values: np.ndarray, next_value: np.ndarray, dones: np.ndarray, gamma: float,
        gae_lambda: float) -> tuple[np.ndarray, np.ndarray]:
    """Generalised advantage estimates and returns of a rollout's ``(T, E, R)`` arrays: ``rewards`` (truncated
    episodes already bootstrapped), the critic's ``values``, ``next_value`` after the last step, and ``dones``
    (the robot's episode ended at that step)."""
    T = rewards.shape[0]
    adv = np.zeros(rewards.shape, dtype=np.float32)
    last = np.zeros(rewards.shape[1:], dtype=np.float32)
    for t in reversed(range(T)):
        nonterminal = 1.0 - dones[t]
        nv = next_value if t == T - 1 else values[t + 1]
        delta = rewards[t] + gamma * nv * nonterminal - values[t]
        last = delta + gamma * gae_lambda * nonterminal * last
        adv[t] = last
    return adv, adv + values


class Samples(NamedTuple):
    """Samples of an update as ``ppo_gradients`` reads them (torch tensors, one entry per sample)."""

    inv: Any  # the sample's row (its input among the distinct ones)
    pair: Any  # (row * 5 + action) * 2: where its advantage is summed
    adv: Any  # its advantage
    ret_one: Any  # (B, 2): its return, and 1 (summed per row: the row's returns and its count)

    @classmethod
    def of(cls, inv: Any, actions: Any, adv: Any, returns: Any) -> Samples:
        torch = torch_module()
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
    torch = torch_module()
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


def grads_of(params: list[Any]) -> list[Any]:
    return [p.grad for p in params]


def clip_grad_norm(grads: list[Any], max_norm: float) -> None:
    """``torch.nn.utils.clip_grad_norm_`` without its checks and grouping (a third of an update here)."""
    torch = torch_module()
    total = torch.linalg.vector_norm(torch.stack(torch._foreach_norm(grads)))
    torch._foreach_mul_(grads, torch.clamp(max_norm / (total + 1e-6), max=1.0))
