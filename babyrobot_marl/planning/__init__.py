"""Planning on the model of one robot: ``p(s', r | s, a)`` from the simulator's own tables,
policy evaluation, policy iteration and value iteration (vectorised numpy), tabular learning.

    from babyrobot_marl.planning import model, value_iteration
    sol = value_iteration(model("maze-8x8"), gamma=1.0)
    sol.value_grid, sol.policy_grid, sol.best_actions   # draw them: env.unwrapped.set_overlay(...)
"""

from .dp import Solution, policy_evaluation, policy_iteration, q_from_values, value_iteration
from .model import Model, from_table, model
from .tabular import q_learning, sarsa

__all__ = [
    "Model",
    "Solution",
    "from_table",
    "model",
    "policy_evaluation",
    "policy_iteration",
    "q_from_values",
    "q_learning",
    "sarsa",
    "value_iteration",
]
