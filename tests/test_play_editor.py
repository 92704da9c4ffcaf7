"""The level editor's state transitions, without a browser: clicks on cells and edges -> level text."""

from __future__ import annotations

import pytest

from babyrobot_marl import levels
from babyrobot_marl.core.level import Level
from babyrobot_marl.play import editor as ed


def test_a_blank_draft_is_a_valid_level_with_a_start_and_an_exit():
    d = ed.blank(3, 2)
    assert ed.text(d) == "+-+-+-+\n|S    |\n+ + + +\n|    E|\n+-+-+-+"
    level, message, cell = ed.verdict(d)
    assert level == Level.from_ascii(ed.text(d)) and message.startswith("ok: a 3x2 level, 1 start") and cell is None
    assert ed.text(ed.blank(2, 1, race=True)) == "+-+-+\n|0 E|\n+-+-+"


def test_clicking_a_cell_cycles_floor_puddles_blocked_start_exit_and_back():
    d = ed.blank(3, 1)  # |S   E|
    seen = []
    for _ in range(6):
        d = ed.cycle_cell(d, (1, 0))
        seen.append(ed.cell_char(d, (1, 0)))
    assert seen == ["p", "P", "#", "S", "E", " "]


def test_a_single_robot_start_moves_where_it_is_placed():
    d = ed.blank(3, 1)
    for _ in range(4):  # floor -> p -> P -> # -> start
        d = ed.cycle_cell(d, (1, 0))
    assert ed.text(d) == "+-+-+-+\n|  S E|\n+-+-+-+"


def test_race_starts_are_numbered_in_turn_and_renumbered_without_gaps():
    d = ed.blank(4, 1, race=True)  # |0     E|
    for cell in ((1, 0), (2, 0)):
        for _ in range(4):
            d = ed.cycle_cell(d, cell)
    assert d[1] == "|0 1 2 E|"
    d = ed.cycle_cell(d, (1, 0))  # start 1 becomes an exit: start 2 becomes start 1
    assert d[1] == "|0 E 1 E|"
    level, message, _ = ed.verdict(d)
    assert level.starts == ((0, 0), (2, 0)) and "2 starts" in message


def test_clicking_an_edge_cycles_open_wall_glass_and_back():
    d = ed.blank(2, 2)
    vertical, horizontal = [], []
    for _ in range(3):
        d = ed.cycle_edge(d, (0, 0), (1, 0))
        vertical.append(d[1][2])
        d = ed.cycle_edge(d, (1, 1), (1, 0))  # either order of the two cells
        horizontal.append(d[2][3])
    assert vertical == ["|", "*", " "] and horizontal == ["-", "*", " "]


def test_the_verdict_points_at_an_exit_no_start_can_reach():
    d = ed.blank(3, 1)  # |S   E|: wall off the exit
    d = ed.cycle_edge(d, (1, 0), (2, 0))
    level, message, cell = ed.verdict(d)
    assert level is None
    with pytest.raises(ValueError) as err:
        Level.from_ascii(ed.text(d))
    assert message == str(err.value) and "cannot reach any exit" in message
    assert cell == (0, 0)  # the start that cannot reach it
    d = ed.cycle_edge(d, (1, 0), (2, 0))  # the wall becomes glass: passable
    assert ed.verdict(d)[0] is not None


def test_no_exit_is_named_by_the_verdict():
    d = ed.cycle_cell(ed.blank(2, 1), (1, 0))  # the exit cycles on to floor
    level, message, _ = ed.verdict(d)
    assert level is None and "missing exit" in message


def test_resize_keeps_what_fits_and_closes_the_border():
    d = ed.from_level(levels.get("walls"))
    small = ed.resize(d, 3, 2)
    assert ed.size(small) == (3, 2)
    assert [line[1:6] for line in small[1:4]] == [line[1:6] for line in d[1:4]]
    assert small[-1] == "+-+-+-+" and all(line[0] in "|+" and line[-1] in "|+" for line in small)
    big = ed.resize(ed.blank(2, 1), 3, 2)
    assert ed.text(big) == "+-+-+-+\n|S E  |\n+ + + +\n|     |\n+-+-+-+"
    with pytest.raises(ValueError, match="width: the editor takes an integer in 1..64"):
        ed.resize(d, 0, 3)


