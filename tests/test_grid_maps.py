"""Grid maps: POGEMA's rows of ``.`` and ``#`` and MovingAI ``.map`` files (``Level.from_grid``),
what ``level=`` and ``--level`` make of them, and the race's refusal of a level without exits."""

from __future__ import annotations

import gymnasium
import pytest

import babyrobot_marl  # noqa: F401  (registers the Gymnasium ids)
from babyrobot_marl import race_v0
from babyrobot_marl.cli.entry import main
from babyrobot_marl.core.checks import MAX_LEVEL_CELLS
from babyrobot_marl.core.grid import looks_like_grid_map
from babyrobot_marl.core.level import Level
from babyrobot_marl.envs.single import BabyRobotEnv
from babyrobot_marl.levels.files import load_level, read_level_file
from babyrobot_marl.levels.resolve import resolve_level

MOVINGAI = "type octile\nheight 3\nwidth 4\nmap\n..@.\nT...\n...O\n"


def test_rows_of_dots_and_blocks_make_a_level_without_walls_starts_or_exits():
    level = Level.from_grid("..#.\n....\n.@T.\nO...")
    assert (level.width, level.height) == (4, 4)
    assert level.blocked == {(2, 0), (1, 2), (2, 2), (0, 3)}
    assert not (level.walls or level.glass or level.starts or level.exits)
    assert len(level.free_cells()) == 12  # every open cell: no exit to reach


def test_a_grid_map_needs_no_border_of_its_own_and_its_indent_and_blank_lines_are_dropped():
    level = Level.from_grid("\n\n    ...\n    .#.\n  \n")
    assert (level.width, level.height) == (3, 2) and level.blocked == {(1, 1)}
    assert Level.from_grid("....").blocked == frozenset()  # one row
    assert Level.from_grid("..\r\n.#\r\n").blocked == {(1, 1)}  # CRLF


def test_a_movingai_map_reads_its_header_and_rows():
    level = Level.from_grid(MOVINGAI, name="m")
    assert (level.width, level.height) == (4, 3)
    assert level.blocked == {(2, 0), (0, 1), (3, 2)}


@pytest.mark.parametrize(("text", "where", "words"), [
    ("...\n.x.", "line 2, column 2", "bad character 'x'"),
    ("...\n..\n...", "line 2, column 3", "ragged row"),
    ("\n\n...\n. .", "line 4, column 2", "bad character ' '"),
    ("type octile\nheight 2\nwidth 3\nmap\n..@.\nT...\n", "line 5", "the header says height 2, width 3"),
    ("type octile\nheight 3\nwidth 4\nmap\n....\n....", "line 5", "the map has 2 rows of 4 characters"),
    ("type octile\nheight x\nwidth 4\nmap\n....", "line 2", "height is an integer >= 1"),
    ("type octile\nwidth 4\nmap\n....", "line 3", "lacks the line height before 'map'"),
    ("type octile\nheight 1\nwidth 4\ncolour blue\nmap\n....", "line 4", "starts with lines"),
    ("type octile\nheight 1\nwidth 4\n", "line 4", "lacks the line 'map'"),
])
def test_errors_name_the_line_and_column(text, where, words):
    with pytest.raises(ValueError) as err:
        Level.from_grid(text)
    assert str(err.value).startswith(where) and words in str(err.value)


def test_the_size_limits_of_level_texts_hold_before_any_cell_is_read():
    side = int(MAX_LEVEL_CELLS**0.5)
    assert Level.from_grid("\n".join(["." * side] * side)).n_cells == MAX_LEVEL_CELLS
    with pytest.raises(ValueError, match="at most 65,536 cells"):
        Level.from_grid("\n".join(["." * (side + 1)] * side + ["x"]))  # refused before the bad character
    with pytest.raises(ValueError, match="empty"):
        Level.from_grid(" \n\n")


def test_what_counts_as_a_grid_map():
    for spec in ("....", "..#\n...", ".@TO", "\n  ..\r\n  .#\n\n"):
        assert looks_like_grid_map(spec)
    for spec in ("default", "maze-8x8", "race-2", "maps/a.map", "+-+\n|E|\n+-+", "#####\n#S E#\n#####", "", " \n",
                 "TOO.map", "O-", "...\n.x.", MOVINGAI):  # a MovingAI text is read from its file (or Level.from_grid)
        assert not looks_like_grid_map(spec)


