"""Fuzzing the command line as a careless or hostile user: random argument lists and level files
(binary, huge, empty, a directory, a FIFO, ``/dev/zero``, a symlink loop, CR line ends, too many
cells) each run in a fresh process with a time limit. Every run exits with status 0 or 2, never
prints a traceback, and an error is one line on stderr.

``train`` is left out: it needs the train extra and trains for minutes; its argument errors are
argparse's, covered here for the other commands. Sizes stay small (mazes up to 8x8, a few
robots, short delays) so that each run ends in seconds: the point is bad input, not long episodes.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from babyrobot_marl.core.checks import MAX_LEVEL_TEXT_CHARS

REPO = Path(__file__).resolve().parents[1]
TIME_LIMIT = 60  # seconds per run: generous on a loaded machine; a hang (a FIFO read, /dev/zero) exceeds it
ERROR_LINE = re.compile(r"^babyrobot-marl(?: \w+)?: error: \S")
TINY = "+-+-+\n|S E|\n+-+-+\n"


@pytest.fixture(scope="module")
def level_files(tmp_path_factory) -> dict[str, str]:
    """Level "files" of every kind a user might point ``--level`` at."""
    d = tmp_path_factory.mktemp("levels")
    files = {
        "valid": TINY,
        "cr": TINY.replace("\n", "\r"),
        "crlf_bom": "\ufeff" + TINY.replace("\n", "\r\n"),
        "empty": "",
        "blank_lines": "\n" * 100_000,
        "formfeed_line": "+-+-+\n|S E|\n\f\n|   |\n+-+-+\n",
        "race": "+-+-+-+\n|0 1 E|\n+-+-+-+\n",
        "too_many_cells": "\n".join(["+" + "-+" * 300] + ["|" + " |" * 300, "+" + "-+" * 300] * 300),
    }
    paths = {}
    for name, text in files.items():
        path = d / f"{name}.txt"
        path.write_bytes(text.encode())
        paths[name] = str(path)
    binary = d / "binary.bin"
    binary.write_bytes(bytes(range(256)) * 64)
    paths["binary"] = str(binary)
    latin1 = d / "latin1.txt"
    latin1.write_bytes(TINY.replace("S", "\xe9").encode("latin-1"))
    paths["latin1"] = str(latin1)
    huge = d / "huge.txt"
    with open(huge, "wb") as f:  # sparse: over the limit without writing it
        f.truncate(MAX_LEVEL_TEXT_CHARS + 10)
    paths["huge"] = str(huge)
    paths["directory"] = str(d)
    paths["missing"] = str(d / "missing.txt")
    if hasattr(os, "mkfifo"):
        os.mkfifo(d / "fifo")
        paths["fifo"] = str(d / "fifo")
    if os.path.exists("/dev/zero"):
        paths["dev_zero"] = "/dev/zero"
    loop = d / "loop"
    loop.symlink_to(loop)
    paths["symlink_loop"] = str(loop)
    return paths


def numbers() -> st.SearchStrategy[str]:
    """Integer-ish text: small, negative, huge (beyond any index), floats, junk."""
    return st.one_of(
        st.integers(-3, 8).map(str),
        st.integers(10**18, 10**40).map(str),
        st.integers(-(10**40), -1).map(str),
        st.sampled_from(["0", "1.5", "nan", "inf", "-inf", "1e999", "", " ", "0x10", "1_000", "9" * 5000, "٣"]),
        st.text(max_size=8),
    )


def level_specs(files: dict[str, str]) -> st.SearchStrategy[str]:
    side = st.one_of(st.integers(0, 8).map(str), st.sampled_from(["257", "99999999999999999999", "1" * 400]))
    mazes = st.builds(
        lambda w, h, s: f"maze-{w}x{h}" + (f"-s{s}" if s is not None else ""),
        side, side, st.one_of(st.none(), st.integers(0, 10**300).map(str), st.just("1" * 5000)),
    )
    return st.one_of(
        st.sampled_from(["default", "walls", "puddles", "glass", "race-2", "race-4", "race-corridor", "maze-8x8"]),
        mazes,
        st.sampled_from(sorted(files.values())),
        st.text(max_size=40),
        st.integers(1, 5000).map(lambda n: "a" * n),
        st.sampled_from([TINY, TINY.replace("\n", "\r"), "x/" * 200, "/", ".", "..", "-", "--level"]),
    )


def option(files: dict[str, str]) -> st.SearchStrategy[list[str]]:
    """One option with a (often bad) value, or a stray token."""
    num = numbers()
    modes = st.sampled_from(["block", "fill", "value", "x"])
    reals = st.sampled_from(["0.9", "0", "1", "2", "nan", "-1", "1e-9"])
    paths = st.sampled_from(sorted(files.values()))  # a policy may be a file too: the same special files
    policy_names = st.sampled_from(["random", "shortest", "keys", "", "x", "a" * 300, "x/" * 200])
    policy_lists = st.sampled_from(["random", "shortest,random", ",", "x,y", "random," * 50, "a" * 300])
    return st.one_of(
        st.tuples(st.just("--level"), level_specs(files)).map(list),
        st.tuples(st.sampled_from(["--seed", "--robots", "--max-steps", "--max-cycles", "--decimals", "--human"]), num).map(list),
        st.tuples(st.just("--policy"), st.one_of(policy_names, paths)).map(list),
        st.tuples(st.just("--policies"), policy_lists).map(list),
        st.tuples(st.sampled_from(["--collisions", "--start", "--method"]), modes).map(list),
        st.tuples(st.sampled_from(["--gamma", "--theta"]), reals).map(list),
        st.tuples(st.just("--delay"), st.sampled_from(["0", "0.001", "-1", "nan", "inf", "x"])).map(list),
        st.sampled_from([["--no-delay"], ["--no-color"], ["--help"], ["--version"], ["--"], ["-x"], ["--level"]]),
        st.text(max_size=12).map(lambda t: [t]),
    )


@st.composite
def argument_lists(draw, files: dict[str, str]) -> list[str]:
    command = draw(st.one_of(st.sampled_from(["levels", "play", "race", "solve"]), st.text(max_size=6)))
    argv = [command]
    if command == "levels" and draw(st.booleans()):
        argv.append(draw(level_specs(files)))
    for opt in draw(st.lists(option(files), max_size=4)):
        argv += opt
    return [a.replace("\0", "") for a in argv]  # a process argument cannot hold a NUL character


def run_cli(argv: list[str]) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(REPO), "PYTHONIOENCODING": "utf-8:surrogateescape"}
    return subprocess.run(
        [sys.executable, "-m", "babyrobot_marl", *argv],
        capture_output=True, timeout=TIME_LIMIT, cwd=REPO, env=env, stdin=subprocess.DEVNULL,
    )


def check_run(argv: list[str]) -> None:
    try:
        proc = run_cli(argv)
    except subprocess.TimeoutExpired:
        pytest.fail(f"no answer within {TIME_LIMIT} s for {argv!r:.300}")
    err = proc.stderr.decode("utf-8", "replace")
    assert "Traceback" not in err, f"a traceback for {argv!r:.300}:\n{err[-3000:]}"
    assert proc.returncode in (0, 2), f"exit status {proc.returncode} for {argv!r:.300}:\n{err[-2000:]}"
    if proc.returncode == 2:
        assert err.count("\n") == 1 and ERROR_LINE.match(err), f"not one error line for {argv!r:.300}:\n{err[-2000:]}"
        # in the command line's words: its flags, never the Python arguments behind them
        assert not re.search(r"\b(n_robots|max_cycles|max_steps|view_radius|near_radius)\b|\b(start|observe)=", err), err


def test_every_special_level_file_is_an_answer_in_time_not_a_hang_or_traceback(level_files):
    for path in level_files.values():
        check_run(["levels", path])


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_random_argument_lists_exit_0_or_2_with_one_error_line_and_no_traceback(level_files, data):
    check_run(data.draw(argument_lists(level_files), label="argv"))


LEVEL_CHARS = "+-|#* .SEpP0123456789\n\r\t\f\v\x00"
FILE_CONTENTS = st.one_of(
    st.binary(max_size=3000),
    st.text(alphabet=LEVEL_CHARS, max_size=3000).map(lambda t: t.encode()),
    st.text(max_size=500).map(lambda t: t.encode("utf-8", "surrogatepass")),
    st.sampled_from([TINY, TINY.replace("\n", "\r")]).map(lambda t: t.encode("utf-16")),  # not UTF-8
)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(content=FILE_CONTENTS, command=st.sampled_from(["levels", "play", "solve"]))
def test_random_level_file_contents_give_a_level_or_one_error_line(tmp_path_factory, content, command):
    path = tmp_path_factory.mktemp("fuzzed") / "level.txt"
    path.write_bytes(content)
    check_run([command, str(path)] if command == "levels" else [command, "--level", str(path)])
