"""The actor-critic network: SB3's ``MlpPolicy`` for a discrete action, its forward pass and its gradient written out."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...core.actions import N_ACTIONS
from ..deps import torch_module


def make_net(n_in: int, net_arch: tuple[int, ...] = (64, 64)) -> Any:
    """SB3's ``MlpPolicy`` for a discrete action: separate actor and critic MLPs (tanh), orthogonal
    initialisation (gain sqrt(2), 0.01 for the action head, 1 for the value head).

    Each MLP's first layer is a ``Linear(n_in, width)`` on the one-hot of a row of indices, stored
    as its weight's rows (``first``, row ``n_in``: padding, kept zero). ``forward_cached`` and
    ``backward`` are the MLP's forward pass keeping its activations and its gradient written out:
    autograd took 1.6-2.5x as long per update on nets this small (``tests/test_ppo.py`` holds the two to
    the same gradients).
    """
    torch = torch_module()
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


def actor_probs(net: Any, rows: Any, dtype: Any = np.float64) -> np.ndarray:
    """The actor's action probabilities ``(B, 5)`` on rows of input indices (a numpy array or a tensor), as a numpy
    array of ``dtype``; None: the net's own (float32). The softmax is the net's: float64 only widens it, exactly."""
    torch = torch_module()
    x = rows if isinstance(rows, torch.Tensor) else torch.from_numpy(rows)
    with torch.no_grad():
        p = torch.softmax(net.actor(x), 1).numpy()
    return p if dtype is None else p.astype(dtype, copy=False)


def log_softmax(z: Any) -> Any:
    torch = torch_module()
    s = z - z.amax(1, keepdim=True)  # torch.log_softmax is several times slower along a dim of 5
    return s - torch.log(torch.exp(s).sum(1, keepdim=True))


DENSE_LIMIT = 1024  # inputs up to which a race's one-hot is built densely in updates (faster than row look-ups)
DENSE_SHARE = 10  # wider inputs too, when a row indexes at least one unit in DENSE_SHARE (a window's many features)


def dense_input(rows: Any, n_in: int) -> Any:
    """The one-hot counts of rows of several indices, ``(B, n_in + 1)``; None for one index per row
    (a look-up is cheapest) or a wide input of few indices per row (the dense matrix would be large and
    mostly zeros; with a tenth or more of the units indexed, a matrix product beats gathering rows)."""
    if rows.shape[1] == 1 or (n_in > DENSE_LIMIT and rows.shape[1] * DENSE_SHARE < n_in):
        return None
    torch = torch_module()
    return torch.zeros(rows.shape[0], n_in + 1).scatter_add_(1, rows, torch.ones(rows.shape))


def weight_shapes(n_in: int, net_arch: tuple[int, ...]) -> dict[str, tuple[int, ...]]:
    """The name and shape of every tensor of ``make_net(n_in, net_arch)``'s state dict (without building it)."""
    shapes = {}
    for part, out in (("actor", N_ACTIONS), ("critic", 1)):
        sizes = [*net_arch, out]
        shapes[f"{part}.first"], shapes[f"{part}.first_bias"] = (n_in + 1, sizes[0]), (sizes[0],)
        for i, (a, b) in enumerate(zip(sizes[:-1], sizes[1:])):
            shapes[f"{part}.layers.{i}.weight"], shapes[f"{part}.layers.{i}.bias"] = (b, a), (b,)
    return shapes
