"""One rule for integer arguments everywhere (``checks.check_int``): Python and numpy integers are
accepted, bools and floats (even ``3.0``) rejected with a ``ValueError`` naming the argument."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import Level, compile_level, levels, policies
from babyrobot_marl.core.checks import check_int, check_real, real_array
from babyrobot_marl.envs.race import RaceEnv
from babyrobot_marl.envs.single import BabyRobotEnv

NUMPY_INTS = [np.int8, np.int32, np.int64, np.uint8, np.uint64, np.array]  # np.array(n): a 0-d integer array
NOT_INTS = {  # each made from the number the call site takes, so only the type is wrong
    "True": lambda n: True,
    "False": lambda n: False,
    "np.bool_": lambda n: np.bool_(True),
    "float": float,
    "np.float64": np.float64,
    "str": str,
    "complex": complex,
    "list": lambda n: [n],
}


def sites() -> dict:
    """Each call site of the rule: (the argument's name, a number it takes, a call with that argument)."""
    table = compile_level(levels.get("default"))
    return {
        "Level(width)": ("width", 3, lambda v: Level(width=v, height=1, exits=[(0, 0)])),
        "Level(height)": ("height", 3, lambda v: Level(width=1, height=v, exits=[(0, 0)])),
        "maze(width)": ("width", 3, lambda v: levels.maze(v, 3)),
        "maze(seed)": ("seed", 3, lambda v: levels.maze(3, 3, seed=v)),
        "policies.make(seed)": ("seed", 3, lambda v: policies.make("random", table, seed=v)),
        "max_steps": ("max_steps", 3, lambda v: BabyRobotEnv(max_steps=v)),
        "n_robots": ("n_robots", 3, lambda v: RaceEnv(level="race-4", n_robots=v)),
        "max_cycles": ("max_cycles", 3, lambda v: RaceEnv(level="race-4", max_cycles=v)),
        "cell_size": ("cell_size", 16, lambda v: BabyRobotEnv(cell_size=v)),
        "animation_frames": ("animation_frames", 3, lambda v: BabyRobotEnv(animation_frames=v)),
    }


SITES = list(sites())


@pytest.mark.parametrize("kind", NUMPY_INTS, ids=lambda k: k.__name__)
@pytest.mark.parametrize("site", SITES)
def test_numpy_integers_are_accepted_wherever_an_integer_is(site, kind):
    _, number, call = sites()[site]
    call(kind(number))


@pytest.mark.parametrize("kind", NOT_INTS.values(), ids=NOT_INTS.keys())
@pytest.mark.parametrize("site", SITES)
def test_bools_floats_and_strings_are_refused_naming_the_argument(site, kind):
    name, number, call = sites()[site]
    with pytest.raises(ValueError, match=name):
        call(kind(number))


def test_check_int_returns_a_python_int_within_bounds():
    assert type(check_int(np.int64(5), "n", 1, 9)) is int
    assert check_int(2**70, "n") == 2**70
    with pytest.raises(ValueError, match=r"^n: must be an integer in 1\.\.9, got 10$"):
        check_int(10, "n", 1, 9)
    with pytest.raises(ValueError, match=r"^n: must be an integer >= 0, got -1$"):
        check_int(-1, "n", lo=0)


def test_check_real_refuses_values_no_float_holds_without_overflow_error():
    assert check_real(np.float32(0.5), "p") == 0.5 and check_real(10**300, "r") == 1e300
    for bad in (10**400, float("inf"), float("nan"), True, 1j, "1"):
        with pytest.raises(ValueError, match="^r: must be a finite number"):
            check_real(bad, "r")


def test_a_huge_integer_in_an_error_message_is_shortened():
    with pytest.raises(ValueError) as info:
        check_int(10**5000, "n", hi=5)
    assert len(str(info.value)) < 200


@pytest.mark.parametrize("cell", [(1.0, 0), (np.float64(1), 0), (True, 0), ("1", 0), (1, None)], ids=repr)
def test_a_cell_is_a_pair_of_integers_by_the_same_rule(cell):
    with pytest.raises(ValueError, match="starts: .* is not a cell"):
        Level(width=3, height=1, starts=[cell], exits=[(2, 0)])
    env = BabyRobotEnv(level="walls")
    with pytest.raises(ValueError, match="start"):
        env.reset(options={"start": cell})


def test_a_cell_of_numpy_integers_is_a_cell():
    level = Level(width=3, height=1, starts=[np.array([1, 0])], exits=[(np.int64(2), np.uint8(0))])
    assert level.starts == ((1, 0),) and type(level.starts[0][0]) is int


def test_real_array_takes_ints_and_floats_and_refuses_complex_strings_and_bools():
    assert real_array([[1, 2.5]], "values").dtype == np.float64
    assert real_array(np.arange(3, dtype=np.int8), "values").tolist() == [0.0, 1.0, 2.0]
    for bad in ([1j, 2], ["1.5", "2"], [True, False], [[1, 2], [3]], None):
        with pytest.raises(ValueError, match="^values: expected"):
            real_array(bad, "values")
