"""Level: the text format of DESIGN.md (parse, write, round trip), its errors, and the Level object."""

from __future__ import annotations

import dataclasses
import re
import textwrap
from collections import deque

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from babyrobot_marl import race_v0
from babyrobot_marl.core.level import Level

DEFAULT_TEXT = """\
+-+-+-+
|S    |
+ + + +
|     |
+ + + +
|    E|
+-+-+-+"""

# One of everything, at known places (x is the column, y the row):
#   wall (0,0)-(1,0) '|', wall (1,0)-(1,1) '-', glass (1,1)-(2,1) '*', glass (2,1)-(2,2) '*',
#   small puddle (1,1), large puddle (0,2), blocked (2,0), exit (2,2), '.' floor at (2,1).
FEATURES_TEXT = """\
+-+-+-+
|S|  #|
+ +-+ +
|  p*.|
+ + +*+
|P   E|
+-+-+-+"""


def edge(a, b):
    """An edge as DESIGN.md stores it: the pair of adjacent cells, sorted."""
    return (a, b) if a < b else (b, a)


def test_default_text_parses_to_a_3x3_grid_with_start_top_left_and_exit_bottom_right():
    level = Level.from_ascii(DEFAULT_TEXT)
    assert (level.width, level.height) == (3, 3)
    assert level.starts == ((0, 0),)
    assert level.exits == {(2, 2)}
    assert not (level.walls or level.glass or level.blocked or level.small_puddles or level.large_puddles)


def test_each_character_lands_in_the_right_set_at_the_right_cell():
    level = Level.from_ascii(FEATURES_TEXT)
    assert (level.width, level.height) == (3, 3)
    assert level.walls == {edge((0, 0), (1, 0)), edge((1, 0), (1, 1))}
    assert level.glass == {edge((1, 1), (2, 1)), edge((2, 1), (2, 2))}
    assert level.blocked == {(2, 0)}
    assert level.small_puddles == {(1, 1)}
    assert level.large_puddles == {(0, 2)}
    assert level.exits == {(2, 2)}
    assert level.starts == ((0, 0),)


def test_hash_in_an_edge_slot_is_a_wall_in_both_orientations():
    with_plain = Level.from_ascii("+-+-+-+\n|S|   |\n+ +-+ +\n|    E|\n+-+-+-+")
    with_hash = Level.from_ascii("+-+-+-+\n|S#   |\n+ +#+ +\n|    E|\n+-+-+-+")
    assert with_hash == with_plain
    assert with_hash.walls == {edge((0, 0), (1, 0)), edge((1, 0), (1, 1))}


def test_hash_borders_are_walls():
    assert Level.from_ascii("#####\n#S E#\n#####") == Level.from_ascii("+-+-+\n|S E|\n+-+-+")


@pytest.mark.parametrize("corner", list("+#-| "))
def test_corner_characters_are_ignored(corner):
    text = DEFAULT_TEXT.replace("+", corner)
    assert Level.from_ascii(text) == Level.from_ascii(DEFAULT_TEXT)


def test_dot_floor_equals_space_floor():
    dotted = DEFAULT_TEXT.replace("|S    |", "|S . .|").replace("|     |", "|. . .|")
    assert dotted != DEFAULT_TEXT
    assert Level.from_ascii(dotted) == Level.from_ascii(DEFAULT_TEXT)


def test_s_is_start_zero():
    assert Level.from_ascii(DEFAULT_TEXT.replace("S", "0")) == Level.from_ascii(DEFAULT_TEXT)


def test_numbered_starts_are_ordered_by_number_not_by_position():
    level = Level.from_ascii("+-+-+-+-+\n|2 0 1 E|\n+-+-+-+-+")
    assert level.starts == ((1, 0), (2, 0), (0, 0))


def test_indented_triple_quoted_text_parses():
    def make():
        return """
            +-+-+-+
            |S    |
            + + + +
            |     |
            + + + +
            |    E|
            +-+-+-+
        """

    assert Level.from_ascii(make()) == Level.from_ascii(DEFAULT_TEXT)


def test_leading_and_trailing_blank_lines_crlf_and_trimmed_trailing_spaces_parse():
    # corners written as ' ' and trimmed by an editor: the even lines are one character short
    text = DEFAULT_TEXT.replace("+", " ")
    trimmed = "\n".join(line.rstrip() for line in text.split("\n"))
    assert trimmed != text
    assert Level.from_ascii("\n\n" + trimmed.replace("\n", "\r\n") + "\n   \n") == Level.from_ascii(DEFAULT_TEXT)


def test_blank_line_inside_a_level_is_a_row_of_open_edges():
    text = DEFAULT_TEXT.replace("+ + + +", "", 1)
    assert Level.from_ascii(text) == Level.from_ascii(DEFAULT_TEXT)


