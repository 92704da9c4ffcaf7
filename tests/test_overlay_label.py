"""``set_overlay(label=...)`` on the envs: the colour bar's own name (e.g. "gap"), kept until changed."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv, race_v0


def _values(level) -> np.ndarray:
    return np.arange(level.height * level.width, dtype=float).reshape(level.height, level.width) / 10


def test_label_names_the_colour_bar_and_is_kept():
    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=32)
    env.reset(seed=0)
    env.set_overlay(values=_values(env.level))
    default = env.render()
    env.set_overlay(label="gap")
    assert env.overlay.label == "gap"
    gap = env.render()
    grid = env.level.height * 32
    assert (gap[:grid] == default[:grid]).all()  # the grid is the same
    assert (gap[grid:] != default[grid:]).any()  # the colour bar's name is not
    env.set_overlay(panel="a line")
    assert env.overlay.label == "gap"  # parts not given are kept
    env.clear_overlay()
    assert env.overlay.label == "" and env.overlay.values is None


def test_race_takes_a_label():
    env = race_v0.parallel_env(level="race-4", n_robots=2, render_mode="rgb_array", cell_size=32)
    env.reset(seed=0)
    u = env.unwrapped
    u.set_overlay(values=_values(u.level), label="steps to go")
    assert u.overlay.label == "steps to go"
    assert env.render().shape[0] > u.level.height * 32


def test_a_bad_label_is_refused_and_changes_nothing():
    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=32)
    env.reset(seed=0)
    env.set_overlay(values=_values(env.level), label="gap")
    with pytest.raises(ValueError, match="^label: "):
        env.set_overlay(values=None, label="two\nlines")
    assert env.overlay.label == "gap" and env.overlay.values is not None


@pytest.mark.parametrize(("lo", "hi", "digits"), [(1, 2, 0), (1, 3, 0), (0, 1, 0), (0.5, 0.8, 1), (1, 59, 0)])
def test_the_colour_bars_ticks_never_print_alike(lo, hi, digits):
    """Visits 1 to 2, written as whole numbers, were ticked 1, 1.2, ... and printed "1 1 1 2 2 2"."""
    from babyrobot_marl.render.overlay import Scale
    from babyrobot_marl.render.panel import ticks

    scale = Scale(float(lo), float(hi), "visits", digits)
    printed = [scale.format(v) for v in ticks(lo, hi, 6, digits)]
    assert len(printed) == len(set(printed)) >= 2 and printed[0] == scale.format(lo) and printed[-1] == scale.format(hi)
