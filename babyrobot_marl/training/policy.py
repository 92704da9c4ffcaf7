"""A trained PPO policy as a robot: the scripted policies' interface, saving and loading.

``TrainedPolicy(obs) -> action`` (also ``.act``, ``.name``) acts like ``policies.RandomPolicy``
and ``policies.ShortestPathPolicy``, on a single env's or a race robot's observation, and has
SB3's ``predict(obs, deterministic=True) -> (action, None)`` for the evaluation helpers.

A saved policy is one torch file (``torch.save`` of plain data and tensors, loaded with
``weights_only=True``): the format tag, the level's size and text, the robots it was trained
with, the layer sizes and the weights. ``make_policy(spec, table, seed)`` takes a scripted
policy's name or the path of a saved policy: the CLI's ``play --policy`` and ``race --policies``.
"""

from __future__ import annotations

import os
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from ..core.table import Table
from .ppo import Inputs, PerKey, _torch, make_net, near_offsets

FORMAT = "babyrobot_marl.ppo"
VERSION = 2  # 2: a race policy sees the robots near it (version 1 read every robot's cell)


class TrainedPolicy:
    """Acts with a trained actor on the input ``inputs`` describes: greedy (``deterministic=True``) or
    sampled from its own generator."""

    name = "trained"

    def __init__(self, net: Any, inputs: Inputs, n_robots: int, deterministic: bool = True, seed: int | None = None):
        self.net, self.inputs, self.n_robots = net, inputs, n_robots
        self.width, self.height = inputs.width, inputs.height
        self.deterministic = deterministic
        self.rng = np.random.default_rng(seed)
        torch = _torch()
        # the probabilities per input: a table over every input when there are few (one forward pass)
        self.probs = PerKey(inputs, lambda rows: torch.softmax(net.actor(rows), 1).double())
        if self.probs.table is not None:
            self._greedy = np.argmax(self.probs.table, axis=1).tolist()

    def action_probabilities(self, obs: Any) -> np.ndarray:
        """The policy's probabilities of the five actions given ``obs``."""
        return self.probs(np.array([self.inputs.key_of_observation(obs)]))[0]

    def __call__(self, obs: Any = None) -> int:
        if self.deterministic and self.probs.table is not None:
            return self._greedy[self.inputs.key_of_observation(obs)]
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


def save_policy(result: Any, path: str | os.PathLike) -> str:
    """Write a ``TrainResult``'s network and what it was trained on to ``path`` exactly; returns ``path``."""
    torch = _torch()
    level = result.level
    data = {
        "format": FORMAT,
        "version": VERSION,
        "width": level.width,
        "height": level.height,
        "level": level.to_ascii(),
        "level_name": level.name or "",
        "n_robots": result.n_robots,
        "net_arch": list(result.config.net_arch),
        "config": {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(result.config).items()},
        "timesteps": result.timesteps,
        "state_dict": result.net.state_dict(),
    }
    with open(path, "wb") as f:  # an open file: torch writes exactly here, whatever the suffix
        torch.save(data, f)
    return str(path)


def load_checkpoint(path: str | os.PathLike) -> dict[str, Any]:
    """The saved data, checked: a ``ValueError`` naming ``policy`` for anything that is not one."""
    torch = _torch()
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"policy: no such policy file {str(path)!r}")
    try:
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
    if version not in (1, VERSION):
        raise ValueError(f"policy: {str(path)!r} has format version {version!r}; this version reads {VERSION}")
    return data


def inputs_of(data: dict[str, Any]) -> Inputs:
    """The input of loaded data's network: its cell, and in a race the robots near it."""
    near = near_offsets(data["config"]["near_radius"]) if data["n_robots"] > 1 else ()
    return Inputs(data["width"], data["height"], near)


def load_net(data: dict[str, Any]) -> Any:
    """The network of loaded data (``load_checkpoint``)."""
    net = make_net(inputs_of(data).n_in, tuple(data["net_arch"]))
    net.load_state_dict(data["state_dict"])
    net.eval()
    return net


def load_policy(
    path: str | os.PathLike, table: Table | None = None, deterministic: bool = True, seed: int | None = None
) -> TrainedPolicy:
    """A saved policy as a robot. With ``table``, the level's size must be the one it was trained on."""
    data = load_checkpoint(path)
    w, h = data["width"], data["height"]
    if table is not None and (table.width, table.height) != (w, h):
        name = data["level_name"] or "its level"
        raise ValueError(
            f"policy: {str(path)!r} was trained on {name} ({w}x{h}); this level is {table.width}x{table.height} "
            f"(pass --level {data['level_name'] or 'a level of that size'})"
        )
    return TrainedPolicy(load_net(data), inputs_of(data), data["n_robots"], deterministic, seed)


def make_policy(spec: str, table: Table, seed: int | None = None) -> Any:
    """A scripted policy by name (``policies.make``), or the saved policy at path ``spec``."""
    from .. import policies

    if spec in policies.POLICY_NAMES:
        return policies.make(spec, table, seed)
    return load_policy(spec, table)


def is_policy_spec(spec: str) -> bool:
    """A scripted policy's name or an existing file (for argument checks)."""
    from .. import policies

    if spec in policies.POLICY_NAMES:
        return True
    try:
        return Path(spec).is_file()
    except (OSError, ValueError):  # a name too long for a path, a NUL byte: no such file
        return False
