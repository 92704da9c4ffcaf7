"""The training layer's checks: PPO's settings, a run whose weights stopped being finite, a saved policy's fields.

Each error is one ``ValueError`` (``TrainingDivergedError`` for a run that diverged) whose message
starts with the setting or field it is about. The integer and real rules are the core's
(``core.checks.check_int``, ``check_real``). This module imports nothing of ``training.ppo``:
``ppo.config`` and ``ppo.inputs`` import it, and ``check_fields`` is given the settings' class.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields
from typing import Any

from ..core.checks import MAX_LEVEL_CELLS, MAX_LEVEL_TEXT_CHARS, check_int, check_real, shown
from .deps import torch_module

MAX_LAYER_SIZE, MAX_LAYERS = 4096, 8  # a net's hidden layers: a setting or a policy file never asks for gigabytes
MAX_NEAR_RADIUS = 4  # 40 cells: a key (16 bits of cell, one bit per cell) stays within int64

# A saved policy (training.policy): its fields, and the observation form the fast trainer's policies read,
# the global MultiDiscrete rows (robot's [x, y], then [x, y, finished] of every other robot)
FIELDS = ("format", "version", "width", "height", "level", "level_name", "n_robots", "net_arch", "config", "timesteps",
          "state_dict")
TRAINED_ON = {"observe": "global", "obs_encoding": "multidiscrete"}
# version 4 records ``hint`` in every observation form; a level family's policy reads ``observe="local"`` windows
# of the saved ``view_radius`` (training.ppo.window.WindowForm)
GLOBAL_FORM = {**TRAINED_ON, "hint": False}
LOCAL_FORM_KEYS = ("observe", "obs_encoding", "view_radius", "hint")
CELL_NAMES = {"gru": "a GRU", "mingru": "a minGRU"}  # PPOConfig.cell: a recurrent net's cell, as summaries name it
CELL_CHOICES = tuple(CELL_NAMES)
FINISHED_RULES = ("remove", "stay")  # a policy's own goals: robots leave at their targets, or stay racing there
# a saved policy's env settings, with their defaults
ENV_SETTINGS = {"goals": "exit", "collisions": "block", "lifelong": False, "finished": "remove"}


# ---------------------------------------------------------------------------- PPO's settings
def check_config(cfg: Any, start_choices: Sequence[str], imitate_choices: Sequence[str] = ()) -> tuple[int, ...]:
    """Every setting of ``cfg`` (a ``PPOConfig`` being made), in this order; returns its ``net_arch`` as a tuple."""
    for name in ("n_envs", "n_steps", "batch_size", "n_epochs", "eval_episodes", "atlas_size", "atlas_every"):
        check_int(getattr(cfg, name), name, 1)
    check_int(cfg.eval_every, "eval_every", 0)
    check_int(cfg.near_radius, "near_radius", 0, MAX_NEAR_RADIUS)
    check_int(cfg.view_radius, "view_radius", 0)
    check_int(cfg.hidden, "hidden", 1, MAX_LAYER_SIZE)
    check_cell(cfg.cell)
    for name in ("hint", "memory", "trail", "recurrent"):
        if not isinstance(getattr(cfg, name), bool):
            raise ValueError(f"{name}: must be True or False, got {shown(getattr(cfg, name))}")
    if cfg.threads is not None:
        check_int(cfg.threads, "threads", 1)
    for name in ("gamma", "gae_lambda"):
        check_real(getattr(cfg, name), name, 0, 1)
    for name in ("learning_rate", "clip_range", "max_grad_norm"):
        if check_real(getattr(cfg, name), name, 0) == 0:
            raise ValueError(f"{name}: must be a finite number > 0, got 0")
    for name in ("ent_coef", "vf_coef", "blocked_cost"):
        check_real(getattr(cfg, name), name, 0)
    arch = tuple(cfg.net_arch)
    for h in arch:
        check_int(h, "net_arch", 1, MAX_LAYER_SIZE)
    if len(arch) > MAX_LAYERS:
        raise ValueError(f"net_arch: at most {MAX_LAYERS} hidden layers, got {len(arch)}")
    if cfg.start not in start_choices:
        raise ValueError(f"start: must be one of {', '.join(map(repr, start_choices))}, got {cfg.start!r}")
    imitate = getattr(cfg, "imitate", None)
    if imitate is not None and imitate not in imitate_choices:
        raise ValueError(f"imitate: must be None or one of {', '.join(map(repr, imitate_choices))}, got {shown(imitate)}")
    if imitate is not None and (cfg.trail or cfg.recurrent):
        raise ValueError(f"imitate: learns a feed-forward policy of its window, hint, last action and neighbours' "
                         f"intents; got {'trail' if cfg.trail else 'recurrent'}=True")
    return arch


# ---------------------------------------------------------------------------- imitating a planner
def check_cell(cell: Any) -> None:
    """``cell``: a recurrent net's cell, one of ``CELL_CHOICES``."""
    if cell not in CELL_CHOICES:
        raise ValueError(f"cell: the recurrent cell, one of {', '.join(map(repr, CELL_CHOICES))}, got {shown(cell)}")