def test_name_is_kept_but_not_compared():
    a = Level.from_ascii(DEFAULT_TEXT, name="a")
    b = Level.from_ascii(DEFAULT_TEXT, name="b")
    assert a.name == "a" and a == b and hash(a) == hash(b)


# --------------------------------------------------------------------------------------- errors
# (text, 1-based line, 1-based column of the fault, a word the message must contain)
BAD_TEXTS = {
    "bad char in a cell slot": ("+-+-+-+\n|S x E|\n+-+-+-+", 2, 4, "cell"),
    "bad char in a vertical edge slot": ("+-+-+\n|S?E|\n+-+-+", 2, 3, "edge"),
    "dash in a vertical edge slot": ("+-+-+\n|S-E|\n+-+-+", 2, 3, "vertical"),
    "bar in a horizontal edge slot": ("+-+\n|S|\n+|+\n|E|\n+-+", 3, 2, "horizontal"),
    "bad char in a corner slot": ("+-x-+\n|S E|\n+-+-+", 1, 3, "corner"),
    "bad char in a middle corner": ("+-+-+\n|S  |\n+ o +\n|  E|\n+-+-+", 3, 3, "corner"),
    "ragged line, one character too long": ("+-+-+-+\n|S   E|x\n+-+-+-+", 2, 8, "ragged"),
    "ragged line, right border missing": ("+-+-+-+\n|S   E\n+-+-+-+", 2, 7, "border"),
    "open top border": ("+-+ +-+\n|S   E|\n+-+-+-+", 1, 4, "border"),
    "open left border": ("+-+-+\n S E|\n+-+-+", 2, 1, "border"),
    "open bottom border": ("+-+-+\n|S E|\n+-+ +", 3, 4, "border"),
    "glass on the border": ("+-+-+\n|S E*\n+-+-+", 2, 5, "border"),
    "even number of lines": ("+-+-+\n|S E|\n+-+-+\n|   |", 4, 1, "lines"),
    "missing exit": ("+-+-+\n|S  |\n+-+-+", 1, 1, "exit"),
    "exit unreachable from the start": ("+-+-+\n|S|E|\n+-+-+", 2, 2, "reach"),
    "exit unreachable from start 1": ("+-+-+-+\n|0 E|1|\n+-+-+-+", 2, 6, "reach"),
    "exit behind a blocked cell": ("+-+-+-+\n|S # E|\n+-+-+-+", 2, 2, "reach"),
    "duplicate start, S and 0": ("+-+-+-+\n|S 0 E|\n+-+-+-+", 2, 4, "twice"),
    "duplicate numbered start": ("+-+-+-+-+\n|1 0 1 E|\n+-+-+-+-+", 2, 6, "twice"),
    "missing start number": ("+-+-+-+\n|0 2 E|\n+-+-+-+", 2, 4, "missing"),
}


def _shifted(text: str, blank_lines: int, indent: int) -> str:
    return "\n" * blank_lines + textwrap.indent(text, " " * indent, lambda line: True) + "\n"


@pytest.mark.parametrize("layout", [(0, 0), (2, 4), (1, 8)], ids=["plain", "2-blank-lines-indent-4", "1-blank-line-indent-8"])
@pytest.mark.parametrize("case", list(BAD_TEXTS))
def test_malformed_text_is_a_value_error_at_the_right_line_and_column(case, layout):
    text, line, column, word = BAD_TEXTS[case]
    blank_lines, indent = layout
    with pytest.raises(ValueError) as info:
        Level.from_ascii(_shifted(text, blank_lines, indent))
    message = str(info.value)
    expected = f"line {line + blank_lines}, column {column + indent}"
    assert re.search(rf"\b{expected}\b", message), f"{message!r} should name {expected!r}"
    assert word in message.lower()


def test_position_of_a_bad_character_deep_inside_a_big_indented_level():
    rows = ["+-+-+-+-+-+"] + ["|         |", "+ + + + + +"] * 4 + ["|        E|", "+-+-+-+-+-+"]
    rows[1] = "|S        |"
    rows[7] = rows[7][:6] + "!" + rows[7][7:]  # line 8, 0-based column 6: a vertical edge slot
    text = "\n\n\n" + "\n".join("      " + r for r in rows)
    with pytest.raises(ValueError, match=r"\bline 11, column 13\b"):
        Level.from_ascii(text)


@pytest.mark.parametrize("text", ["", "\n\n", "   \n  "])
def test_empty_text_is_a_value_error(text):
    with pytest.raises(ValueError, match="empty"):
        Level.from_ascii(text)


@pytest.mark.parametrize("text", [None, 3, b"+-+"])
def test_non_string_text_is_a_type_error(text):
    with pytest.raises(TypeError, match="text"):
        Level.from_ascii(text)


