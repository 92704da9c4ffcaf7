"""A trained PPO policy as a robot: the scripted policies' interface, saving and loading.

``TrainedPolicy(obs) -> action`` (also ``.act``, ``.name``) acts like ``policies.RandomPolicy``
and ``policies.ShortestPathPolicy``, on a single env's or a race robot's observation, and has
SB3's ``predict(obs, deterministic=True) -> (action, None)`` for the evaluation helpers.

A saved policy is one torch file (``torch.save`` of plain data and tensors, loaded with
``weights_only=True``): the format tag, the level's size and text, the robots it was trained
with, the observation form it reads (``observation``: ``observe="global"``,
``obs_encoding="multidiscrete"``; ``config["near_radius"]``: the robots it sees), the layer sizes
and the weights. Every field is checked on load (``load_checkpoint``): anything else is one
``ValueError`` naming ``policy``, the file and the field.

A policy reads the observation form it was trained on; ``policy.for_env(env)`` (or
``load_policy(path, env=env)``) reads that env's form instead: any ``obs_encoding``, and
``observe="local"`` / ``"nearest"`` when the view holds every robot the policy sees, else a
``ValueError`` naming the mismatch. ``make_policy(spec, table, seed, env)`` takes a scripted
policy's name or the path of a saved policy: the CLI's ``play --policy`` and ``race --policies``.
"""

from __future__ import annotations

import copy
import os
import warnings
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..core.checks import shown
from ..core.table import Table
from ..envs.encodings import Encoder
from .checks import ENV_SETTINGS, GLOBAL_FORM, check_fields, check_weights
from .deps import torch_module, torch_threads
from .lru import LastUsed
from .ppo.config import PPOConfig
from .ppo.form import NO_ACTION, WindowForm
from .ppo.inputs import Inputs, near_offsets
from .ppo.intents import robot_intents
from .ppo.net import make_net, weight_shapes
from .ppo.recurrent import make_recurrent_net, recurrent_weight_shapes
from .ppo.sampler import PerKey
from .ppo.trail import Trail

FORMAT = "babyrobot_marl.ppo"
# 4: the observation form records the goal hint, and a level family's policy reads local windows; 3: the file
# records the observation form the policy reads; 2: a race policy sees the robots near it (version 1 read every
# robot's cell)
VERSION = 4
# a file's fields (checks.FIELDS) and the observation form it records (checks.TRAINED_ON) are checked in checks


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
        return self._next(obs)[0]

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
                p = self.net.gate_inputs(x) if recurrent else torch.softmax(self.net.actor(x), 1).double().numpy()[0]
                self._probs.put(key, p)
            if self.hidden is None:
                return p, None
            h = self.net.step(p, self.hidden)
            return torch.softmax(self.net.heads(h)[0], 1).double().numpy()[0], h

    def __call__(self, obs: Any = None) -> int:
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


def save_policy(result: Any, path: str | os.PathLike) -> str:
    """Write a ``TrainResult``'s network and what it was trained on to ``path`` exactly; returns ``path``."""
    torch = torch_module()
    level = result.level
    data = {
        "format": FORMAT,
        "version": VERSION,
        "width": level.width,
        "height": level.height,
        "level": level.to_ascii(),
        "level_name": getattr(result, "family", None) or level.name or "",
        "n_robots": result.n_robots,
        "observation": observation_form(result),
        "net_arch": list(result.config.net_arch),
        "config": {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(result.config).items()},
        "timesteps": result.timesteps,
        "state_dict": result.net.state_dict(),
    }
    if getattr(result, "env", None) and result.env != ENV_SETTINGS:  # trained under other env settings: named
        data["env"] = dict(result.env)
    with open(path, "wb") as f:  # an open file: torch writes exactly here, whatever the suffix
        torch.save(data, f)
    return str(path)


def observation_form(result: Any) -> dict[str, Any]:
    """What the policy of a ``TrainResult`` reads: the global rows, or (a level family) local windows."""
    if getattr(result, "family", None) is None:
        return dict(GLOBAL_FORM)
    form = {"observe": "local", "obs_encoding": "multidiscrete", "view_radius": result.config.view_radius,
            "hint": bool(result.config.hint)}
    own = getattr(result, "goals", "exit") == "own"
    return {**form, "goals": "own"} if own else form  # own goals: it also reads its target channel


