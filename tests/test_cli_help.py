"""The command line's help speaks one language: the same placeholder for the same kind of value in
every command, and each command offers only what it takes."""

from __future__ import annotations

import argparse

import pytest

from babyrobot_marl.cli import build_parser

# the placeholders of the command line: counts, seeds and sizes N; other numbers X; files PATH
PLACEHOLDERS = {"N", "X", "SECONDS", "PATH", "NAME", "NAME|FILE|maze:A..B", "POLICY", "P1,P2,...", "H1,H2"}


def commands() -> dict[str, argparse.ArgumentParser]:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def test_every_placeholder_is_one_of_the_few_the_commands_share():
    used = {(name, a.dest): a.metavar for name, p in commands().items() for a in p._actions if a.metavar}
    assert set(used.values()) <= PLACEHOLDERS, {k: v for k, v in used.items() if v not in PLACEHOLDERS}
    # one flag, one placeholder, whichever command takes it
    by_flag: dict[str, set[str]] = {}
    for p in commands().values():
        for a in p._actions:
            if a.option_strings and a.metavar:
                by_flag.setdefault(a.option_strings[-1], set()).add(a.metavar)
    assert {flag: ms for flag, ms in by_flag.items() if len(ms) > 1} == {}


def test_evaluate_offers_only_the_policies_it_takes():
    text = commands()["evaluate"].format_help()
    assert "keys" not in text and "shortest" in text and "random" in text


@pytest.mark.parametrize("command", ["solve", "levels"])
def test_a_command_of_one_level_does_not_promise_a_new_maze_every_episode(command):
    assert "every episode" not in " ".join(commands()[command].format_help().split())


def test_solve_says_a_family_gives_it_one_maze_drawn_from_its_seed():
    assert "one square maze of side A..B, drawn from --seed" in " ".join(commands()["solve"].format_help().split())
