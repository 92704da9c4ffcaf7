"""The ``babyrobot-marl`` command line: levels, play, and one-line errors for bad input."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from babyrobot_marl import cli, levels
from babyrobot_marl.cli import common
from babyrobot_marl.play import screen
from tests.cli_run import run
from tests.streams import TextSink

REPO = Path(__file__).resolve().parents[1]
SUMMARY = re.compile(r"seed (\d+): (\d+) steps, return (\S+), (.*)$", re.M)

# The default 3x3 level has no inner walls: start (0, 0), exit (2, 2). The shortest path is
# 4 moves (2 east, 2 south); each of the first 3 enters a floor cell (-1), the 4th the exit (0).
DEFAULT_SHORTEST_STEPS = 4
DEFAULT_SHORTEST_RETURN = -3.0


def summary(out: str) -> tuple[int, int, float, str]:
    m = SUMMARY.search(out)
    assert m, f"no summary line in:\n{out}"
    return int(m[1]), int(m[2]), float(m[3]), m[4]


# ------------------------------------------------------------------------ levels
def test_levels_lists_every_builtin_level_with_its_size_and_number_of_starts(capsys):
    assert run(["levels"]) == 0
    out = capsys.readouterr().out
    rows = {line.split()[0]: line.split() for line in out.splitlines() if line.strip()}
    for name in levels.names():
        lv = levels.get(name)
        assert rows[name][1:3] == [f"{lv.width}x{lv.height}", str(len(lv.starts))], rows[name]
    assert rows["race-4"][1:3] == ["7x7", "4"]


@pytest.mark.parametrize("argv", [["levels", "walls"], ["levels", "--show", "walls"]])
def test_levels_with_a_name_prints_that_levels_text(capsys, argv):
    assert run(argv) == 0
    assert capsys.readouterr().out == levels.text("walls") + "\n"


def test_levels_shows_a_level_file_in_canonical_form(capsys, tmp_path):
    path = tmp_path / "tiny.txt"
    path.write_text("    +-+-+-+\n    |S . E|\n    +-+-+-+\n")  # indented, '.' floor: both accepted
    assert run(["levels", str(path)]) == 0
    assert capsys.readouterr().out == "+-+-+-+\n|S   E|\n+-+-+-+\n"


# ------------------------------------------------------------------------ play
def test_play_shortest_on_the_default_level_reaches_the_exit_in_4_steps(capsys):
    assert run(["play", "--level", "default", "--policy", "shortest", "--seed", "0", "--no-delay"]) == 0
    out = capsys.readouterr().out
    seed, steps, ret, outcome = summary(out)
    assert (seed, steps, ret, outcome) == (0, DEFAULT_SHORTEST_STEPS, DEFAULT_SHORTEST_RETURN, "reached the exit")
    # into a pipe: the first frame, how many were left out, the last (the robot on the exit) with the key, the summary
    frames = out.split("\n\n")
    assert len(frames) == 4
    assert frames[0].splitlines()[1] == "|R    |"
    left_out = "frames left out: one per step on a terminal, or every one here with --all-frames"
    assert frames[1] == f"({DEFAULT_SHORTEST_STEPS - 1} {left_out})"
    assert frames[2].splitlines()[5] == "|    R|"
    assert frames[2].splitlines()[-1] == "key: R robot, +-| wall, S start, E exit"


def test_play_all_frames_prints_one_frame_per_step_into_a_pipe(capsys):
    assert run(["play", "--level", "default", "--policy", "shortest", "--seed", "0", "--no-delay", "--all-frames"]) == 0
    frames = capsys.readouterr().out.split("\n\n")
    assert len(frames) == DEFAULT_SHORTEST_STEPS + 2  # one after the reset, one per step, the summary
    assert [f.count("step ") for f in frames[:-1]] == [1] * (DEFAULT_SHORTEST_STEPS + 1)


def test_the_key_names_only_the_symbols_the_level_shows():
    from babyrobot_marl import levels
    from babyrobot_marl.render.ansi import symbols

    assert symbols(levels.get("default")) == "key: +-| wall, S start, E exit"
    race4 = symbols(levels.get("race-4"), "A..D robots")
    for part in ("A..D robots", "# blocked cell", "* glass wall", "p/P small/large puddle", "0-3 numbered starts", "E exit"):
        assert part in race4, part
    assert "S start" not in race4 and "p/P" not in symbols(levels.get("glass"))


def test_play_random_is_repeatable_with_the_same_seed_and_differs_with_another(capsys):
    argv = ["play", "--level", "puddles", "--policy", "random", "--no-delay", "--max-steps", "30", "--seed"]
    outs = []
    for seed in ("3", "3", "4"):
        assert run([*argv, seed]) == 0
        outs.append(capsys.readouterr().out)
    assert outs[0] == outs[1]
    assert outs[0].split("\n\nlevel")[0] != outs[2].split("\n\nlevel")[0]


def test_play_without_a_seed_prints_the_seed_that_replays_the_episode(capsys):
    argv = ["play", "--level", "glass", "--policy", "random", "--no-delay", "--max-steps", "40"]
    assert run(argv) == 0
    first = capsys.readouterr().out
    seed = summary(first)[0]
    assert run([*argv, "--seed", str(seed)]) == 0
    assert capsys.readouterr().out == first


def test_play_truncates_after_max_steps_and_says_the_exit_was_not_reached(capsys):
    assert run(["play", "--level", "maze-16x16", "--policy", "random", "--seed", "0", "--no-delay", "--max-steps", "5"]) == 0
    _, steps, ret, outcome = summary(capsys.readouterr().out)
    assert steps == 5
    assert ret == -5.0  # a maze has only floor cells: -1 per step
    assert outcome.startswith("did not reach the exit")


def test_play_accepts_a_path_to_a_level_file(capsys, tmp_path):
    path = tmp_path / "corridor.txt"
    path.write_text("+-+-+-+\n|S    |\n+-+-+ +\n|E    |\n+-+-+-+\n")  # a U: 5 moves round the wall
    assert run(["play", "--level", str(path), "--policy", "shortest", "--seed", "0", "--no-delay"]) == 0
    _, steps, ret, outcome = summary(capsys.readouterr().out)
    assert (steps, ret, outcome) == (5, -4.0, "reached the exit")


def test_play_into_a_file_or_pipe_writes_no_escape_codes(capsys):
    assert run(["play", "--level", "race-4", "--policy", "random", "--seed", "1", "--max-steps", "10", "--delay", "0"]) == 0
    assert "\x1b" not in capsys.readouterr().out


def test_play_on_a_terminal_redraws_in_place_with_a_coloured_robot(capsys, monkeypatch):
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True)
    monkeypatch.delenv("NO_COLOR", raising=False)
    assert run(["play", "--level", "default", "--policy", "shortest", "--seed", "0", "--no-delay"]) == 0
    out = capsys.readouterr().out
    assert out.count(screen.CURSOR_HOME) == DEFAULT_SHORTEST_STEPS + 1
    assert "\x1b[1;31mR\x1b[0m" in out  # robot 0's colour in render.ansi
    assert out.endswith(f"{DEFAULT_SHORTEST_STEPS} steps, return {DEFAULT_SHORTEST_RETURN}, reached the exit\n")
    assert screen.SHOW_CURSOR in out  # the cursor hidden for the animation comes back


@pytest.mark.parametrize("how", ["flag", "env"])
def test_play_on_a_terminal_has_no_colour_with_no_color(capsys, monkeypatch, how):
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True)
    argv = ["play", "--seed", "0", "--no-delay"]
    if how == "flag":
        argv.append("--no-color")
    else:
        monkeypatch.setenv("NO_COLOR", "1")
    assert run(argv) == 0
    out = capsys.readouterr().out
    assert "\x1b[1;" not in out
    assert out.count(screen.CURSOR_HOME) == DEFAULT_SHORTEST_STEPS + 1  # still redrawn in place


def test_animate_pauses_between_frames_but_not_before_the_first():
    pauses: list[float] = []
    shown = screen.animate(["a", "b", "c"], screen.Display(colour=False, clear=False, delay=0.25), TextSink(), pauses.append)
    assert shown == 3
    assert pauses == [0.25, 0.25]


def test_animate_off_a_terminal_separates_frames_with_a_blank_line():
    out = TextSink()
    screen.animate(["a\nb", "c"], screen.Display(colour=False, clear=False, delay=0.0), out)
    assert out.text == "a\nb\n\nc\n"


@pytest.mark.parametrize(("frames", "expected"), [
    ([], ""),
    (["a"], "a\n"),
    (["a", "b"], "a\n\nb\n"),
    (["a", "b", "c", "d"], "a\n\n(2 frames left out: one per step on a terminal, or every one here with --all-frames)\n\nd\n"),
])
def test_animate_into_a_log_shows_the_first_and_the_last_frame_and_counts_the_rest(frames, expected):
    out = TextSink()
    assert screen.animate(iter(frames), screen.Display(colour=False, clear=False, delay=0.0, ends_only=True), out) == len(frames)
    assert out.text == expected


@pytest.mark.parametrize(("tty", "all_frames", "ends_only"), [(True, False, False), (False, False, True), (False, True, False)])
def test_only_a_log_without_all_frames_shows_the_ends(tty, all_frames, ends_only):
    args = cli.build_parser().parse_args(["race"] + (["--all-frames"] if all_frames else []))
    assert common.display_of(args, TextSink(tty=tty)).ends_only is ends_only


@pytest.mark.parametrize(
    ("tty", "delay", "expected"), [(True, None, screen.DEFAULT_DELAY), (False, None, 0.0), (False, 0.5, 0.5)]
)
def test_default_delay_applies_on_a_terminal_only_and_an_explicit_delay_always(tty, delay, expected):
    args = cli.build_parser().parse_args(["play"] + ([] if delay is None else ["--delay", str(delay)]))
    assert common.display_of(args, TextSink(tty=tty)).delay == expected


# ------------------------------------------------------------------------ the command itself
def test_no_command_prints_the_help_listing_the_subcommands(capsys):
    assert run([]) == 0
    out = capsys.readouterr().out
    assert "levels" in out and "play" in out


def test_version_prints_the_package_version(capsys):
    import babyrobot_marl

    assert run(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"babyrobot-marl {babyrobot_marl.__version__}"


BAD_INPUT = {
    "unknown level": (["play", "--level", "nope"], "unknown level 'nope'"),
    "unknown policy": (["play", "--policy", "greedy"], "--policy: unknown policy 'greedy'; give random, shortest, keys or"),
    "negative seed": (["play", "--seed", "-1"], "--seed: must be an integer in 0..4,294,967,295"),
    "seed not an integer": (["play", "--seed", "1.5"], "--seed: must be an integer in 0..4,294,967,295"),
    "negative delay": (["play", "--delay", "-0.1"], "--delay: must be a number of seconds >= 0"),
    "delay not a number": (["play", "--delay", "fast"], "--delay: must be a number of seconds >= 0"),
    "infinite delay": (["play", "--delay", "inf"], "--delay: must be a number of seconds >= 0"),
    "delay and no-delay": (["play", "--delay", "1", "--no-delay"], "not allowed with"),
    "zero max steps": (["play", "--max-steps", "0"], "--max-steps: must be an integer >= 1"),
    "missing level file": (["play", "--level", "no/such/level.txt"], "no such level file"),
    "maze too large": (["play", "--level", "maze-300x3"], "a maze side is an integer in 1..256"),
    "unknown level to show": (["levels", "nope"], "unknown level 'nope'"),
    "two levels to show": (["levels", "walls", "--show", "glass"], "give one level to show"),
    "unknown command": (["fly"], "invalid choice: 'fly'"),
    "race unknown policy": (["race", "--policies", "shortest,greedy"], "unknown policy 'greedy'"),
    "race policies count": (["race", "--robots", "3", "--policies", "shortest,random"], "one policy for all robots or one per"),
    "race zero robots": (["race", "--robots", "0"], "--robots: must be an integer >= 1"),
    "race too few starts": (["race", "--level", "race-2", "--robots", "3", "--start", "level"], "pass --start fill"),
    "race unknown collisions": (["race", "--collisions", "crash"], "invalid choice: 'crash'"),
}


@pytest.mark.parametrize(("argv", "message"), BAD_INPUT.values(), ids=BAD_INPUT.keys())
def test_bad_input_exits_non_zero_with_one_error_line(capsys, argv, message):
    assert run(argv) != 0
    captured = capsys.readouterr()
    assert_one_error_line(captured.err, message)
    assert captured.out == ""


def test_a_broken_level_file_is_reported_with_its_line_and_column(capsys, tmp_path):
    path = tmp_path / "broken.txt"
    path.write_text("+-+-+\n|S?E|\n+-+-+\n")  # '?' in the vertical edge slot of line 2, column 3
    assert run(["play", "--level", str(path)]) == 2
    assert_one_error_line(capsys.readouterr().err, f"level file {path}: line 2, column 3: bad character '?'")


def assert_one_error_line(err: str, message: str) -> None:
    assert "Traceback" not in err
    assert err.count("\n") == 1 and err.endswith("\n"), f"expected one line on stderr, got:\n{err}"
    assert err.startswith("babyrobot-marl") and ": error: " in err, err
    assert message in err, err


# ------------------------------------------------------------------------ race
RESULT_ROW = re.compile(r"^(\d+|-)\s+([A-Z]) (robot_\d)\s+(\w+)\s+(\d+)(?: \(not finished\))?\s+(\S+)\s+(\d+)$", re.M)


def race_results(out: str) -> dict[str, tuple[str, int, float, int]]:
    """robot -> (rank, steps, return, collisions) from the results table."""
    rows = {m[3]: (m[1], int(m[5]), float(m[6]), int(m[7])) for m in RESULT_ROW.finditer(out)}
    assert rows, f"no results table in:\n{out}"
    return rows


def test_race_on_the_corridor_a_contest_at_the_exit_decides_the_winner(capsys):
    # race-corridor: robot_0 at (0, 0) and robot_2 at (6, 2) are both 4 moves from the exit
    # (3, 1) with nobody in their way, so both head into the exit on step 4: under "block" one
    # of them, drawn by the seed, gets it (rank 1, 3 floor cells -1 each + exit 0 + win bonus 10
    # = 7); the other is blocked and finishes later (on step 5 it may meet the winner's follower
    # at the exit, and lose again). Over seeds, each of the two wins sometimes.
    winners = set()
    for seed in range(12):
        assert run(["race", "--level", "race-corridor", "--robots", "4", "--policies", "shortest", "--seed", str(seed)]) == 0
        rows = race_results(capsys.readouterr().out)
        first = [r for r, row in rows.items() if row[0] == "1"]
        assert len(first) == 1 and first[0] in ("robot_0", "robot_2"), rows
        loser = "robot_2" if first[0] == "robot_0" else "robot_0"
        assert rows[first[0]][1:3] == (4, 7.0)
        assert rows[loser][0] in ("2", "3") and rows[loser][1] >= 5 and rows[loser][3] >= 1
        assert all(row[0] != "-" for row in rows.values())  # shortest robots all finish
        winners.add(first[0])
    assert winners == {"robot_0", "robot_2"}


def test_race_is_repeatable_with_a_seed(capsys):
    argv = ["race", "--level", "race-4", "--robots", "4", "--policies", "shortest,random,random,random", "--seed", "5"]
    assert run(argv) == 0
    first = capsys.readouterr().out
    assert run(argv) == 0
    assert capsys.readouterr().out == first


def test_race_with_collisions_pass_never_blocks_anyone(capsys):
    assert run(["race", "--level", "race-corridor", "--robots", "4", "--collisions", "pass", "--seed", "0"]) == 0
    rows = race_results(capsys.readouterr().out)
    assert all(row[3] == 0 for row in rows.values()), rows
    assert {r for r, row in rows.items() if row[0] == "1"} == {"robot_0", "robot_2"}  # both 4 steps away: a tie


# ------------------------------------------------------------------------ as a program
def run_module(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run(
        [sys.executable, "-m", "babyrobot_marl", *args], capture_output=True, text=True, timeout=120, cwd=REPO, env=env
    )


def test_python_m_play_shortest_on_the_default_level_prints_4_steps_and_return_minus_3():
    proc = run_module("play", "--level", "default", "--policy", "shortest", "--seed", "0", "--no-delay")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    _, steps, ret, outcome = summary(proc.stdout)
    assert (steps, ret, outcome) == (DEFAULT_SHORTEST_STEPS, DEFAULT_SHORTEST_RETURN, "reached the exit")
    assert "\x1b" not in proc.stdout  # a pipe is not a terminal


def test_python_m_with_bad_input_prints_one_line_and_no_traceback():
    proc = run_module("play", "--level", "nope", "--seed", "0")
    assert proc.returncode == 2
    assert_one_error_line(proc.stderr, "unknown level 'nope'")
