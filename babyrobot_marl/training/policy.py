"""A trained PPO policy saved and loaded (the policies themselves, as robots, are ``trained.py``).

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

import os
import warnings
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

from ..core.table import Table
from .checks import ENV_SETTINGS, GLOBAL_FORM, check_fields, check_weights
from .deps import torch_module
from .ppo.config import PPOConfig
from .ppo.form import WindowForm
from .ppo.inputs import Inputs, near_offsets
from .ppo.net import make_net, weight_shapes
from .ppo.recurrent import make_recurrent_net, recurrent_weight_shapes
from .trained import TrainedPolicy, WindowPolicy

FORMAT = "babyrobot_marl.ppo"
# 4: the observation form records the goal hint, and a level family's policy reads local windows; 3: the file
# records the observation form the policy reads; 2: a race policy sees the robots near it (version 1 read every
# robot's cell)
VERSION = 4
# a file's fields (checks.FIELDS) and the observation form it records (checks.TRAINED_ON) are checked in checks


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
        if intents:  # an imitation crowd decides in turns; one saved before read who goes first, or not even that
            rows = _n_rows(data)
            kinds = [replace(window, ranks=True, turns=True), replace(window, ranks=True), window]
            window = next((f for f in kinds if f.n_in + 1 == rows), kinds[0])
        return window
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
    return recurrent_weight_shapes(inputs.n_in, arch, cfg.get("hidden", PPOConfig.hidden), cfg.get("cell", PPOConfig.cell))


def load_net(data: dict[str, Any]) -> Any:
    """The network of loaded data (``load_checkpoint``)."""
    cfg, n_in = data["config"], inputs_of(data).n_in
    if cfg.get("recurrent", False):
        net = make_recurrent_net(n_in, tuple(data["net_arch"]), cfg.get("hidden", PPOConfig.hidden),
                                 cfg.get("cell", PPOConfig.cell))
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
