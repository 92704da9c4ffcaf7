"""A trained PPO policy as a robot: ``TrainedPolicy`` (one level's inputs) and ``WindowPolicy`` (a level family's
local window), with the scripted policies' interface; saving and loading them are in ``policy.py``.

``TrainedPolicy(obs) -> action`` (also ``.act``, ``.name``) acts like ``policies.RandomPolicy``
and ``policies.ShortestPathPolicy``, on a single env's or a race robot's observation, and has
SB3's ``predict(obs, deterministic=True) -> (action, None)`` for the evaluation helpers.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from ..core.checks import shown
from ..envs.encodings import Encoder
from .deps import torch_module, torch_threads
from .lru import LastUsed
from .ppo.form import NO_ACTION, WindowForm
from .ppo.inputs import Inputs
from .ppo.intents import robot_index, robot_intents
from .ppo.net import actor_probs
from .ppo.sampler import PerKey, sample_actions
from .ppo.trail import Trail
from .ppo.turns import env_turn


class Decoder:
    """Reads one observation of an env's form as a ``TrainedPolicy``'s key (``Inputs``).

    Without an env (``Decoder(inputs)``) it takes the form the policy was trained on, the global
    ``MultiDiscrete`` rows, and refuses what cannot be one (floats, a wrong length, values off the
    grid). ``Decoder.of_env(inputs, env)`` undoes the env's ``obs_encoding`` and reads its
    ``observe`` mode: "local" needs ``view_radius >= near_radius``, "nearest" ``k >= n_robots - 1``
    (fewer could leave out a robot the policy sees); a policy of one robot reads only ``[x, y]``.
    """

    def __init__(self, inputs: Inputs, observe: str = "global", encoder: Encoder | None = None, view_radius: int = 0):
        self.inputs, self.observe, self.encoder = inputs, observe, encoder  # encoder None: the form trained on
        side = 2 * view_radius + 1  # "local": the window cell of each near offset, row by row
        self.window_at = np.array([(dy + view_radius) * side + dx + view_radius for dx, dy in inputs.near], dtype=np.int64)

    @classmethod
    def of_env(cls, inputs: Inputs, env: Any) -> Decoder:
        """The decoder of ``env``'s observations (a Gymnasium or PettingZoo env of this package, wrapped or not)."""
        e = getattr(env, "unwrapped", env)
        e = getattr(e, "race", e)  # the race's Gymnasium adapter: robot_0's race observation
        encoder = getattr(e, "encoder", None)
        if encoder is None:
            raise TypeError(f"env: expected an env of babyrobot_marl (BabyRobotEnv, race_v0), got {type(env).__name__}")
        observe, observer = getattr(e, "observe", "global"), getattr(e, "_observer", None)
        m = len(inputs.near)
        radius = observer.view.radius if observe == "local" else 0
        need = max((abs(dx) + abs(dy) for dx, dy in inputs.near), default=0)  # near_radius
        if m and observe == "local" and radius < need:
            raise ValueError(f"policy: trained to see the robots within {need} steps (near_radius {need}); this env's "
                             f"observe='local' view_radius={radius} shows fewer: use view_radius >= {need}")
        if m and observe == "nearest" and observer.k < e.n_robots - 1:
            raise ValueError(f"policy: trained to see every robot near it; this env's observe='nearest' k={observer.k} "
                             f"of {e.n_robots - 1} other robots can leave one out: use k >= {e.n_robots - 1} (n_robots - 1)")
        return cls(inputs, observe, encoder, radius)

    def __call__(self, obs: Any) -> int:
        o = self._integers(obs)
        inputs, w, h = self.inputs, self.inputs.width, self.inputs.height
        if len(o) < 2 or not (0 <= o[0] < w and 0 <= o[1] < h):
            raise ValueError(f"obs: the robot's [x, y] must be on this policy's {w}x{h} grid, got {shown(o[:2].tolist())}")
        cell = int(o[1]) * w + int(o[0])
        m = len(inputs.near)
        if not m:
            return cell
        if self.observe == "local":
            bits = o[2:].reshape(-1, 6)[self.window_at, 1]  # LOCAL_FEATURES: the robot column
        else:
            occupied = self._others(o[2:], cell)
            bits = np.array([int(c) in occupied for c in inputs.neighbours[cell]])
        return (cell << m) | int(bits.astype(np.int64) @ (1 << np.arange(m)))

    def _others(self, rest: np.ndarray, cell: int) -> set[int]:
        """The cells of the other racing robots in view."""
        w, h = self.inputs.width, self.inputs.height
        if self.observe == "nearest":  # [dx + W - 1, dy + H - 1] each; missing ones off the grid
            x, y = rest[0::2] - (w - 1) + cell % w, rest[1::2] - (h - 1) + cell // w
            inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
            return set((y[inside] * w + x[inside]).tolist())
        triples = rest.reshape(-1, 3)
        return {int(y) * w + int(x) for x, y, finished in triples if not finished}

    def _integers(self, obs: Any) -> np.ndarray:
        """The observation's ``MultiDiscrete`` integers, its encoding undone and its form checked."""
        o = np.asarray(obs).reshape(-1)
        if self.encoder is None:  # the form trained on: global MultiDiscrete rows
            if not np.issubdtype(o.dtype, np.integer) or (len(o) - 2) % 3 or len(o) < 2:
                kind = o.dtype.name if o.dtype.kind in "biuf" else type(obs).__name__
                raise ValueError(
                    f"obs: this policy reads observe='global', obs_encoding='multidiscrete' observations (integers: [x, y], "
                    f"then [x, y, finished] per other robot), got {len(o)} {kind} numbers; bind it to your env with "
                    "policy.for_env(env) (other encodings and observe modes), or make the env with those settings"
                )
            return o.astype(np.int64)
        length = self.encoder.space.shape[0]
        if len(o) != length:
            raise ValueError(f"obs: this env's observations (observe={self.observe!r}, "
                             f"obs_encoding={self.encoder.encoding!r}) have {length} numbers, got {len(o)}")
        return self.encoder.decode(o)


