"""``babyrobot-marl train``'s arguments: its flags, their types and help, and the PPO knobs each maps to."""

from __future__ import annotations

import argparse

from ..core.goals import GOAL_MODES
from ..core.rules import COLLISION_MODES
from ..training.checks import FINISHED_RULES, MAX_NEAR_RADIUS
from ..training.crowd import CROWD_DEFAULTS, said
from .checks import (
    SEED_HELP,
    int_in,
    layer_sizes,
    non_negative_float,
    non_negative_int,
    output_path,
    policy_file,
    positive_float,
    positive_int,
    seed_int,
    unit_real,
)
from .common import add_level_arg, add_memory_args

BACKENDS = ("fast", "sb3")
# PPO knobs: CLI flag -> (PPOConfig / SB3 PPO keyword, type)
KNOBS = {
    "n_envs": ("n_envs", positive_int),
    "n_steps": ("n_steps", positive_int),
    "batch_size": ("batch_size", positive_int),
    "n_epochs": ("n_epochs", positive_int),
    "lr": ("learning_rate", positive_float),
    "gamma": ("gamma", unit_real),
    "gae_lambda": ("gae_lambda", unit_real),
    "clip_range": ("clip_range", positive_float),
    "ent_coef": ("ent_coef", non_negative_float),
}
# the backends' own rollout sizes (PPOConfig; SB3: training.single.ALGO_KWARGS, training.race)
FAST_ROLLOUT, SB3_ROLLOUT, SB3_RACE_ROLLOUT = (1024, 16), (8, 128), (4, 256)  # (n_envs, n_steps)



def add_train_arguments(p: argparse.ArgumentParser) -> None:
    """Every flag of ``train`` on its parser ``p``."""
    add_level_arg(p, default="maze-8x8")
    p.add_argument("--robots", type=positive_int, default=1, metavar="N", help="1: single robot; more: a race (default: 1)")
    p.add_argument("--steps", type=positive_int, default=None, metavar="N",
                   help="training timesteps (one per robot per step); or --seconds")
    p.add_argument("--seconds", type=positive_float, default=None, metavar="SECONDS",
                   help="fast backend: train for SECONDS of wall-clock time (rollouts and updates) instead of --steps")
    p.add_argument("--observe", choices=("global", "local"), default="global",
                   help="fast backend: what the net reads; 'local' (needed for a level family, --level maze:A..B): the "
                   "local window of --view-radius, which any maze shows alike (default: global, the robot's cell)")
    p.add_argument("--view-radius", type=non_negative_int, default=None, metavar="N",
                   help="--observe local: the window's radius, as race_v0's view_radius (default: 2)")
    p.add_argument("--hint", action="store_true", help="--observe local: the net also reads the goal hint (race_v0's hint=True)")
    add_memory_args(p)
    p.add_argument("--max-cycles", type=positive_int, default=None, metavar="N",
                   help="a race's training and evaluation episodes end after N steps (default: the race's own limit)")
    p.add_argument("--imitate", choices=("pibt",), default=None,
                   help="--observe local, a crowd of --goals own under --collisions soft and --finished stay: it learns "
                   "what the planner PIBT does (DAgger) instead of by PPO, each robot also reading what the robots near it "
                   "intend")
    p.add_argument("--collisions", choices=COLLISION_MODES, default=None,
                   help="fast backend, race: the collision rule; soft: POGEMA's (default: the env's, block)")
    p.add_argument("--goals", choices=GOAL_MODES, default="exit",
                   help="exit: the robots race to the level's exits (default); own: each robot has its own target cell, "
                   "drawn at each episode's start (POGEMA's task; with --observe local: the net reads its target channel "
                   "and, with --hint, the hint toward its own target); saved with the policy")
    p.add_argument("--lifelong", action="store_true",
                   help="with --goals own: a robot on its target gets a new one and keeps going until the step limit")
    p.add_argument("--finished", choices=FINISHED_RULES, default="remove",
                   help="with --goals own: remove (default): a robot leaves the board at its target; stay: it stays there, "
                   "racing on and blocking, and an episode ends early only when every robot stands on its target "
                   "(POGEMA's on_target='nothing', the rule of its published maze runs); saved with the policy")
    p.add_argument("--backend", choices=BACKENDS, default="fast",
                   help="fast: PPO on the batch engine (default); sb3: Stable-Baselines3")
    p.add_argument("--algo", choices=("ppo", "dqn"), default="ppo", help="dqn: single robot, --backend sb3 only (default: ppo)")
    p.add_argument("--seed", type=seed_int, default=0, metavar="N",
                   help=f"seed of training and evaluation, {SEED_HELP} (default: 0)")
    p.add_argument("--episodes", type=positive_int, default=None, metavar="N",
                   help="final evaluation: episodes (one robot, default 20) or races per opponent (default 100)")
    p.add_argument("--save", type=output_path, metavar="PATH",
                   help="save the trained policy to exactly PATH (fast: a torch file; sb3: SB3's zip); its folder must exist")
    p.add_argument("--load", type=policy_file, metavar="PATH", help="fast backend: start from a policy saved by --save")
    p.add_argument("--gif", type=output_path, metavar="PATH", help="single robot: write a GIF of the learnt policy here")
    p.add_argument("--curve", type=output_path, metavar="PATH", help="write the learning curve here as a PNG")
    p.add_argument("--threads", type=non_negative_int, default=1, metavar="N",
                   help="torch threads while training (default: 1, which a busy machine slows in proportion instead of "
                   "stalling; 0: torch's own setting)")
    p.add_argument("--no-progress", action="store_true", help="neither a progress bar nor evaluation lines")
    knobs = p.add_argument_group("PPO settings (default: the backend's)")
    for flag, (name, kind) in KNOBS.items():
        knobs.add_argument("--" + flag.replace("_", "-"), type=kind, default=None, metavar="X", help=f"SB3's {name}")
    knobs.add_argument("--net-arch", type=layer_sizes, default=None, metavar="H1,H2", help="hidden layers (default: 64,64)")
    knobs.add_argument("--eval-every", type=positive_int, default=None, metavar="N", help="timesteps between evaluations")
    knobs.add_argument("--near-radius", type=int_in(0, MAX_NEAR_RADIUS), default=None, metavar="N",
                       help="fast backend, race: a robot sees the robots within N steps of it, 0..4 (default: 1; "
                       f"{CROWD_DEFAULTS['near_radius']} for a crowd, no wider than --view-radius: see --blocked-cost)")
    knobs.add_argument("--blocked-cost", type=non_negative_float, default=None, metavar="X",
                       help="fast backend, race: a robot's training reward loses X on each step another robot stops its "
                       "move (default: 0; a crowd, 2 or more robots under --collisions block, bounce or soft, trains with the "
                       f"crowd defaults {said(CROWD_DEFAULTS)} unless given, as train's summary line says)")
