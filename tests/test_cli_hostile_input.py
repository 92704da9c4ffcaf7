"""The command line against careless or hostile input: exit status 2 and one line on stderr,
no traceback, no hang, nothing large allocated before the input is checked (issue 15)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tracemalloc
from pathlib import Path

import pytest

from babyrobot_marl import levels
from babyrobot_marl.cli import levels as levels_command
from babyrobot_marl.core.checks import MAX_LEVEL_TEXT_CHARS
from tests.cli_run import run

REPO = Path(__file__).resolve().parents[1]
TINY = "+-+-+\n|S E|\n+-+-+\n"


def one_error_line(err: str) -> str:
    assert "Traceback" not in err, err
    assert err.count("\n") == 1 and err.startswith("babyrobot-marl: error: "), f"not one error line:\n{err}"
    return err


def test_a_level_name_longer_than_any_file_name_is_an_unknown_level_not_an_oserror(capsys):
    assert run(["play", "--level", "a" * 300, "--no-delay"]) == 2
    err = one_error_line(capsys.readouterr().err)
    assert "unknown level" in err and "(302 characters)" in err and "a" * 100 not in err  # shortened, not echoed whole


def test_a_maze_name_with_a_300_digit_seed_makes_that_maze(capsys):
    name = "maze-8x8-s" + "1" * 300
    assert run(["play", "--level", name, "--seed", "0", "--no-delay"]) == 0
    out = capsys.readouterr().out
    assert levels.get(name).to_ascii().splitlines()[1] in out


def test_a_maze_seed_past_pythons_digit_limit_is_a_clear_error(capsys):
    assert run(["levels", "maze-8x8-s" + "1" * 5000]) == 2
    assert "too many digits" in one_error_line(capsys.readouterr().err)


def test_more_robots_than_an_index_can_hold_are_refused_by_the_levels_free_cells(capsys):
    assert run(["race", "--robots", "99999999999999999999", "--no-delay"]) == 2
    assert "robots do not fit" in one_error_line(capsys.readouterr().err)


def test_robots_that_do_not_fit_are_refused_before_anything_per_robot_is_allocated(capsys):
    tracemalloc.start()
    try:
        assert run(["race", "--robots", "100000000", "--no-delay"]) == 2
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert "robots do not fit" in one_error_line(capsys.readouterr().err)
    assert peak < 50 * 2**20, f"{peak / 2**20:.0f} MB allocated before refusing 100,000,000 robots (800 MB before the fix)"


def test_a_directory_as_level_is_refused_as_a_directory(capsys, tmp_path):
    assert run(["play", "--level", str(tmp_path), "--no-delay"]) == 2
    assert "it is a directory" in one_error_line(capsys.readouterr().err)


def test_dev_zero_as_level_is_refused_as_a_device_without_reading_it(capsys):
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero on this system")
    assert run(["play", "--level", "/dev/zero", "--no-delay"]) == 2
    assert "it is a device" in one_error_line(capsys.readouterr().err)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_as_level_is_refused_without_waiting_for_a_writer(tmp_path):
    fifo = tmp_path / "level.fifo"
    os.mkfifo(fifo)
    proc = subprocess.run(
        [sys.executable, "-m", "babyrobot_marl", "play", "--level", str(fifo), "--no-delay"],
        capture_output=True, text=True, timeout=60, cwd=REPO, env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    assert proc.returncode == 2
    assert "it is a FIFO" in one_error_line(proc.stderr)


@pytest.mark.parametrize(
    ("content", "reason"),
    [(bytes(range(256)) * 4, "binary file"), (b"+-+-+\n|S\xe9E|\n+-+-+\n", "not UTF-8 text (byte 0xe9 at offset 8)")],
    ids=["nul bytes", "latin-1"],
)
def test_a_binary_file_as_level_is_refused_as_not_a_level_text(capsys, tmp_path, content, reason):
    path = tmp_path / "level.bin"
    path.write_bytes(content)
    assert run(["play", "--level", str(path), "--no-delay"]) == 2
    assert reason in one_error_line(capsys.readouterr().err)


def test_a_level_file_over_the_size_limit_is_refused_before_it_is_read(capsys, tmp_path):
    path = tmp_path / "huge.txt"
    with open(path, "wb") as f:  # sparse: the size says "too large" without writing megabytes
        f.truncate(MAX_LEVEL_TEXT_CHARS + 1)
    tracemalloc.start()
    try:
        assert run(["levels", str(path)]) == 2
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    err = one_error_line(capsys.readouterr().err)
    assert "too large" in err and f"{MAX_LEVEL_TEXT_CHARS:,} bytes" in err
    assert peak < MAX_LEVEL_TEXT_CHARS, "the file was read although its size is over the limit"


def test_a_level_file_of_many_cells_in_few_bytes_is_refused_by_its_cell_count(capsys, tmp_path):
    side = 300  # 90,000 cells, 364 kB of text: within the byte limit, over the cell limit
    path = tmp_path / "big.txt"
    path.write_text("\n".join(["+" + "-+" * side] + ["|" + " |" * side, "+" + "-+" * side] * side))
    assert run(["play", "--level", str(path), "--no-delay"]) == 2
    err = one_error_line(capsys.readouterr().err)
    assert "at most 65,536 cells" in err and "300x300" in err


def test_a_cr_only_level_text_is_read_as_a_level_not_taken_for_a_name(capsys):
    assert run(["levels", TINY.replace("\n", "\r")]) == 0
    assert capsys.readouterr().out == TINY


def test_a_level_file_with_cr_line_ends_is_read_as_with_lf(capsys, tmp_path):
    path = tmp_path / "mac.txt"
    path.write_bytes(TINY.replace("\n", "\r").encode())
    assert run(["levels", str(path)]) == 0
    assert capsys.readouterr().out == TINY


def test_an_unwritable_output_path_is_one_error_line_not_a_traceback(capsys, monkeypatch):
    def fail(args, out):
        raise PermissionError(13, "Permission denied", "/root/x.zip")

    monkeypatch.setattr(levels_command, "run", fail)
    assert run(["levels"]) == 2
    assert "Permission denied" in one_error_line(capsys.readouterr().err)


def test_running_out_of_memory_is_one_error_line_not_a_traceback(capsys, monkeypatch):
    def fail(args, out):
        raise MemoryError

    monkeypatch.setattr(levels_command, "run", fail)
    assert run(["levels"]) == 2
    assert "out of memory" in one_error_line(capsys.readouterr().err)


@pytest.mark.parametrize("argv", [["play", "--policy", "x" * 300], ["race", "--policies", "shortest," + "y" * 300]])
def test_a_policy_name_too_long_for_a_path_is_an_unknown_policy_not_a_traceback(argv, capsys):
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "policy" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("races", ["100001", "99999999999999999999", "0", "1e3"])
def test_races_past_the_limit_or_not_a_count_are_one_error_line_naming_the_limit(races, capsys):
    assert run(["race", "--races", races, "--no-delay"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("\n") == 1
    assert err.startswith("babyrobot-marl: error: --races: must be an integer in 1..100,000"), err


def test_races_at_the_limit_are_accepted_by_the_argument_parser():
    from babyrobot_marl.cli.checks import MAX_RACES, race_count

    assert race_count(str(MAX_RACES)) == MAX_RACES == 100_000


# The library's errors name its Python arguments (n_robots, start='fill'); the command line's name its flags.
PYTHON_NAMES = ("n_robots", "max_cycles", "max_steps", "view_radius", "near_radius", "start=", "observe=", "hint=")
IN_FLAGS = {
    "robots that do not fit": (["race", "--robots", "99"], "--robots: 99 robots do not fit"),
    "robots that do not fit (train)": (["train", "--level", "default", "--robots", "40", "--steps", "10"], "--robots: 40 robots"),
    "too few numbered starts": (["race", "--level", "race-2", "--robots", "3", "--start", "level"], "pass --start fill"),
    "unknown level": (["play", "--level", "nope"], "--level: unknown level 'nope'"),
    "unknown level (evaluate)": (["evaluate", "shortest", "--level", "nope"], "--level: unknown level 'nope'"),
    "unknown level to show": (["levels", "nope"], "NAME: unknown level 'nope'"),
    "maze side": (["play", "--level", "maze-0x0"], "--level 'maze-0x0': a maze side is an integer in 1..256"),
    "missing policy file": (["play", "--policy", "gone.pt"], "--policy: no such file 'gone.pt'"),
    "missing policy file (race)": (["race", "--policies", "shortest,gone.pt"], "--policies: no such file 'gone.pt'"),
    "missing policy file (evaluate)": (["evaluate", "gone.pt"], "POLICY: no such file 'gone.pt'"),
    "missing policy file (train)": (["train", "--steps", "10", "--load", "gone.pt"], "--load: no such file 'gone.pt'"),
    "keys in evaluate": (["evaluate", "keys"], "'keys' (you at the keyboard) is for 'play --policy' and 'race --human'"),
    "policies count": (["race", "--robots", "3", "--policies", "shortest,random"], "--policies: give one policy for all"),
}


@pytest.mark.parametrize(("argv", "message"), IN_FLAGS.values(), ids=IN_FLAGS.keys())
def test_errors_name_the_command_lines_flags_not_pythons_arguments(argv, message, capsys):
    assert run(argv) == 2
    err = capsys.readouterr().err  # argparse's errors take the commands' shape: "babyrobot-marl: error: --flag: ..."
    assert "Traceback" not in err and err.count("\n") == 1 and re.match(r"babyrobot-marl: error: ", err), err
    assert message in err
    assert not any(name in err for name in PYTHON_NAMES), err
    assert "invalid choice" not in err


def test_a_policy_folder_is_refused_as_a_folder(capsys, tmp_path):
    assert run(["play", "--policy", str(tmp_path)]) == 2
    assert "is a folder, not a saved policy" in capsys.readouterr().err


def test_flag_words_turns_python_arguments_into_flags():
    from babyrobot_marl.cli.common import flag_words

    assert flag_words("n_robots: 9 robots do not fit") == "--robots: 9 robots do not fit"
    assert flag_words("start: use start='fill' or start='random'") == "--start: use --start fill or --start random"
    assert flag_words("policy: trained on observe='local', view_radius=2, hint=True", "evaluate") == (
        "POLICY: trained on --observe local, --view-radius 2, --hint")
    assert flag_words("policy: x", "train") == "--load: x" and flag_words("level: unknown", "levels") == "NAME: unknown"
    assert flag_words("a sentence about a level: kept") == "a sentence about a level: kept"
