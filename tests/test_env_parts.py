"""Issue 25: envs are composed, not stacked. An env holds its parts (the level picker, the drawing)
as objects it calls; no class it inherits from the package carries state (no ``__init__``, no
``self.x = ...``), as gymnax's thin env classes call pure functions."""

from __future__ import annotations

import ast
import copy
import inspect
import pickle
import textwrap

import pytest

from babyrobot_marl.envs.drawing import EnvDrawing, OverlayMethods
from babyrobot_marl.envs.race import RaceEnv
from babyrobot_marl.envs.race_gym import BabyRobotRaceEnv
from babyrobot_marl.envs.single import BabyRobotEnv
from babyrobot_marl.levels.sources import LevelPicker


def stateful_lines(cls: type) -> list[str]:
    """What makes ``cls`` carry state: its own ``__init__``, and every ``self.<name> = ...`` in its body."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and node.name == "__init__":
            found.append(f"{cls.__name__}.__init__")
        if isinstance(node, ast.Assign):
            targets = node.targets
        else:
            targets = [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign)) else []
        for t in targets:
            for sub in ast.walk(t):
                if isinstance(sub, ast.Attribute) and isinstance(sub.value, ast.Name) and sub.value.id == "self":
                    found.append(f"{cls.__name__}: self.{sub.attr} = ...")
    return found


@pytest.mark.parametrize("env_class", [BabyRobotEnv, RaceEnv, BabyRobotRaceEnv])
def test_no_package_class_an_env_inherits_from_carries_state(env_class):
    bases = [c for c in env_class.__mro__[1:] if c.__module__.startswith("babyrobot_marl")]
    assert all(not stateful_lines(c) for c in bases), {c.__name__: stateful_lines(c) for c in bases}
    assert stateful_lines(env_class)  # the check sees state where there is some: the env's own


def test_the_check_would_see_a_stateful_mixin():
    class Stateful:
        def remember(self) -> None:
            self.seen = 1

    assert stateful_lines(Stateful) == ["Stateful: self.seen = ..."]


def test_the_race_holds_its_parts_and_its_overlay_methods_call_them():
    env = RaceEnv(level="maze-8x8-*", n_robots=2, start="random")
    assert isinstance(env.drawing, EnvDrawing) and isinstance(env.levels, LevelPicker)
    assert not env.levels.fixed and env.level is env.levels.first
    assert isinstance(env, OverlayMethods) and env.overlay is env.drawing.overlay and env.canvas is None
    env.set_overlay(panel="hello")
    assert env.drawing.overlay.panel == ("hello",)
    env.reset(seed=3)
    drawn = env.level
    env.reset(seed=3)
    assert env.level == drawn and env.drawing.level is env.level  # the drawing follows the level drawn


def test_single_env_holds_its_drawing_and_copies_draw_on_a_new_canvas():
    env = BabyRobotEnv(level="walls", render_mode="rgb_array")
    assert isinstance(env.drawing, EnvDrawing) and env.rgb_renderer is env.drawing.renderer
    env.drawing.canvas = object()  # stands in for a live widget, which lives in one kernel
    assert copy.deepcopy(env).canvas is None and pickle.loads(pickle.dumps(env.drawing)).canvas is None


def test_race_copies_taken_before_the_first_reset_draw_different_races():
    env = RaceEnv(level="race-2", n_robots=2, start="random")
    a, b = copy.deepcopy(env), copy.deepcopy(env)
    assert a._np_random is None and b._np_random is None
    a.reset()
    b.reset()  # each made its own generator from fresh entropy at its first use
    assert a.np_random.bit_generator.state != b.np_random.bit_generator.state