class TrainedPolicy:
    """Acts with a trained actor on the input ``inputs`` describes: greedy (``deterministic=True``) or
    sampled from its own generator. It reads the observation form it was trained on
    (``Decoder``); ``for_env(env)`` gives the same policy reading ``env``'s form."""

    name = "trained"

    def __init__(self, net: Any, inputs: Inputs, n_robots: int, deterministic: bool = True, seed: int | None = None,
                 decoder: Decoder | None = None):
        self.net, self.inputs, self.n_robots = net, inputs, n_robots
        self.width, self.height = inputs.width, inputs.height
        self.deterministic = deterministic
        self.rng = np.random.default_rng(seed)
        self.decoder = decoder or Decoder(inputs)
        torch = torch_module()
        # the probabilities per input: a table over every input when there are few (one forward pass)
        self.probs = PerKey(inputs, lambda rows: torch.softmax(net.actor(rows), 1).double())
        if self.probs.table is not None:
            self._greedy = np.argmax(self.probs.table, axis=1).tolist()

    def for_env(self, env: Any) -> TrainedPolicy:
        """This policy reading ``env``'s observations (its ``obs_encoding`` and ``observe`` mode), or a
        ``ValueError`` naming what it cannot read. The level's size must be the one trained on."""
        e = getattr(getattr(env, "unwrapped", env), "race", getattr(env, "unwrapped", env))
        table = getattr(e, "table", None)
        if table is not None and (table.width, table.height) != (self.width, self.height):
            raise ValueError(f"policy: trained on a {self.width}x{self.height} level; this env's level is "
                             f"{table.width}x{table.height}")
        bound = copy.copy(self)  # the same net, tables and generator
        bound.decoder = Decoder.of_env(self.inputs, env)
        return bound

    def action_probabilities(self, obs: Any) -> np.ndarray:
        """The policy's probabilities of the five actions given ``obs``."""
        return self.probs(np.array([self.decoder(obs)]))[0]

    def __call__(self, obs: Any = None) -> int:
        if self.deterministic and self.probs.table is not None:
            return self._greedy[self.decoder(obs)]
        p = self.action_probabilities(obs)
        if self.deterministic:
            return int(np.argmax(p))
        return int(self.rng.choice(len(p), p=p / p.sum()))

    act = __call__

    def predict(
        self, obs: Any, state: Any = None, episode_start: Any = None, deterministic: bool = True
    ) -> tuple[np.ndarray, None]:
        """SB3's ``predict`` for one observation (greedy unless ``deterministic=False``)."""
        if deterministic == self.deterministic:
            return np.asarray(self(obs)), None
        saved, self.deterministic = self.deterministic, deterministic
        try:
            return np.asarray(self(obs)), None
        finally:
            self.deterministic = saved


PROBS_CACHE = 8192  # a window policy's action probabilities kept, the least recently used dropped first (~10 MB)


