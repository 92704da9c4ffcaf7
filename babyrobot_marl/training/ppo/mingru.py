"""A minGRU cell (Feng et al., 2024, "Were RNNs All We Needed?"): ``PPOConfig(recurrent=True, cell="mingru")``.

A GRU's gates read the state: every robot-step pays three products with ``W_hh``, forward and backward, in
each epoch. A minGRU's gates read the input alone::

    z = sigmoid(W_z x + b_z)      c = tanh(W_c x + b_c)      h' = (1 - z) h + z c

so with ``a = 1 - z`` and ``b = z c`` a step is ``h' = a h + b``, and ``a`` and ``b`` are functions of the input:
the trainer computes them once per distinct input (a rollout of a family meets a few thousand) and a robot-step
costs two element-wise operations, forward or backward, instead of a GRU's matrix products. The state still
carries the episode: what decays and what is written depend on what the robot sees at each step.
(The candidate keeps a GRU's tanh, so states stay within [-1, 1].)
"""

from __future__ import annotations

from typing import Any

from ..deps import torch_module


def mingru_inputs(g: Any, dim: int) -> Any:
    """``[a, b]`` along ``dim`` from the input's pre-activations ``g`` ``[W_z x + b_z, W_c x + b_c]``."""
    torch = torch_module()
    zg, cg = g.chunk(2, dim)
    z = torch.sigmoid(zg)
    return torch.cat((1.0 - z, z * torch.tanh(cg)), dim)


def mingru_unroll(x: Any, keep: Any, h: Any) -> tuple[Any, tuple[Any, ...]]:
    """The states ``(H, T, B)`` from the inputs' ``[a, b]`` ``x`` ``(2H, T, B)``, the resets ``keep`` ``(1, T, B)``
    and the first state ``h`` ``(H, B)``, feature-major as ``Recurrence.unroll``; and what the backward pass
    reads (each step's reset state, and ``a``)."""
    torch = torch_module()
    H, (_, T, B) = h.shape[0], x.shape
    states, reset = x.new_empty(H, T, B), x.new_empty(H, T, B)
    for t in range(T):
        hm = torch.mul(h, keep[:, t], out=reset[:, t])
        h = torch.addcmul(x[H:, t], x[:H, t], hm, out=states[:, t])
    return states, (reset, x[:H])


def mingru_backward(d_states: Any, saved: tuple[Any, ...], keep: Any) -> Any:
    """The loss's gradient at ``[a, b]`` ``(2H, T, B)`` from its gradient at the states ``(H, T, B)``, through time:
    ``h' = a h + b`` gives ``d b = d h'``, ``d a = d h' h`` and ``d h = d h' a`` (zero across a reset)."""
    torch = torch_module()
    reset, a = saved
    H, T, B = d_states.shape
    d_x = d_states.new_empty(2 * H, T, B)
    carry = d_states.new_zeros(H, B)
    for t in reversed(range(T)):
        dh = torch.add(d_states[:, t], carry, out=d_x[H:, t])
        torch.mul(dh, reset[:, t], out=d_x[:H, t])
        carry = dh * a[:, t] * keep[:, t]
    return d_x