def check_imitation(family: Any, n_robots: int, env_kwargs: dict[str, Any]) -> None:
    """One line naming the setting if a run on ``family`` (``ppo.window.Family``) cannot imitate PIBT, before any work."""
    if family.goals != "own" or n_robots < 2:
        raise ValueError("imitate: PIBT plans for a crowd of own goals: goals='own' and 2 or more robots")
    if family.lifelong or not family.stay:
        raise ValueError("imitate: PIBT's robots stay on their targets: finished='stay', not lifelong")
    if env_kwargs.get("collisions", "block") != "soft":
        raise ValueError("imitate: PIBT's moves are learnt under POGEMA's rule: collisions='soft'")


# ---------------------------------------------------------------------------- a run that diverged
class TrainingDivergedError(ValueError):
    """The loss or the weights became NaN or infinite (a learning rate too large, most often)."""


def weights_finite(params: Any) -> bool:
    """Whether every weight of ``params`` (torch tensors) is a finite number: one norm per parameter."""
    torch = torch_module()
    return bool(torch.isfinite(torch.stack(torch._foreach_norm(list(params)))).all())


def check_finite(params: list[Any], timesteps: int, cfg: Any) -> None:
    """Raise ``TrainingDivergedError`` if any weight is not finite (a NaN or infinite loss or gradient
    makes the weights so at the optimizer's step); cheap once per update."""
    if not weights_finite(params):
        raise TrainingDivergedError(f"learning_rate: training diverged within {timesteps:,} timesteps (the loss or the weights "
                                    f"are no longer finite numbers) at learning_rate {cfg.learning_rate:g}; try a smaller one")


def check_finite_sb3(agent: Any, lr: float | None) -> None:
    """An SB3 model whose weights are no longer finite numbers is refused before it is evaluated or saved
    (``lr``: the CLI's ``--lr``, None when not given)."""
    if not weights_finite(agent.policy.parameters()):
        flag = f"--lr {lr:g}" if lr is not None else "--lr"
        raise ValueError(f"{flag}: training diverged (the weights are no longer finite numbers); nothing was saved: "
                         "try a smaller --lr")


# ---------------------------------------------------------------------------- a saved policy's fields
def check_fields(data: dict[str, Any], version: int, config_type: type) -> None:
    """Each field of saved data but the weights as ``save_policy`` writes it (its ``ValueError`` names the
    field); ``config_type``: ``PPOConfig``, which checks the saved settings (``check_config``)."""
    expected = FIELDS + (("observation",) if version >= 3 else ())
    optional = ("env",) if version >= 4 else ()  # the env settings trained under (own goals, collisions, lifelong)
    missing, unknown = [k for k in expected if k not in data], [k for k in data if k not in expected + optional]
    if missing or unknown:
        raise ValueError(f"{'missing' if missing else 'unknown'} field {shown((missing or unknown)[0])}")
    w, h, n = (_int_field(data, k, 1, hi) for k, hi in (("width", MAX_LEVEL_CELLS), ("height", MAX_LEVEL_CELLS),
                                                         ("n_robots", None)))
    if w * h > MAX_LEVEL_CELLS:
        raise ValueError(f"width, height: a level has at most {MAX_LEVEL_CELLS:,} cells, got {w}x{h}")
    _int_field(data, "timesteps", 0, None)
    for key in ("level", "level_name"):
        if not isinstance(data[key], str) or len(data[key]) > MAX_LEVEL_TEXT_CHARS:
            raise ValueError(f"{key}: must be a text, got {shown(data[key])}")
    if version == 3 and data["observation"] != TRAINED_ON:
        raise ValueError(f"observation: this version reads policies of {TRAINED_ON}, got {shown(data['observation'])}")
    if version >= 4:
        check_observation_form(data["observation"])
        check_env_settings(data.get("env", {}))
    arch = data["net_arch"]
    if (not isinstance(arch, (list, tuple)) or len(arch) > MAX_LAYERS
            or not all(type(x) is int and 1 <= x <= MAX_LAYER_SIZE for x in arch)):
        raise ValueError(f"net_arch: must be a list of up to {MAX_LAYERS} layer sizes in 1..{MAX_LAYER_SIZE:,}, "
                         f"got {shown(arch)}")
    config = data["config"]
    if not isinstance(config, dict) or not set(config) <= {f.name for f in fields(config_type)}:
        raise ValueError(f"config: must be the PPO settings the policy was trained with, got {shown(config)}")
    if n > 1 and "near_radius" not in config:
        raise ValueError("config: a race policy's settings name its near_radius")
    try:
        config_type(**{k: tuple(v) if k == "net_arch" and isinstance(v, list) else v for k, v in config.items()})
    except (TypeError, ValueError) as err:
        raise ValueError(f"config: {err}") from None