def test_from_level_round_trips_every_builtin_level():
    for name in levels.names():
        level = levels.get(name)
        if level.width <= ed.MAX_SIDE and level.height <= ed.MAX_SIDE:
            assert ed.verdict(ed.from_level(level))[0] == level


def test_race_mode_on_and_off():
    d = ed.blank(3, 1)
    d = ed.with_race(d, True)
    assert d[1] == "|0   E|" and ed.is_race(d)
    d = ed.cycle_cell(ed.cycle_cell(ed.cycle_cell(ed.cycle_cell(d, (1, 0)), (1, 0)), (1, 0)), (1, 0))
    assert d[1] == "|0 1 E|"
    assert ed.with_race(d, False)[1] == "|S   E|"


@pytest.mark.parametrize(
    "px, py, expected",
    [
        (16, 16, ("cell", (0, 0))),
        (47, 20, ("cell", (1, 0))),
        (31, 16, ("edge", (0, 0), (1, 0))),  # just left of the line between columns 0 and 1
        (33, 16, ("edge", (0, 0), (1, 0))),  # just right of it
        (48, 30, ("edge", (1, 0), (1, 1))),  # just above the line between rows 0 and 1
        (48, 62, None),  # the bottom border
        (2, 16, None),  # the left border
        (31, 31, None),  # a corner
        (200, 10, None),  # outside
    ],
)
def test_a_click_hits_a_cell_an_inner_edge_or_nothing(px, py, expected):
    assert ed.hit(px, py, 32, 3, 2) == expected


def test_bad_cells_and_edges_are_refused():
    d = ed.blank(2, 2)
    with pytest.raises(ValueError, match="outside the 2x2 grid"):
        ed.cycle_cell(d, (2, 0))
    with pytest.raises(ValueError, match="not neighbours"):
        ed.cycle_edge(d, (0, 0), (1, 1))


def test_a_second_start_says_that_it_moved_the_first():
    d = ed.blank(3, 2)  # its start at (0, 0)
    moved = ed.set_cell(d, (1, 1), "start")
    assert ed.cell_char(moved, (0, 0)) == " " and ed.cell_char(moved, (1, 1)) == "S"
    said = ed.moved_start(d, moved)
    assert "moved" in said and "column 0, row 0" in said and "column 1, row 1" in said
    assert ed.moved_start(d, ed.set_cell(d, (1, 1), "p")) == ""  # no start placed: nothing to say
    race = ed.with_race(d, True)
    assert ed.moved_start(race, ed.set_cell(race, (1, 1), "start")) == ""  # a race keeps both starts


def test_the_editor_says_what_is_wrong_once():
    """The verdict says what is missing; the place of the player under it does not say it again."""
    pytest.importorskip("ipywidgets")
    from babyrobot_marl.play import notebook

    e = notebook.edit((3, 2))  # start (0, 0), exit (2, 1)
    e.play()
    e.click_cell((2, 1))  # the exit turns to floor: no exit
    assert "needs an exit" in e.verdict.value
    (note,) = e.player_box.children
    assert "player comes back" in note.value and "needs an exit" not in note.value
    for _ in range(4):  # floor -> p -> P -> # -> start: the start moves here, and the verdict says so
        e.click_cell((1, 1))
    assert "the start moved here" in e.verdict.value


def test_the_editors_canvas_fills_the_column_as_the_games_canvas_does():
    """Without a cell size the editor's canvas is 90% of the column wide (never wider than its
    pixels), as a fitted game canvas is; its clicks land on the same cells."""
    pytest.importorskip("ipycanvas")
    from babyrobot_marl.play import notebook
    from babyrobot_marl.render.canvas import FIT_SHARE, fit_cell_size

    e = notebook.edit((5, 3))
    cs = fit_cell_size(ed.sketch(e.draft))
    assert e.cell_size == cs
    assert (e.canvas.width, e.canvas.height) == (5 * cs * 2, 3 * cs * 2)
    assert (e.canvas.layout.width, e.canvas.layout.max_width) == (FIT_SHARE, f"{5 * cs}px")
    e.click((2 + 0.5) * cs, (1 + 0.5) * cs)  # the middle of cell (2, 1)
    assert e._selected == (2, 1)
    e.resize(8, 8)  # a larger level: smaller cells, the canvas as wide
    assert e.cell_size == fit_cell_size(ed.sketch(e.draft)) and e.canvas.width == 8 * e.cell_size * 2