# --------------------------------------------------------------------------------------- Level object
def test_constructor_normalises_edges_and_cells():
    level = Level(width=3, height=2, starts=[(0, 0)], exits=[(2, 0)], walls=[((1, 0), (0, 0))], glass=[[(1, 0), (2, 0)]])
    assert level.walls == frozenset({((0, 0), (1, 0))})
    assert level.glass == frozenset({((1, 0), (2, 0))})
    assert level.starts == ((0, 0),) and isinstance(level.exits, frozenset)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"width": 0}, "width"),
        ({"height": -1}, "height"),
        ({"width": 2.0}, "width"),
        ({"width": True}, "width"),
        ({"exits": [(5, 0)]}, "exits"),
        ({"starts": [(0, 3)]}, "starts"),
        ({"walls": [((0, 0), (2, 0))]}, "walls"),
        ({"walls": [((0, 0), (0, -1))]}, "walls"),
        ({"glass": [(0, 0)]}, "glass"),
        ({"walls": [((0, 0), (1, 0))], "glass": [((0, 0), (1, 0))]}, "glass"),
        ({"blocked": [(2, 0)]}, "blocked"),
        ({"small_puddles": [(2, 0)]}, "small_puddles"),
        ({"large_puddles": [(0.5, 0)]}, "large_puddles"),
        ({"starts": [(0, 0), (0, 0)]}, "starts"),
        ({"walls": [((0, 0), (1, 0))]}, "starts"),  # the start is cut off from the exit
        ({"blocked": [(1, 0)]}, "starts"),
        ({"rewards": {(0, 0): float("nan")}}, "rewards"),
        ({"rewards": {(0, 0): "big"}}, "rewards"),
        ({"rewards": {(9, 0): 1.0}}, "rewards"),
    ],
)
def test_constructor_rejects_bad_fields_naming_the_field(kwargs, field):
    base = {"width": 3, "height": 1, "starts": [(0, 0)], "exits": [(2, 0)]}
    with pytest.raises(ValueError, match=field):
        Level(**{**base, **kwargs})


def test_a_level_without_exits_is_a_level_the_race_refuses_by_name():
    level = Level(width=3, height=1, starts=[(0, 0)], exits=[])  # a grid map's: robots with targets of their own
    assert level.exits == frozenset() and level.free_cells() == [(0, 0), (1, 0), (2, 0)]
    with pytest.raises(ValueError, match="^level: has no exit; use goals='own'$"):
        race_v0.parallel_env(level=level, n_robots=1)


def test_level_is_immutable_and_hashable():
    level = Level.from_ascii(DEFAULT_TEXT)
    with pytest.raises(dataclasses.FrozenInstanceError):
        level.width = 4
    assert {level: 1}[Level.from_ascii(DEFAULT_TEXT)] == 1


def test_with_rewards_returns_a_new_level_and_merges():
    level = Level.from_ascii(DEFAULT_TEXT)
    a = level.with_rewards({(1, 0): 5.0})
    b = a.with_rewards({(2, 0): -3, (1, 0): 6.5})
    assert level.reward_map() == {}
    assert a.reward_map() == {(1, 0): 5.0}
    assert b.reward_map() == {(1, 0): 6.5, (2, 0): -3.0}
    assert a != level and b != a


@pytest.mark.parametrize(("corner_a", "corner_b"), [((0, 1), (2, 2)), ((2, 2), (0, 1)), ((0, 2), (2, 1))])
def test_with_area_reward_covers_exactly_the_rectangle(corner_a, corner_b):
    level = Level.from_ascii(DEFAULT_TEXT).with_area_reward(corner_a, corner_b, -7)
    assert level.reward_map() == {(x, y): -7.0 for x in range(3) for y in (1, 2)}


@pytest.mark.parametrize(
    ("rewards", "field"), [({(0, 0): float("inf")}, "rewards"), ({(3, 3): 1.0}, "rewards"), ({"a": 1}, "rewards")]
)
def test_with_rewards_rejects_bad_values(rewards, field):
    with pytest.raises(ValueError, match=field):
        Level.from_ascii(DEFAULT_TEXT).with_rewards(rewards)


def test_free_cells_exclude_blocked_exits_puddles_and_cells_cut_off_from_the_exits():
    level = Level(
        width=4,
        height=2,
        # a wall column between x=1 and x=2: the left half cannot reach the exit
        walls=[((1, 0), (2, 0)), ((1, 1), (2, 1))],
        blocked=[(3, 0)],
        small_puddles=[(2, 0)],
        exits=[(3, 1)],
    )
    assert sorted(level.free_cells()) == [(2, 1)]
    assert level.cells_reaching_exit() == {(2, 0), (2, 1), (3, 1)}


