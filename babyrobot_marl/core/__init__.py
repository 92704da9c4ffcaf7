"""The shared grid core: levels, rules, compiled tables, the step. Only numpy; no env APIs."""

from .actions import DELTAS, N_ACTIONS, Action
from .engine import OUTCOMES, move, move_array
from .level import Cell, Edge, Level
from .model import frozenlake_P, outcomes, sparse_arrays, transition_arrays
from .rules import COLLISION_MODES, Rules
from .table import Table, compile_level

__all__ = [
    "Action",
    "COLLISION_MODES",
    "Cell",
    "DELTAS",
    "Edge",
    "Level",
    "N_ACTIONS",
    "OUTCOMES",
    "Rules",
    "Table",
    "compile_level",
    "frozenlake_P",
    "move",
    "move_array",
    "outcomes",
    "sparse_arrays",
    "transition_arrays",
]