def check_observation_form(form: Any) -> None:
    """A version-4 file's ``observation``: the global rows (``GLOBAL_FORM``) or a local window with its
    ``view_radius`` and ``hint``."""
    ok = form == GLOBAL_FORM or (
        isinstance(form, dict) and tuple(form) in (LOCAL_FORM_KEYS, LOCAL_FORM_KEYS + ("goals",))
        and form.get("goals", "own") == "own" and form["observe"] == "local"
        and form["obs_encoding"] == "multidiscrete" and type(form["view_radius"]) is int and form["view_radius"] >= 0
        and isinstance(form["hint"], bool))
    if not ok:
        raise ValueError(f"observation: this version reads policies of {GLOBAL_FORM} or {{'observe': 'local', "
                         f"'obs_encoding': 'multidiscrete', 'view_radius': R, 'hint': True/False[, 'goals': 'own']}}, "
                         f"got {shown(form)}")


def check_env_settings(env: Any) -> None:
    """A version-4 file's ``env``: the goals mode, collision rule, lifelong flag and finished rule it was trained
    under (files from before ``finished`` existed leave it out: ``"remove"``)."""
    from ..core.goals import GOAL_MODES
    from ..core.rules import COLLISION_MODES

    ok = isinstance(env, dict) and set(env) <= set(ENV_SETTINGS) and (
        env.get("goals", "exit") in GOAL_MODES and env.get("collisions", "block") in COLLISION_MODES
        and isinstance(env.get("lifelong", False), bool) and env.get("finished", "remove") in FINISHED_RULES)
    if not ok:
        raise ValueError(f"env: the settings trained under, {{'goals': one of {GOAL_MODES}, 'collisions': one of "
                         f"{COLLISION_MODES}, 'lifelong': True/False, 'finished': one of {FINISHED_RULES}}}, "
                         f"got {shown(env)}")


def _int_field(data: dict[str, Any], key: str, lo: int, hi: int | None) -> int:
    value = data[key]
    if type(value) is not int or value < lo or (hi is not None and value > hi):
        raise ValueError(f"{key}: must be an integer >= {lo}{'' if hi is None else f' and <= {hi:,}'}, got {shown(value)}")
    return value


def check_weights(state: Any, shapes: dict[str, tuple[int, ...]], net_arch: tuple[int, ...]) -> None:
    """The saved state dict holds exactly the tensors of ``shapes`` (``ppo.net.weight_shapes``), float32 and
    finite, with the first layer's padding row zero."""
    torch = torch_module()
    if not isinstance(state, dict) or set(state) != set(shapes):
        got = sorted(state)[:8] if isinstance(state, dict) else type(state).__name__
        raise ValueError(f"state_dict: must hold the tensors {sorted(shapes)} of layers {list(net_arch)}, got {shown(got, 200)}")
    for name, shape in shapes.items():
        t = state[name]
        if not isinstance(t, torch.Tensor) or t.dtype != torch.float32 or tuple(t.shape) != shape:
            got = f"{t.dtype} {tuple(t.shape)}" if isinstance(t, torch.Tensor) else type(t).__name__
            raise ValueError(f"state_dict: {name} must be a float32 tensor of shape {shape}, got {got}")
        if not bool(torch.isfinite(t).all()):
            raise ValueError(f"state_dict: {name} holds non-finite weights (NaN or infinity: a training that diverged)")
    firsts = [name for name in shapes if name.split(".")[-1] == "first"]  # actor's and critic's, or a recurrent net's one
    n_in = shapes[firsts[0]][0] - 1  # the padding row
    if any(bool((state[name][n_in] != 0).any()) for name in firsts):
        raise ValueError("state_dict: the padding row of the first layer must be zero")