def test_level_takes_grid_strings_and_map_files(tmp_path):
    path = tmp_path / "room.map"
    path.write_text(MOVINGAI)
    for level in (read_level_file(path), load_level(str(path))):
        assert level.blocked == {(2, 0), (0, 1), (3, 2)} and level.name == "room"
    grid = tmp_path / "rows.txt"  # rows of "." and "#" in a file of another name: a grid map too
    grid.write_text("..\n#.\n")
    assert read_level_file(grid).blocked == {(0, 1)}
    assert load_level("..#\n...").blocked == {(2, 0)}
    assert load_level("....").blocked == frozenset()  # one row: not a level name
    with pytest.raises(ValueError, match=r"^level file .*bad\.map: line 1, column 1: bad character"):
        (tmp_path / "bad.map").write_text("+-+\n")
        read_level_file(tmp_path / "bad.map")


NO_EXIT = "level: has no exit; use goals='own'"


def test_the_race_refuses_a_level_without_exits_by_name(tmp_path):
    path = tmp_path / "room.map"
    path.write_text(MOVINGAI)
    for spec in ("....\n.#..", str(path), Level.from_grid("....")):
        with pytest.raises(ValueError, match=f"^{NO_EXIT}$"):
            resolve_level(spec)
        with pytest.raises(ValueError, match=f"^{NO_EXIT}$"):
            race_v0.parallel_env(level=spec, n_robots=2, start="random")
        with pytest.raises(ValueError, match=f"^{NO_EXIT}$"):
            BabyRobotEnv(level=spec)
        with pytest.raises(ValueError, match=f"^{NO_EXIT}$"):
            gymnasium.make("babyrobot_marl/BabyRobotRace-v0", level=spec)
    (tmp_path / "bad.map").write_text("..\nx.\n")
    with pytest.raises(ValueError, match=r"^level file .*bad\.map: line 2, column 1: bad character 'x'"):
        race_v0.parallel_env(level=str(tmp_path / "bad.map"), n_robots=2)
    with pytest.raises(ValueError, match="^level: grid map: text: a level has at most 65,536 cells"):
        race_v0.parallel_env(level=f"{'.' * 300}\n" * 300, n_robots=2)


def test_a_grid_map_with_an_exit_added_races(tmp_path):
    grid = Level.from_grid("....\n.#..\n....")
    level = Level(width=grid.width, height=grid.height, blocked=grid.blocked, exits={(3, 2)})
    env = race_v0.parallel_env(level=level, n_robots=3, start="random", collisions="soft")
    env.reset(seed=0)
    assert len(set(env.robot_cells)) == 3 and (1, 1) not in env.robot_cells


@pytest.mark.parametrize("command", ["race", "play"])
def test_the_cli_refuses_a_grid_map_without_exits_in_one_line_naming_the_flag(command, capsys):
    extra = ["--robots", "2"] if command == "race" else []
    code = main([command, "--level", "....\n.#..", "--seed", "1", *extra])
    err = capsys.readouterr().err.strip()
    # the CLI names its flags: --level, --goals own
    assert code == 2 and err == "babyrobot-marl: error: --level: has no exit; use --goals own"


def test_a_grid_map_without_exits_races_with_own_goals():
    """With ``goals="own"`` a level needs no exit: race_v0, BabyRobotRace-v0 and RaceVectorEnv take the map."""
    import gymnasium as gym

    from babyrobot_marl.envs.vector import RaceVectorEnv

    grid = "........\n.##..#..\n........\n..#....."
    env = race_v0.parallel_env(level=grid, n_robots=4, goals="own", collisions="soft", observe="local", start="random")
    env.reset(seed=3)
    assert len(env.goals) == 4 and not set(env.goals.values()) & Level.from_grid(grid).blocked
    single = gym.make("babyrobot_marl/BabyRobotRace-v0", level=grid, opponents=["random"], goals="own", start="random")
    single.reset(seed=0)
    vec = RaceVectorEnv(2, level=grid, n_robots=2, goals="own", start="random")
    vec.reset(seed=0)
    with pytest.raises(ValueError, match=f"^{NO_EXIT}$"):
        race_v0.parallel_env(level=grid, n_robots=2, goals="exit")