# --------------------------------------------------------------------------------------- writing and round trips
def independent_text(width, height, walls, glass, cells):
    """The canonical text written straight from DESIGN.md's table, independently of Level.to_ascii."""
    grid = [["+"] * (2 * width + 1) for _ in range(2 * height + 1)]
    for y in range(2 * height + 1):
        for x in range(2 * width + 1):
            if y % 2 == 1 and x % 2 == 1:
                grid[y][x] = cells.get(((x - 1) // 2, (y - 1) // 2), " ")
            elif y % 2 == 1 and x % 2 == 0:  # vertical slot between ((x-2)//2, row) and (x//2, row)
                a, b = ((x - 2) // 2, (y - 1) // 2), (x // 2, (y - 1) // 2)
                border = x in (0, 2 * width)
                grid[y][x] = "|" if border or (a, b) in walls else ("*" if (a, b) in glass else " ")
            elif y % 2 == 0 and x % 2 == 1:
                a, b = ((x - 1) // 2, (y - 2) // 2), ((x - 1) // 2, y // 2)
                border = y in (0, 2 * height)
                grid[y][x] = "-" if border or (a, b) in walls else ("*" if (a, b) in glass else " ")
    return "\n".join("".join(row) for row in grid)


def reachable_from_exits(width, height, walls, blocked, exits):
    seen, todo = set(exits), deque(exits)
    while todo:
        x, y = todo.popleft()
        for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
            if 0 <= n[0] < width and 0 <= n[1] < height and n not in blocked and n not in seen and edge((x, y), n) not in walls:
                seen.add(n)
                todo.append(n)
    return seen


@st.composite
def random_levels(draw):
    width, height = draw(st.integers(1, 6)), draw(st.integers(1, 6))
    cells = [(x, y) for y in range(height) for x in range(width)]
    if len(cells) < 2:
        width = 2
        cells = [(0, 0), (1, 0)]
    edges = [((x, y), (x + 1, y)) for (x, y) in cells if x + 1 < width] + [
        ((x, y), (x, y + 1)) for (x, y) in cells if y + 1 < height
    ]
    edge_kinds = draw(st.lists(st.sampled_from(" |*"), min_size=len(edges), max_size=len(edges)))
    cell_kinds = draw(st.lists(st.sampled_from("  #pPE"), min_size=len(cells), max_size=len(cells)))
    cell_kinds[draw(st.integers(0, len(cells) - 1))] = "E"
    kinds = dict(zip(cells, cell_kinds, strict=True))
    walls = {e for e, k in zip(edges, edge_kinds, strict=True) if k == "|"}
    glass = {e for e, k in zip(edges, edge_kinds, strict=True) if k == "*"}
    blocked = {c for c, k in kinds.items() if k == "#"}
    exits = {c for c, k in kinds.items() if k == "E"}
    reach = reachable_from_exits(width, height, walls, blocked, exits)
    candidates = [c for c in cells if kinds[c] == " " and c in reach]
    starts = draw(st.permutations(candidates))[: draw(st.integers(0, min(10, len(candidates))))]
    level = Level(
        width=width,
        height=height,
        walls=walls,
        glass=glass,
        blocked=blocked,
        small_puddles={c for c, k in kinds.items() if k == "p"},
        large_puddles={c for c, k in kinds.items() if k == "P"},
        exits=exits,
        starts=tuple(starts),
    )
    cells_text = {c: k for c, k in kinds.items() if k != " "}
    for i, c in enumerate(starts):
        cells_text[c] = "S" if len(starts) == 1 else str(i)
    return level, independent_text(width, height, walls, glass, cells_text)


@settings(max_examples=150, deadline=None)
@given(random_levels())
def test_random_levels_write_the_canonical_text_and_read_back_equal(case):
    level, text = case
    assert level.to_ascii() == text
    assert Level.from_ascii(text) == level
    assert Level.from_ascii(level.to_ascii()) == level
    lines = level.to_ascii().split("\n")
    assert len(lines) == 2 * level.height + 1
    assert all(len(line) == 2 * level.width + 1 for line in lines)


def test_str_is_the_text():
    level = Level.from_ascii(DEFAULT_TEXT)
    assert str(level) == DEFAULT_TEXT == level.to_ascii()


def test_single_start_written_as_zero_comes_back_as_s():
    assert Level.from_ascii(DEFAULT_TEXT.replace("S", "0")).to_ascii() == DEFAULT_TEXT


def test_custom_rewards_are_not_part_of_the_text():
    level = Level.from_ascii(DEFAULT_TEXT).with_rewards({(1, 1): 3.0})
    assert level.to_ascii() == DEFAULT_TEXT
    assert Level.from_ascii(level.to_ascii()) == Level.from_ascii(DEFAULT_TEXT)


def test_more_than_ten_starts_cannot_be_written():
    level = Level(width=12, height=1, starts=[(x, 0) for x in range(11)], exits=[(11, 0)])
    with pytest.raises(ValueError, match="starts"):
        level.to_ascii()