class WindowPolicy(TrainedPolicy):
    """A level family's policy: acts on ``race_v0``'s ``observe="local"`` rows of its ``view_radius`` (and
    hint bits, if trained with ``hint``), on any level. ``for_env(env)`` checks that ``env`` shows that
    form and undoes its ``obs_encoding``. The net runs once per distinct input (the last ``PROBS_CACHE`` kept).

    Trained with ``memory``, it also reads the action it took last (``last``, none at first); with ``trail``,
    its robot's trail (``trail``: where it has stood this episode, read on the env's level); a recurrent
    one (``PPOConfig.recurrent``) keeps its GRU's state (``hidden``, zero at first). One instance acts for one
    robot in one episode, so bind a new one (``for_env``) per robot and episode, as ``experiments.evaluate``
    and ``run_races`` do."""

    def __init__(self, net: Any, form: WindowForm, n_robots: int, deterministic: bool = True, seed: int | None = None,
                 encoder: Encoder | None = None):
        self.net, self.form, self.n_robots, self.encoder = net, form, n_robots, encoder
        self.deterministic = deterministic
        self.rng = np.random.default_rng(seed)
        self._probs = LastUsed(PROBS_CACHE)  # shared by the bound copies
        self.last = NO_ACTION  # the action it took last (read with ``memory``)
        self.hidden = self._fresh()  # a recurrent net's state (None: feed-forward)
        self.trail, self._env = Trail(), None  # where its robot has stood (read with ``trail``) on its env's level

    def _fresh(self) -> Any:
        return self.net.initial_state(1) if getattr(self.net, "recurrent", False) else None

    def _bound(self, encoder: Any, env: Any) -> WindowPolicy:
        """A copy reading through ``encoder`` on ``env``'s level: the same net, cache and generator; a memory of its own."""
        bound = copy.copy(self)
        bound.encoder, bound.last, bound.hidden, bound.trail = encoder, NO_ACTION, self._fresh(), Trail()
        bound._env = env  # its table read at each step: a level family's env draws a new level at reset
        return bound

    @property
    def observation(self) -> dict[str, Any]:
        """The env settings whose observations it reads (``race_v0.parallel_env(**policy.observation)``)."""
        form = {"observe": "local", "view_radius": self.form.radius, "hint": self.form.hint}
        return {**form, "goals": "own"} if self.form.own else form

    def for_env(self, env: Any) -> WindowPolicy:
        """This policy reading ``env``'s observations: a race env's of its own form, or a one-robot
        ``BabyRobotEnv``'s ``[x, y]`` read as that robot's local window (``SingleWindowRows``)."""
        e = getattr(env, "unwrapped", env)
        e = getattr(e, "race", e)
        encoder = getattr(e, "encoder", None)
        if encoder is None:
            raise TypeError(f"env: expected an env of babyrobot_marl (race_v0), got {type(env).__name__}")
        if not hasattr(e, "possible_agents") and self.form.own:
            raise ValueError("policy: trained with goals='own'; a one-robot env has its level's exits")
        if not hasattr(e, "possible_agents"):  # one robot, no race: its window read from the level
            return self._bound(SingleWindowRows(e, self.form), e)
        observer = getattr(e, "_observer", None)
        radius = observer.view.radius if getattr(e, "observe", "global") == "local" else None
        hint = bool(getattr(e, "hint", False))
        if radius != self.form.radius or hint != self.form.hint:
            shown_env = f"observe={getattr(e, 'observe', 'global')!r}"
            if radius is not None:
                shown_env += f", view_radius={radius}, hint={hint}"
            raise ValueError(f"policy: trained on observe='local', view_radius={self.form.radius}, hint={self.form.hint}; "
                             f"this env has {shown_env}")
        if getattr(e, "goals_mode", "exit") != self.form.goals:
            raise ValueError(f"policy: trained with goals={self.form.goals!r}; this env has goals={e.goals_mode!r}")
        if self.form.near and radius < max(abs(dx) + abs(dy) for dx, dy in self.form.near):
            raise ValueError(f"policy: sees the robots near it within view_radius {radius}")
        return self._bound(encoder, e)

    def rows(self, obs: Any) -> np.ndarray:
        """The net's row of indices for one observation (its encoding undone, its length checked)."""
        o = np.asarray(obs).reshape(-1)
        if self.encoder is not None:
            o = self.encoder.decode(o)
        size = self.form.obs_size()
        if len(o) != size or not np.issubdtype(o.dtype, np.integer):
            raise ValueError(f"obs: this policy reads observe='local' rows of view_radius {self.form.radius}"
                             f"{' with the hint' if self.form.hint else ''} ({size} integers), got {len(o)} "
                             f"{o.dtype.name} numbers; bind it to your env with policy.for_env(env)")
        trail = None
        if self.form.trail:
            if self._env is None:
                raise ValueError("obs: this policy reads its robot's trail on the env's level; bind it to your env "
                                 "with policy.for_env(env)")
            trail = np.array([self.trail.peek(o[0], o[1], self._env.table)])  # marked when the robot acts
        intents = None
        if self.form.intents:  # what the robots near it intend, read from the env it is bound to
            if self._env is None:
                raise ValueError("obs: this policy reads what the robots near its robot intend; bind it to your env "
                                 "with policy.for_env(env)")
            intents = robot_intents(self._env, self.form, (int(o[0]), int(o[1])))
        return self.form.rows_of_observations(o[None, :], np.array([self.last]), trail, intents)

    def action_probabilities(self, obs: Any) -> np.ndarray:
        return self._turn(obs)[0] if self.form.turns else self._next(obs)[0]

    def _turn(self, obs: Any) -> tuple[np.ndarray, int]:
        """A crowd that decides in turns: its robot's probabilities and action in the plan of its env's step
        (``turns.env_turn``), made at the step's first call, whichever robot's."""
        if self._env is None:
            raise ValueError("obs: this policy's robots decide in turns with the robots near them; bind it to your env "
                             "with policy.for_env(env)")
        decode = (lambda o: np.asarray(o).reshape(-1)) if self.encoder is None else self.encoder.decode

        def probs(rows: np.ndarray) -> np.ndarray:
            with torch_threads(1):
                return actor_probs(self.net, rows)

        def pick(p: np.ndarray) -> np.ndarray:
            return p.argmax(axis=1) if self.deterministic else sample_actions(p, self.rng)

        plan = env_turn(self._env, self.form, lambda o: decode(np.asarray(o).reshape(-1)), probs, pick)
        o = decode(np.asarray(obs).reshape(-1))
        i = robot_index(self._env, (int(o[0]), int(o[1])))
        return plan.probs[i], int(plan.actions[i])

    def _next(self, obs: Any) -> tuple[np.ndarray, Any]:
        """The probabilities and the recurrent state after ``obs`` (None: feed-forward)."""
        rows = self.rows(obs)
        key = rows.tobytes()
        p = self._probs.get(key)  # per input: the probabilities, or a recurrent net's input layers
        torch = torch_module()
        # one thread: on a busy machine torch's own threads wait on each other, 5 ms for this 1-row pass
        with torch.no_grad(), torch_threads(1):
            if p is None:
                x = torch.from_numpy(rows)
                recurrent = self.hidden is not None
                p = self.net.gate_inputs(x) if recurrent else actor_probs(self.net, x)[0]
                self._probs.put(key, p)
            if self.hidden is None:
                return p, None
            h = self.net.step(p, self.hidden)
            return torch.softmax(self.net.heads(h)[0], 1).double().numpy()[0], h

    def __call__(self, obs: Any = None) -> int:
        if self.form.turns:
            self.last = self._turn(obs)[1]
            return self.last
        p, self.hidden = self._next(obs)
        if self.form.trail:
            self.trail.mark()
        self.last = int(np.argmax(p)) if self.deterministic else int(self.rng.choice(len(p), p=p / p.sum()))
        return self.last

    act = __call__


class SingleWindowRows:
    """A one-robot env's ``[x, y]`` (``BabyRobotEnv``) decoded into the row race_v0's ``observe="local"``
    shows a lone robot there: its window of ``form.radius`` and, with ``form.hint``, the goal hint."""

    def __init__(self, env: Any, form: WindowForm):
        from ..core.observe import local_view
        from ..planning.hint import optimal_actions

        self.env, self.view = env, local_view(env.table, form.radius)
        self.hint = optimal_actions(env.table.level, env.rules).reshape(-1, 5) if form.hint else None

    def decode(self, obs: Any) -> np.ndarray:
        from ..core.observe import local_observations

        x, y = (int(v) for v in self.env.encoder.decode(np.asarray(obs).reshape(-1))[:2])
        cell = self.env.table.cell_id((x, y))
        row = local_observations(self.view, np.array([[cell]]), np.array([[True]]))[0, 0]
        return row if self.hint is None else np.concatenate([row, self.hint[cell].astype(np.int64)])
