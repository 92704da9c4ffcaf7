"""Planning: the exact MDP of one robot and dynamic programming on it.

>>> from babyrobot_marl.planning import model, value_iteration
>>> sol = value_iteration(model("walls"))
>>> sol.value_grid, sol.policy_grid, sol.best_actions  # draw with env.unwrapped.set_overlay(...)

``model`` reads the same compiled tables the simulator steps with; ``policy_evaluation``,
``policy_iteration`` and ``value_iteration`` are vectorised numpy over its sparse arrays;
``optimal_actions`` is the race envs' goal hint (``goal_actions`` with own goals); ``PIBT`` plans a
crowd with targets of its own one step at a time, without collisions; ``LaCAM`` searches over PIBT's
steps for a plan of the whole episode.
"""

from .dp import Solution, policy_evaluation, policy_iteration, q_values, value_iteration
from .hint import goal_actions, optimal_actions
from .lacam import LaCAM
from .mdp import Model, model
from .pibt import PIBT
from .text import policy_text, value_text

__all__ = [
    "LaCAM",
    "Model",
    "PIBT",
    "Solution",
    "goal_actions",
    "model",
    "optimal_actions",
    "policy_evaluation",
    "policy_iteration",
    "policy_text",
    "q_values",
    "value_iteration",
    "value_text",
]
