"""PPO stepped on the batch engine's arrays: one robot, or a race with one policy shared by every robot.

CleanRL's rule, split by concept: the modules read in this order, ``config`` (``PPOConfig``),
``inputs`` (observation encoding), ``net`` (the actor-critic network), ``sampler`` (the policy per
input during a rollout), ``update`` (advantages and the PPO gradient), ``result``, then ``loop``:
``train_ppo``, one loop read top to bottom: rollout, advantages, update, evaluation. The algorithm
and its knobs are Stable-Baselines3's PPO (``n_steps`` per env, ``batch_size``, ``n_epochs``,
``gamma``, ``gae_lambda``, ``clip_range``, ``ent_coef``, ``vf_coef``, ``max_grad_norm``,
``learning_rate``, ``net_arch``; advantages normalised per minibatch, truncated episodes
bootstrapped from their last observation, Adam with ``eps=1e-5``, orthogonal initialisation).
What is different is where the time goes:

* The environment is ``core.batch.BatchRace``: a step of every env and robot is a few numpy
  calls, with no Gymnasium, SB3 or per-env Python in the loop.
* Inputs repeat, so the net runs once per distinct input, not once per robot-step. A robot's
  input is the one-hot of its cell and, in a race, one bit for each cell within ``near_radius``
  steps (default 1: the four cells next to it) saying whether a racing robot stands there
  (``Inputs``: one integer key per robot-step). Robots further off cannot touch its next step;
  leaving them out gives a few hundred distinct inputs per rollout of 65,536 robot-steps on
  race-4 (a policy that reads every robot's cell sees ~88% distinct ones: as slow as SB3), and a
  policy that races with any number of robots.
* During a rollout (fixed weights) the policy is a table over the inputs: one forward pass per
  rollout (or per step, for the distinct inputs of that step, when the possible inputs are many).
  In an update, the net runs once per distinct input of the rollout, and the samples' gradients
  are summed per (input, action, sign of the advantage) before they reach the net: a sample's
  probability ratio depends only on its input and action.
* The first layer, a ``Linear`` on the one-hot, is a look-up of weight rows: the same function
  and gradient as a dense layer, without building the one-hot of every sample.
* Level families (``train_ppo("maze:8..16", config=PPOConfig(hint=True))``): the net reads the local
  window and the goal hint instead of the cell (``window``: an atlas of mazes stepped as one level);
  what a robot remembers rides along: its last action (``memory``), its trail (``trail``: the order in
  which it stood on the cells next to it) or a GRU's state (``recurrent``).
* A race robot that has finished is parked until its race ends (``finished="freeze"``): its
  parked steps are no decisions and are left out of the update (SB3 through SuperSuit trains on
  them, reward 0).

Determinism: ``torch.manual_seed(seed)``, numpy generators seeded from ``seed`` (env ``i``'s first
episode seeded ``seed + i``, later ones drawn by ``BatchRace.reset_drawn`` from one generator) and a
fixed number of torch threads (``threads``, default 1) during training: torch's CPU kernels used
here are deterministic at a fixed thread count, so the same seed on the same machine gives the same
learning curve. One thread also keeps training from stalling when the machine is busy (torch's
OpenMP threads spin and wait on each other when other processes hold the cores); ``threads=None``
leaves torch's own setting.
"""

from ..checks import MAX_NEAR_RADIUS, TrainingDivergedError, check_finite
from .config import START_CHOICES, PPOConfig, known_settings
from .inputs import Inputs, make_inputs, near_offsets
from .loop import make_batch, torch_threads, train_ppo
from .net import DENSE_LIMIT, dense_input, log_softmax, make_net, weight_shapes
from .result import EvalPoint, TrainResult
from .sampler import TABLE_LIMIT, PerKey, Sampler, distinct_rows
from .update import Samples, clip_grad_norm, gae, grads_of, ppo_gradients
from .window import Atlas, Family, WindowForm, play_atlas, stack_levels

__all__ = [
    "DENSE_LIMIT", "MAX_NEAR_RADIUS", "START_CHOICES", "TABLE_LIMIT", "Atlas", "EvalPoint", "Family", "Inputs",
    "PPOConfig", "PerKey", "WindowForm",
    "Sampler", "Samples", "TrainResult", "TrainingDivergedError", "check_finite", "clip_grad_norm", "dense_input",
    "distinct_rows", "gae", "grads_of", "known_settings", "log_softmax", "make_batch", "make_inputs", "make_net",
    "near_offsets", "play_atlas", "ppo_gradients", "stack_levels", "torch_threads", "train_ppo", "weight_shapes",
]
