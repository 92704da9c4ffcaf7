"""PPO's settings: ``PPOConfig``, Stable-Baselines3's knobs and this trainer's own, each checked when it is made."""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from typing import Any

from ..checks import check_config

START_CHOICES = ("random", "level")
IMITATE_CHOICES = ("pibt",)  # the planners a crowd can learn from (``imitation.py``)


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
    Level families (``train_ppo(level="maze:8..16")``): the net reads the local window of
    ``view_radius`` and, with ``hint``, the goal hint (``window.WindowForm``); with ``memory``, also
    the robot's own last action (a memoryless policy loops in a maze: it cannot tell the corridor it
    came from); with ``trail``, the order in which it stood on the cells next to it (``trail.py``); with
    ``recurrent``, a recurrent cell of ``hidden`` units between the input layers and the heads (the robot
    remembers its episode: ``recurrent.py``): ``cell`` ``"gru"``, or ``"mingru"``, whose gates read the input
    alone, so a robot-step costs a few element-wise operations instead of a GRU's products (``mingru.py``);
    the envs step an atlas of ``atlas_size`` mazes, drawn anew
    every ``atlas_every`` rollouts.
    ``imitate``: ``"pibt"`` learns a crowd of own goals by imitating the planner PIBT instead of by PPO
    (DAgger, ``imitation.py``); its robots also read what their neighbours intend and which go first
    (``intents.py``), and decide in turns, each told what the near robots before it chose (``turns.py``).
    ``eval_every``: timesteps between evaluations (0: only at the end).
    ``blocked_cost``: a race robot's training reward loses this much on a step another robot stops
    its move (``BatchRace.step``'s ``blocked``): each robot's return counts only its own steps, so
    pressing into a robot that stays or contesting a cell otherwise costs it no more than waiting;
    a crowd jams on it. Training only: the figures and returns reported are the env's.
    ``babyrobot-marl train`` trains a crowd (several robots under ``block`` or ``bounce``) with
    ``near_radius=2`` (no wider than its window) and ``blocked_cost=0.5`` unless given (``crowd_defaults``); these
    fields' own defaults stay those of one robot.
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
    view_radius: int = 2
    hint: bool = False
    memory: bool = False
    trail: bool = False
    recurrent: bool = False
    hidden: int = 32
    cell: str = "gru"
    atlas_size: int = 64
    atlas_every: int = 16
    blocked_cost: float = 0.0
    imitate: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "net_arch", check_config(self, START_CHOICES, IMITATE_CHOICES))

    def replace(self, **changes: Any) -> PPOConfig:
        return PPOConfig(**{**asdict(self), **known_settings(changes, "replace")})


def known_settings(changes: dict[str, Any], caller: str) -> dict[str, Any]:
    """``changes`` if every key is a ``PPOConfig`` field, else Python's own ``TypeError`` and the known names."""
    known = {f.name for f in fields(PPOConfig)}
    unknown = sorted(set(changes) - known)
    if unknown:
        names = ", ".join(sorted(known))
        raise TypeError(f"{caller}() got an unexpected keyword argument {unknown[0]!r}; PPO settings are: {names}")
    return changes
