"""``--level maze:A..B`` on the commands that take ``--level`` (issue 27, item 2)."""

from __future__ import annotations

import re

import pytest

from babyrobot_marl import race_v0
from tests.cli_run import run


def drawn_by(spec: str, seed: int) -> str:
    env = race_v0.parallel_env(level=spec, n_robots=1)
    env.reset(seed=seed)
    return env.level.name


@pytest.mark.parametrize("command", [["race", "--robots", "3", "--no-delay"], ["play", "--no-delay"], ["solve"]])
def test_commands_take_a_family_spec_and_draw_the_maze_the_seed_draws(command, capsys):
    assert run([*command, "--level", "maze:5..9", "--seed", "7"]) == 0
    out = capsys.readouterr().out
    name = drawn_by("maze:5..9", 7)
    assert re.fullmatch(r"maze-(\d)x\1-s\d+", name) and name in out


def test_race_runs_many_races_on_a_family(capsys):
    assert run(["race", "--level", "maze:6..8", "--robots", "3", "--seed", "1", "--races", "12"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("12 races on maze:6..8") and "all finished: 1" in out


@pytest.mark.parametrize("command", [["race"], ["play"], ["solve"], ["train"]])
@pytest.mark.parametrize("spec", ["maze:16..8", "maze:8", "maze:x..9", "maze:0..4"])
def test_a_bad_spec_is_one_line_naming_the_flag_and_the_form(command, spec, capsys):
    assert run([*command, "--level", spec]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("babyrobot-marl: error: --level: a level family is 'maze:A..B'") and "e.g. 'maze:8..16'" in err
