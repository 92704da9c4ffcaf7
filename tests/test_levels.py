"""Built-in levels and the maze generator: documented contents, canonical texts, perfect mazes."""

from __future__ import annotations

from collections import deque

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import levels
from babyrobot_marl.core.level import Level

# The table in the docstring of babyrobot_marl.levels: name -> (width, height, number of starts).
DOCUMENTED = {
    "default": (3, 3, 1),
    "walls": (5, 5, 1),
    "puddles": (5, 5, 1),
    "blocked": (5, 5, 1),
    "glass": (5, 5, 1),
    "mixed-8x8": (8, 8, 1),
    "race-2": (5, 5, 2),
    "race-4": (7, 7, 4),
    "race-corridor": (7, 3, 4),
    "maze-8x8": (8, 8, 1),
    "maze-16x16": (16, 16, 1),
}

DESIGN_DEFAULT = """\
+-+-+-+
|S    |
+ + + +
|     |
+ + + +
|    E|
+-+-+-+"""


def edge(a, b):
    return (a, b) if a < b else (b, a)


def open_neighbours(level: Level, cell):
    """Cells one move away with no wall in between (glass counts as open), computed from the level's sets."""
    x, y = cell
    for n in ((x, y - 1), (x + 1, y), (x, y + 1), (x - 1, y)):
        if 0 <= n[0] < level.width and 0 <= n[1] < level.height and n not in level.blocked and edge(cell, n) not in level.walls:
            yield n


def connected_from(level: Level, cell):
    seen, todo = {cell}, deque([cell])
    while todo:
        for n in open_neighbours(level, todo.popleft()):
            if n not in seen:
                seen.add(n)
                todo.append(n)
    return seen


def assert_perfect_maze(level: Level):
    w, h = level.width, level.height
    all_edges = {((x, y), (x + 1, y)) for y in range(h) for x in range(w - 1)} | {
        ((x, y), (x, y + 1)) for y in range(h - 1) for x in range(w)
    }
    assert level.walls <= all_edges
    assert len(all_edges - level.walls) == w * h - 1  # a spanning tree of the grid graph has n - 1 edges ...
    assert len(connected_from(level, (0, 0))) == w * h  # ... and connects every cell
    assert not (level.glass or level.blocked or level.small_puddles or level.large_puddles)
    assert level.starts == ((0, 0),)
    assert level.exits == {(w - 1, h - 1)}


def test_the_documented_levels_are_built_in():
    assert set(DOCUMENTED) <= set(levels.names())
    assert len(levels.names()) == len(set(levels.names()))


@pytest.mark.parametrize("name", levels.names())
def test_every_built_in_level_loads_with_its_name_and_round_trips(name):
    level = levels.get(name)
    assert isinstance(level, Level)
    assert level.name == name
    assert Level.from_ascii(level.to_ascii()) == level
    assert levels.text(name) == level.to_ascii()
    assert Level.from_ascii(levels.text(name)) == level


@pytest.mark.parametrize("name", [n for n in levels.names() if n in levels._TEXTS])
def test_text_levels_write_back_their_canonical_source_text(name):
    assert levels.get(name).to_ascii() == levels._TEXTS[name].strip("\n")


@pytest.mark.parametrize("name", list(DOCUMENTED))
def test_documented_size_and_number_of_starts(name):
    level = levels.get(name)
    assert (level.width, level.height, len(level.starts)) == DOCUMENTED[name]


@pytest.mark.parametrize("name", levels.names())
def test_every_start_of_a_built_in_level_reaches_an_exit(name):
    level = levels.get(name)
    assert level.starts
    for start in level.starts:
        assert connected_from(level, start) & level.exits


def test_default_level_is_the_one_in_design_md():
    assert levels.get("default").to_ascii() == DESIGN_DEFAULT
    assert levels.get("default") == Level.from_ascii(DESIGN_DEFAULT)


@pytest.mark.parametrize(
    ("name", "features"),
    [
        ("walls", ["walls"]),
        ("puddles", ["small_puddles", "large_puddles"]),
        ("blocked", ["blocked"]),
        ("glass", ["glass"]),
        ("mixed-8x8", ["walls", "glass", "small_puddles", "large_puddles", "blocked"]),
    ],
)
def test_each_feature_level_shows_its_feature(name, features):
    level = levels.get(name)
    for feature in features:
        assert getattr(level, feature), f"{name} should have {feature}"


def test_unknown_level_name_is_a_value_error_listing_every_known_name():
    with pytest.raises(ValueError, match="no-such-level") as info:
        levels.get("no-such-level")
    for name in levels.names():
        assert name in str(info.value)


@pytest.mark.parametrize("name", [None, 3, ("default",)])
def test_non_string_level_name_is_a_type_error(name):
    with pytest.raises(TypeError, match="level"):
        levels.get(name)


# --------------------------------------------------------------------------------------- mazes
@pytest.mark.parametrize(("width", "height"), [(1, 2), (2, 1), (2, 2), (5, 3), (3, 7), (8, 8), (16, 16), (31, 9)])
@pytest.mark.parametrize("seed", [0, 1, 12345])
def test_maze_is_perfect(width, height, seed):
    level = levels.maze(width, height, seed)
    assert (level.width, level.height) == (width, height)
    assert_perfect_maze(level)


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 12), st.integers(1, 12), st.integers(0, 2**32 - 1))
def test_random_mazes_are_perfect_and_round_trip(width, height, seed):
    if width * height < 2:
        width = 2
    level = levels.maze(width, height, seed)
    assert_perfect_maze(level)
    assert Level.from_ascii(level.to_ascii()) == level


def test_maze_is_a_function_of_its_seed():
    assert levels.maze(9, 6, seed=4) == levels.maze(9, 6, seed=4)
    assert len({levels.maze(9, 6, seed=s) for s in range(8)}) > 1


def test_maze_names_build_the_seeded_maze():
    assert levels.get("maze-8x8") == levels.maze(8, 8, 0)
    assert levels.get("maze-16x16") == levels.maze(16, 16, 0)
    assert levels.get("maze-5x7-s3") == levels.maze(5, 7, 3)
    assert levels.get("maze-5x7-s3").name == "maze-5x7-s3"
    assert (levels.get("maze-11x4").width, levels.get("maze-11x4").height) == (11, 4)


@pytest.mark.parametrize(
    ("width", "height", "field"),
    [(0, 5, "width"), (5, 0, "height"), (257, 2, "width"), (2.5, 2, "width"), (True, 2, "width"), (1, 1, "width")],
)
def test_maze_rejects_bad_sizes(width, height, field):
    with pytest.raises(ValueError, match=field):
        levels.maze(width, height)
