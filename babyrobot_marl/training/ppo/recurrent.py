"""Recurrent policies (``PPOConfig.recurrent``): a GRU cell (or a minGRU, ``PPOConfig.cell``: ``mingru.py``) between
the input layers and the heads, and the hidden state of every robot kept beside the batch engine's cells.

A memoryless policy in a maze takes the same action wherever its windows look alike, so a greedy robot
cycles; one that remembers where it has been need not. The net (``make_recurrent_net``): the input
layers (a look-up of the first layer's rows, as ``net.make_net``; tanh), a GRU cell of ``hidden`` units,
then a linear actor head and a linear critic head on its state, as CleanRL's ``ppo_atari_lstm.py``.
A GRU rather than an LSTM: one state tensor per robot instead of two (one array to keep, reset and
replay), three weight blocks instead of four, and on small tasks the two learn alike.

Training (``Recurrence``) follows CleanRL's loop: during a rollout each robot's state is zeroed before
the first step of each of its episodes (and stays zero once it has finished and is parked); the state at
the rollout's start is kept, and the update replays each robot's whole rollout segment from it with the
same resets (truncated backpropagation through time over segments of ``n_steps``). Minibatches hold whole
segments; a parked robot's steps are no decisions and are masked out of the loss.

The actor and the critic share the cell, so the critic reads returns in units of ``1 / (1 - gamma)`` (the
largest discounted return of a step cost of 1): in raw units (-100 in a large maze) the value loss's gradient
drowns the policy's in the shared layers, and the clipped gradient leaves the policy almost unlearnt.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...core.actions import N_ACTIONS
from ..checks import check_cell
from ..deps import torch_module
from .mingru import mingru_backward, mingru_inputs, mingru_unroll
from .net import DENSE_LIMIT, log_softmax
from .sampler import Remembered, distinct_below, distinct_rows

DEFAULT_HIDDEN = 32  # PPOConfig.hidden
DEFAULT_CELL = "gru"  # PPOConfig.cell
DENSE_ROOM = 1 << 25  # floats up to which an update builds the one-hot counts of all its distinct inputs at once


def make_recurrent_net(n_in: int, net_arch: tuple[int, ...] = (64,), hidden: int = DEFAULT_HIDDEN,
                       cell: str = DEFAULT_CELL) -> Any:
    """The recurrent actor-critic: ``encode(rows)`` (the input layers, tanh; row ``n_in`` of ``first`` is the
    padding, kept zero), ``gate_inputs(rows)`` (then the cell's input part), ``step(gi, h)`` (the cell: a GRU, or
    ``cell="mingru"``, ``mingru.py``), ``heads(h) -> (logits, value)``. Orthogonal initialisation as SB3 and
    CleanRL (sqrt(2) for the input layers, 1 for the cell, 0.01 / 1 for the heads)."""
    torch = torch_module()
    nn = torch.nn
    sizes = list(net_arch) or [hidden]
    check_cell(cell)

    class RecurrentActorCritic(nn.Module):
        recurrent = True

        def __init__(self) -> None:
            super().__init__()
            self.n_in, self.net_arch, self.hidden, self.cell = n_in, tuple(net_arch), hidden, cell
            self.first = nn.Parameter(torch.empty(n_in + 1, sizes[0]))
            self.first_bias = nn.Parameter(torch.zeros(sizes[0]))
            self.layers = nn.ModuleList(nn.Linear(a, b) for a, b in zip(sizes[:-1], sizes[1:]))
            if cell == "gru":
                self.gru = nn.GRUCell(sizes[-1], hidden)
            else:  # the update gate and the candidate, from the input alone
                self.mingru = nn.Linear(sizes[-1], 2 * hidden)
            self.actor = nn.Linear(hidden, N_ACTIONS)
            self.critic = nn.Linear(hidden, 1)
            with torch.no_grad():
                w = torch.empty(sizes[0], n_in)
                nn.init.orthogonal_(w, math.sqrt(2))
                self.first[:n_in] = w.T
                self.first[n_in] = 0.0
                for layer in self.layers:
                    nn.init.orthogonal_(layer.weight, math.sqrt(2))
                    nn.init.zeros_(layer.bias)
                for name, p in (self.gru if cell == "gru" else self.mingru).named_parameters():
                    nn.init.orthogonal_(p) if "weight" in name else nn.init.zeros_(p)
                for head, gain in ((self.actor, 0.01), (self.critic, 1.0)):
                    nn.init.orthogonal_(head.weight, gain)
                    nn.init.zeros_(head.bias)

        def dense(self, rows: Any, room: Any = None) -> Any:
            """The multi-hot counts of rows of several indices, ``(B, n_in + 1)``, the padding column zero (no
            input, no gradient); None where a look-up is cheaper (one index per row, or a wide input). ``room``: a
            tensor of at least ``B`` rows to write them in (memory the process has touched already: fresh memory of
            tens of megabytes costs more to fault in than the counts)."""
            if not self.dense_applies(rows):
                return None
            dense = torch.zeros(rows.shape[0], n_in + 1) if room is None else room[: rows.shape[0]].zero_()
            dense.scatter_add_(1, rows, torch.ones(()).expand(rows.shape))
            dense[:, n_in] = 0.0
            return dense

        def dense_applies(self, rows: Any) -> bool:
            """Whether ``dense`` builds counts for ``rows``: not for one index per row or a wide input (a look-up is
            cheaper)."""
            return rows.shape[1] > 1 and n_in <= DENSE_LIMIT

        def encode(self, rows: Any, dense: Any = None) -> Any:
            """The input layers on ``rows`` (``dense``: their ``self.dense(rows)``, when it was built already; then
            ``rows`` is not read)."""
            dense = self.dense(rows) if dense is None else dense
            if dense is not None:  # the one-hot counts times the weights: faster than many look-ups
                h = torch.tanh(torch.addmm(self.first_bias, dense, self.first))
            else:
                b, k = rows.shape
                h = nn.functional.embedding(rows, self.first, padding_idx=n_in)  # the padding row gets no gradient
                h = torch.tanh((h if k == 1 else h.sum(1)).view(b, -1) + self.first_bias)
            for layer in self.layers:
                h = torch.tanh(layer(h))
            return h

        def gate_inputs(self, rows: Any, dense: Any = None) -> Any:
            """The cell's input part (``(B, 3 * hidden)``: a GRU's ``W_ih x + b_ih``; ``(B, 2 * hidden)``: a minGRU's
            decay and input): a function of the input alone, computed once per distinct input and looked up per
            robot-step."""
            if cell == "gru":
                return torch.addmm(self.gru.bias_ih, self.encode(rows, dense), self.gru.weight_ih.T)
            return mingru_inputs(torch.addmm(self.mingru.bias, self.encode(rows, dense), self.mingru.weight.T), 1)

        def gate_columns(self, rows: Any, dense: Any = None) -> Any:
            """``gate_inputs`` feature-major, ``(G, B)`` (the update's layout)."""
            x = self.encode(rows, dense).T
            if cell == "gru":
                return torch.addmm(self.gru.bias_ih[:, None], self.gru.weight_ih, x)
            return mingru_inputs(torch.addmm(self.mingru.bias[:, None], self.mingru.weight, x), 0)

        def step(self, gi: Any, h: Any) -> Any:
            """The cell's step from its input part ``gi`` (``gate_inputs``) and the state ``h``: ``nn.GRUCell``'s, or
            a minGRU's ``a h + b``."""
            if cell == "mingru":
                return torch.addcmul(gi[:, hidden:], gi[:, :hidden], h)
            gh = torch.addmm(self.gru.bias_hh, h, self.gru.weight_hh.T)
            r, z = torch.sigmoid(gi[:, : 2 * hidden] + gh[:, : 2 * hidden]).chunk(2, 1)
            n = torch.tanh(gi[:, 2 * hidden :] + r * gh[:, 2 * hidden :])
            return n + z * (h - n)

        def heads(self, h: Any) -> tuple[Any, Any]:
            return self.actor(h), self.critic(h)[:, 0]

        def initial_state(self, n: int) -> Any:
            return torch.zeros(n, hidden)

    return RecurrentActorCritic()


def recurrent_weight_shapes(n_in: int, net_arch: tuple[int, ...], hidden: int,
                            cell: str = DEFAULT_CELL) -> dict[str, tuple[int, ...]]:
    """The name and shape of every tensor of ``make_recurrent_net(n_in, net_arch, hidden, cell)``'s state dict."""
    sizes = list(net_arch) or [hidden]
    shapes: dict[str, tuple[int, ...]] = {"first": (n_in + 1, sizes[0]), "first_bias": (sizes[0],)}
    for i, (a, b) in enumerate(zip(sizes[:-1], sizes[1:])):
        shapes[f"layers.{i}.weight"], shapes[f"layers.{i}.bias"] = (b, a), (b,)
    if cell == "gru":
        shapes.update({"gru.weight_ih": (3 * hidden, sizes[-1]), "gru.weight_hh": (3 * hidden, hidden),
                       "gru.bias_ih": (3 * hidden,), "gru.bias_hh": (3 * hidden,)})
    else:
        shapes.update({"mingru.weight": (2 * hidden, sizes[-1]), "mingru.bias": (2 * hidden,)})
    shapes.update({"actor.weight": (N_ACTIONS, hidden),
                   "actor.bias": (N_ACTIONS,), "critic.weight": (1, hidden), "critic.bias": (1,)})
    return shapes


def normalised(a: Any, m: Any, n: Any) -> Any:
    """The advantages ``a`` normalised over the ``n`` decisions (``m`` 1) among them, as the loss reads them."""
    torch = torch_module()
    mean = (a * m).sum() / n
    return (a - mean) / (torch.sqrt((((a - mean) * m) ** 2).sum() / (n - 1)) + 1e-8)


class Recurrence:
    """The hidden states of ``n_seq`` robots (``E * R``, row-major) through rollouts, what the update replays,
    and the update itself. In a rollout: ``start(inputs)``, then per step ``sample(keys, rng)`` (the actor:
    each robot's state advanced one step) and ``ended(done)`` (whose episode ended at that step)."""

    def __init__(self, net: Any, n_seq: int, n_steps: int, value_scale: float = 1.0):
        self.net, self.t = net, 0
        # the critic head reads returns in units of ``value_scale``: its state is shared with the actor, and
        # returns of -100 would make the value loss's gradient drown the policy's in the cell and input layers
        self.value_scale = float(value_scale)
        self.h = net.initial_state(n_seq)
        self.keep = np.ones(n_seq, dtype=bool)  # False: the robot's next step starts an episode (state zeroed)
        self.keep_buf = np.zeros((n_steps, n_seq), dtype=bool)
        self.logp_buf = np.zeros((n_steps, n_seq), dtype=np.float32)  # the sampled action's log-probability
        self.value_buf = np.zeros((n_steps, n_seq), dtype=np.float32)
        self.final_value = np.zeros((n_steps, n_seq), dtype=np.float32)  # of a truncated episode's last observation
        self.h0 = self.h
        self.room = torch_module().zeros(0, 0)  # the update's one-hot counts, kept from one update to the next

    def restart(self) -> None:
        """Every robot starts a new episode (new mazes)."""
        self.keep[:] = False

    def start(self, inputs: Any) -> Recurrence:
        """A rollout begins: the weights are fixed, so the input layers run once per distinct input."""
        self.t, self.h0 = 0, self.h.clone()
        self.features = Remembered(inputs, self.net.gate_inputs)
        return self

    def _advance(self, keys: np.ndarray, h: Any) -> Any:
        torch = torch_module()
        return self.net.step(torch.from_numpy(self.features(keys)), h)

    def sample(self, keys: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """One action per robot by inverse-CDF sampling (one uniform number each, as ``Sampler``)."""
        torch = torch_module()
        self.keep_buf[self.t] = self.keep
        self.h = self._advance(keys, self.h * torch.from_numpy(self.keep)[:, None])
        logits, value = self.net.heads(self.h)
        logp = log_softmax(logits).numpy()
        u = rng.random((keys.size, 1))
        actions = np.minimum((u >= np.cumsum(np.exp(logp), axis=1)).sum(axis=1), N_ACTIONS - 1)
        self.logp_buf[self.t] = logp[np.arange(keys.size), actions]
        self.value_buf[self.t] = value.numpy() * self.value_scale
        return actions

    def ended(self, done: np.ndarray) -> None:
        self.keep = ~done.reshape(-1)
        self.t += 1

    def truncated(self, keys: np.ndarray, which: np.ndarray) -> None:
        """The critic's values of the last observations (``keys``) of the robots ``which`` whose episodes the
        time limit ended at this step: their states carry on into that observation."""
        at = np.flatnonzero(which.reshape(-1))
        h = self._advance(keys.reshape(-1)[at], self.h[at])
        self.final_value[self.t - 1, at] = self.net.heads(h)[1].numpy() * self.value_scale

    def next_value(self, keys: np.ndarray) -> np.ndarray:
        """The critic's values of the observations after the rollout (for GAE's bootstrap)."""
        torch = torch_module()
        h = self._advance(keys.reshape(-1), self.h * torch.from_numpy(self.keep)[:, None])
        return self.net.heads(h)[1].numpy().reshape(keys.shape) * self.value_scale

    def replay(self, rows: Any, inv: Any, seq: Any) -> tuple[Any, Any]:
        """The logits and values ``(T * B, ...)`` of the robots ``seq`` over the rollout, replayed from their
        states at its start with the rollout's resets; ``rows[inv]`` (``(T, B)``): their inputs. By autograd
        through ``net.step``: the reference the update's written-out pass (``unroll``) is held to."""
        torch = torch_module()
        present, local = torch.unique(inv, return_inverse=True)
        # (T * B, 3H): the input layers once per distinct input (index_select: its gradient is one index_add)
        x = self.net.gate_inputs(rows[present]).index_select(0, local.reshape(-1)).view(*inv.shape, -1)
        keep = torch.from_numpy(self.keep_buf)[:, seq, None]
        h, states = self.h0[seq], []
        for t, x_t in enumerate(x.unbind(0)):  # unbind: one gradient buffer for all steps (x[t]'s would fill one each)
            h = self.net.step(x_t, h * keep[t])
            states.append(h)
        return self.net.heads(torch.cat(states))

    def unroll(self, x: Any, keep: Any, h: Any) -> tuple[Any, tuple[Any, ...]]:
        """The replay's cell without autograd, feature-major: the states ``(H, T, B)`` from the gates' input parts
        ``x`` ``(3H, T, B)``, the resets ``keep`` ``(1, T, B)`` and the first state ``h`` ``(H, B)``, and what
        ``unroll_backward`` reads (each step's reset state, gates and ``W_hn h``). Feature-major, each gate is one
        block, every step's values are written in place and the weights' gradients are single products over all
        steps (in ``(B, 3H)`` rows, slicing the gates and copying them cost as much as the arithmetic)."""
        if self.net.cell == "mingru":
            return mingru_unroll(x, keep, h)
        torch = torch_module()
        gru, H = self.net.gru, self.net.hidden
        _, T, B = x.shape
        states, reset, gates, gh_n = (x.new_empty(k, T, B) for k in (H, H, 3 * H, H))
        w, b = gru.weight_hh, gru.bias_hh[:, None]
        for t in range(T):
            hm = torch.mul(h, keep[:, t], out=reset[:, t])
            gh = torch.addmm(b, w, hm)
            rz, n = gates[: 2 * H, t], gates[2 * H :, t]
            torch.sigmoid(torch.add(x[: 2 * H, t], gh[: 2 * H], out=rz), out=rz)
            torch.tanh(torch.addcmul(x[2 * H :, t], rz[:H], gh[2 * H :], out=n), out=n)
            gh_n[:, t] = gh[2 * H :]
            h = torch.addcmul(n, rz[H:], hm - n, out=states[:, t])
        return states, (reset, gates, gh_n)

    def unroll_backward(self, d_states: Any, saved: tuple[Any, ...], keep: Any) -> Any:
        """The loss's gradient at the gates' input parts ``(3H, T, B)`` from its gradient at the states
        ``d_states`` (``(H, T, B)``), through time; adds ``W_hh``'s and ``b_hh``'s to their ``.grad``.
        Written out as ``net.py``'s MLP: autograd's graph of a step's dozen small operations cost more than them."""
        if self.net.cell == "mingru":
            return mingru_backward(d_states, saved, keep)
        torch = torch_module()
        gru, H = self.net.gru, self.net.hidden
        reset, gates, gh_n = saved
        _, T, B = d_states.shape
        r, z, n = gates[:H], gates[H : 2 * H], gates[2 * H :]
        # the factors that do not depend on the gradient, for all steps at once: the loop keeps only what carries
        f_n = (1 - z) * (1 - n * n)  # through h = n + z (h_prev - n), then n's tanh
        f_z = (reset - n) * z * (1 - z)  # through z's sigmoid
        f_r = gh_n * r * (1 - r)  # through n's input r * W_hn h, then r's sigmoid
        d_gi, d_gh = d_states.new_empty(3 * H, T, B), d_states.new_empty(3 * H, T, B)
        carry = d_states.new_zeros(H, B)
        w_t = gru.weight_hh.T
        for t in reversed(range(T)):
            dh = torch.add(d_states[:, t], carry)
            gh, d_n = d_gh[:, t], d_gi[2 * H :, t]
            torch.mul(dh, f_n[:, t], out=d_n)
            torch.mul(d_n, f_r[:, t], out=gh[:H])
            torch.mul(dh, f_z[:, t], out=gh[H : 2 * H])
            torch.mul(d_n, r[:, t], out=gh[2 * H :])  # W_hn h enters n times r
            carry = torch.addmm(dh.mul_(z[:, t]), w_t, gh).mul_(keep[:, t])
        d_gi[: 2 * H] = d_gh[: 2 * H]
        flat = d_gh.view(3 * H, -1)
        for p, g in ((gru.weight_hh, flat @ reset.view(H, -1).T), (gru.bias_hh, flat.sum(1))):
            p.grad = g if p.grad is None else p.grad.add_(g)
        return d_gi

    def update(self, inputs: Any, keys: np.ndarray, actions: np.ndarray, adv: np.ndarray, returns: np.ndarray,
               valid: np.ndarray, cfg: Any, optim: Any, params: list[Any], order: Any) -> None:
        """``n_epochs`` passes over the rollout's segments (``(T, S)`` arrays), minibatches of whole segments
        (``batch_size // n_steps`` of them), each replayed from its state at the rollout's start."""
        from .update import clip_grad_norm, grads_of

        torch = torch_module()
        T, S = keys.shape[0], self.h0.shape[0]
        rows, inv = distinct_rows(inputs, keys.reshape(-1))
        inv = inv.view(T, S)
        keep = torch.from_numpy(self.keep_buf.astype(np.float32))
        per = max(1, cfg.batch_size // T)
        batch = (torch.from_numpy(self.logp_buf), torch.from_numpy(actions.reshape(T, S)),
                 torch.from_numpy(adv.reshape(T, S)),
                 torch.from_numpy((returns.reshape(T, S) / self.value_scale).astype(np.float32)),
                 torch.from_numpy(valid.reshape(T, S).astype(np.float32)))
        # the one-hot counts of every distinct input at once, when they fit: a minibatch's are then its rows of them
        dense_all = None
        if self.net.dense_applies(rows) and rows.shape[0] * (self.net.n_in + 1) <= DENSE_ROOM:
            if len(self.room) < rows.shape[0]:
                self.room = torch.empty(rows.shape[0] + rows.shape[0] // 4, self.net.n_in + 1)
            dense_all = self.net.dense(rows, self.room)
        whole = None  # one minibatch holds every segment: its distinct inputs found once, not every epoch
        for _ in range(cfg.n_epochs):
            perm = torch.randperm(S, generator=order) if per < S else torch.arange(S)
            for start in range(0, S, per):
                seq = perm[start : start + per]
                part = [b.index_select(1, seq) for b in batch]
                if part[-1].sum() == 0:
                    continue
                optim.zero_grad(set_to_none=False)
                if whole is None or per < S:
                    present, local = map(torch.from_numpy, distinct_below(inv[:, seq].numpy(), rows.shape[0]))
                    if dense_all is not None:
                        mb_rows, dense = None, dense_all.index_select(0, present)
                    else:
                        mb_rows = rows[present]
                        dense = self.net.dense(mb_rows)
                    whole = mb_rows, dense, local.reshape(-1), keep.index_select(1, seq)[None], self.h0[seq].T
                mb_rows, dense, local, mb_keep, h0 = whole
                # the input layers once per distinct input (feature-major), by autograd; the cell through time, the
                # heads and the loss by hand
                x = self.net.gate_columns(mb_rows, dense).index_select(1, local).view(-1, T, len(seq))
                with torch.no_grad():
                    states, saved = self.unroll(x.detach(), mb_keep, h0)
                    d_states = self.heads_backward(states.view(states.shape[0], -1), part, cfg)
                    d_x = self.unroll_backward(d_states.view_as(states), saved, mb_keep)
                x.backward(d_x)
                clip_grad_norm(grads_of(params), cfg.max_grad_norm)
                optim.step()

    def heads_backward(self, h: Any, part: list[Any], cfg: Any) -> Any:
        """``loss``'s gradient, written out (autograd's graph of its dozen operations on every robot-step cost more
        than they): adds the heads' gradients to their ``.grad`` and returns the loss's gradient at the states ``h``
        (``(H, T * B)``, feature-major); ``part``: the minibatch's ``(T, B)`` arrays as ``loss`` reads them."""
        torch = torch_module()
        old, act, a, ret, m = (x.reshape(-1) for x in part)
        n = m.sum()
        actor, critic = self.net.actor, self.net.critic
        logp = log_softmax(torch.addmm(actor.bias[:, None], actor.weight, h).T)
        value = torch.addmm(critic.bias[:, None], critic.weight, h)[0]
        p = torch.exp(logp)
        if cfg.normalize_advantage and n > 1:
            a = normalised(a, m, n)
        ratio = torch.exp(logp.gather(1, act[:, None])[:, 0] - old)
        w = m / n  # each decision's weight in the mean; parked steps none
        # the min picks the unclipped term (the one with a gradient) for A > 0 while r <= 1 + c, for A < 0 while r >= 1 - c
        c = cfg.clip_range
        g = torch.where(a > 0, ratio <= 1.0 + c, ratio >= 1.0 - c) * (-a * ratio * w)  # d loss / d logp(action)
        # d logp(action) / d z = onehot(action) - p;  d (-entropy) / d z = p (log p + entropy)
        entropy = -(p * logp).sum(1, keepdim=True)
        dz = (p * (logp + entropy)).mul_((cfg.ent_coef * w)[:, None]).sub_(g[:, None] * p)
        dz.scatter_add_(1, act[:, None], g[:, None])
        dv = (value - ret).mul_(2.0 * cfg.vf_coef * w)
        for param, grad in ((actor.weight, dz.T @ h.T), (actor.bias, dz.sum(0)), (critic.weight, dv[None] @ h.T),
                            (critic.bias, dv.sum(0, keepdim=True))):
            param.grad = grad if param.grad is None else param.grad.add_(grad)
        return torch.addmm(critic.weight.T @ dv[None], actor.weight.T, dz.T)

    @staticmethod
    def loss(logits: Any, value: Any, old: Any, act: Any, a: Any, ret: Any, m: Any, cfg: Any) -> Any:
        """SB3's PPO loss over a minibatch of whole segments (``(T, B)`` arrays), the parked steps (``m`` 0)
        left out; advantages normalised over the minibatch's decisions. The update uses its gradient as
        ``heads_backward`` writes it; this is the reference it is held to."""
        torch = torch_module()
        T = old.shape[0]
        n = m.sum()
        logp = log_softmax(logits).view(T, -1, N_ACTIONS)
        new = logp.gather(2, act[..., None])[..., 0]
        if cfg.normalize_advantage and n > 1:
            a = normalised(a, m, n)
        ratio = torch.exp(new - old)
        pg = torch.maximum(-a * ratio, -a * torch.clamp(ratio, 1 - cfg.clip_range, 1 + cfg.clip_range))
        entropy = -(torch.exp(logp) * logp).sum(2)
        v_err = (value.view(T, -1) - ret) ** 2
        return ((pg - cfg.ent_coef * entropy + cfg.vf_coef * v_err) * m).sum() / n