def load_checkpoint(path: str | os.PathLike) -> dict[str, Any]:
    """The saved data, every field checked: a ``ValueError`` naming ``policy``, the file and the field
    for anything that is not a policy this version reads."""
    torch = torch_module()
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"policy: no such policy file {str(path)!r}")
    try:
        with warnings.catch_warnings():  # torch warns about a plain pickle's protocol before refusing it
            warnings.simplefilter("ignore")
            data = torch.load(p, map_location="cpu", weights_only=True)
    except Exception as err:  # a zip of SB3, a text file, a truncated file: all say the same
        what = type(err).__name__
        raise ValueError(f"policy: {str(path)!r} is not a policy saved by 'babyrobot-marl train' ({what})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ValueError(f"policy: {str(path)!r} is not a policy saved by 'babyrobot-marl train'")
    version = data.get("version")
    if version == 1 and data.get("n_robots") != 1:  # a one-robot policy of version 1 is the same net
        raise ValueError(f"policy: {str(path)!r} is a race policy of format version 1 (it read every robot's cell); "
                         f"train it again with this version")
    if version not in (1, 2, 3, VERSION):
        raise ValueError(f"policy: {str(path)!r} has format version {version!r}; this version reads {VERSION}")
    try:
        check_fields(data, version, PPOConfig)
        arch = tuple(data["net_arch"])
        check_weights(data["state_dict"], _shapes(data, inputs_of(data)), arch)
    except ValueError as err:
        raise ValueError(f"policy: {str(path)!r} is a broken policy file: {err}") from None
    return data


def inputs_of(data: dict[str, Any]) -> Inputs | WindowForm:
    """The input of loaded data's network: its cell, and in a race the robots near it; for a level
    family's policy, its local window (``WindowForm``)."""
    near = near_offsets(data["config"]["near_radius"]) if data["n_robots"] > 1 else ()
    form = data.get("observation", GLOBAL_FORM)
    if form.get("observe") == "local":
        memory, trail = (bool(data["config"].get(name, False)) for name in ("memory", "trail"))
        intents = data["config"].get("imitate") is not None and bool(near)  # an imitation crowd reads its neighbours
        window = WindowForm(form["view_radius"], near, form["hint"], memory, form.get("goals", "exit"), trail, intents)
        return replace(window, ranks=intents and _n_rows(data) != window.n_in + 1)  # saved before ranks: without them
    return Inputs(data["width"], data["height"], near)


def _n_rows(data: dict[str, Any]) -> int | None:
    """The rows of the saved net's first layer (its inputs and the padding), None where it has none."""
    first = data.get("state_dict", {}).get("actor.first")
    return None if first is None else int(first.shape[0])


def observation_kwargs(path: str | os.PathLike) -> dict[str, Any]:
    """The env arguments of the observations a saved policy reads: ``{}`` for the global rows (an env's
    default), else ``observe="local"`` with its ``view_radius`` and ``hint``."""
    form = load_checkpoint(path).get("observation", GLOBAL_FORM)
    if form.get("observe") != "local":
        return {}
    return {"observe": "local", "view_radius": form["view_radius"], "hint": form["hint"]}


def _shapes(data: dict[str, Any], inputs: Inputs | WindowForm) -> dict[str, tuple[int, ...]]:
    """The weights' names and shapes of loaded data's network: a recurrent one reads local windows only."""
    cfg, arch = data["config"], tuple(data["net_arch"])
    if not cfg.get("recurrent", False):
        return weight_shapes(inputs.n_in, arch)
    if not isinstance(inputs, WindowForm):
        raise ValueError("config: a recurrent policy reads local windows (observe='local'), got the global rows")
    return recurrent_weight_shapes(inputs.n_in, arch, cfg.get("hidden", PPOConfig.hidden))


def load_net(data: dict[str, Any]) -> Any:
    """The network of loaded data (``load_checkpoint``)."""
    cfg, n_in = data["config"], inputs_of(data).n_in
    if cfg.get("recurrent", False):
        net = make_recurrent_net(n_in, tuple(data["net_arch"]), cfg.get("hidden", PPOConfig.hidden))
    else:
        net = make_net(n_in, tuple(data["net_arch"]))
    net.load_state_dict(data["state_dict"])
    net.eval()
    return net


def load_policy(
    path: str | os.PathLike, table: Table | None = None, deterministic: bool = True, seed: int | None = None,
    env: Any = None,
) -> TrainedPolicy:
    """A saved policy as a robot. With ``table`` (or ``env``), the level's size must be the one it was
    trained on; with ``env``, it reads that env's observations (``TrainedPolicy.for_env``)."""
    data = load_checkpoint(path)
    inputs = inputs_of(data)
    if isinstance(inputs, WindowForm):  # any level: it reads local windows
        window = WindowPolicy(load_net(data), inputs, data["n_robots"], deterministic, seed)
        return window if env is None else window.for_env(env)
    w, h = data["width"], data["height"]
    if table is None and env is not None:
        e = getattr(env, "unwrapped", env)
        table = getattr(getattr(e, "race", e), "table", None)
    if table is not None and (table.width, table.height) != (w, h):
        name = data["level_name"] or "its level"
        raise ValueError(
            f"policy: {str(path)!r} was trained on {name} ({w}x{h}); this level is {table.width}x{table.height} "
            f"(pass --level {data['level_name'] or 'a level of that size'})"
        )
    policy = TrainedPolicy(load_net(data), inputs, data["n_robots"], deterministic, seed)
    return policy if env is None else policy.for_env(env)


def make_policy(spec: str, table: Table, seed: int | None = None, env: Any = None) -> Any:
    """A scripted policy by name (``policies.make``), or the saved policy at path ``spec`` (named
    ``spec``; reading ``env``'s observations if given)."""
    from .. import policies

    if spec in policies.POLICY_NAMES:
        return policies.make(spec, table, seed)
    policy = load_policy(spec, table, env=env)
    policy.name = spec  # its name in tables: the file
    return policy


def is_policy_spec(spec: str) -> bool:
    """A scripted policy's name or an existing file (for argument checks)."""
    from .. import policies

    if spec in policies.POLICY_NAMES:
        return True
    try:
        return Path(spec).is_file()
    except (OSError, ValueError):  # a name too long for a path, a NUL byte: no such file
        return False
