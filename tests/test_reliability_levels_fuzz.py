"""Level text fuzzing: random and mutated level texts never crash ``Level.from_ascii``.

A text either parses, and then round-trips (``from_ascii(to_ascii(level)) == level``, and
``to_ascii`` is a fixed point), or raises a ``ValueError`` naming "line L, column C" inside the
text. The only whole-text error without a position is the empty text: every ``LevelError`` the
parser raises carries a slot or a cell, and ``Level``'s own checks that carry neither (an edge
outside the grid, an edge both wall and glass, no exit at all) cannot be reached from a text,
because the parser finds those first or cannot produce them.
"""

from __future__ import annotations

import ast
import contextlib
import dataclasses
import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import event as hypothesis_event
from hypothesis import strategies as st
from hypothesis.errors import InvalidArgument

from babyrobot_marl import Level
from tests.strategies import RANDOM_TEXTS, base_texts, grid_levels, mutated_texts, slot_texts, small_level_texts

POSITION = re.compile(r"\bline (\d+), column (\d+)\b")
WHOLE_TEXT_ERRORS = {"text: the level text is empty"}  # ValueErrors of from_ascii that name no position
FUZZ = settings(max_examples=800, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def event(value: str) -> None:
    """A Hypothesis event (statistics), ignored outside a Hypothesis test."""
    with contextlib.suppress(InvalidArgument):
        hypothesis_event(value)


def error_kind(message: str) -> str:
    """The message without its position and the character quoted in it: a statistics bucket."""
    text = POSITION.sub("", message).lstrip(": ")
    text = re.sub(r"'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\"", "X", text)
    return re.sub(r"\d+", "N", text).split(";")[0].split(" (")[0].split(":")[0][:50]


def text_lines(text: str) -> list[str]:
    """The lines as the format counts them: CRLF, LF and a lone CR each end a line."""
    return re.split(r"\r\n|\r|\n", text)


def check_text(text: str) -> None:
    try:
        level = Level.from_ascii(text)
    except ValueError as err:
        message = str(err)
        if message in WHOLE_TEXT_ERRORS:
            event("error: empty text")
            assert not text.strip(" \t\r\n"), f"{message!r} for a text that is not empty: {text!r}"
            return
        m = POSITION.search(message)
        assert m, f"a ValueError without a line and column: {message!r} for {text!r}"
        event(f"error: {error_kind(message)}")
        line, column = int(m[1]), int(m[2])
        lines = text_lines(text)
        assert 1 <= line <= len(lines), f"line {line} of a {len(lines)}-line text: {message!r}"
        widest = max(len(x.rstrip(" ")) for x in lines)  # only spaces are trimmed: a tab or form feed is a character
        assert 1 <= column <= widest, f"column {column} beyond the widest line ({widest}): {message!r}"
        bad = re.search(r"bad character ('(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\")", message)
        if bad:
            char = ast.literal_eval(bad[1])
            here = lines[line - 1][column - 1] if column <= len(lines[line - 1]) else None
            assert here == char, f"{message!r}: the text has {here!r} at line {line}, column {column}"
        found = re.search(r"found ('(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\")", message)
        if found:
            char = ast.literal_eval(found[1])
            row = lines[line - 1]
            here = row[column - 1] if column <= len(row.rstrip(" ")) else " "  # past the end: padded with spaces
            assert here == char, f"{message!r}: the text has {here!r} at line {line}, column {column}"
        return
    event("parsed")
    written = level.to_ascii()
    again = Level.from_ascii(written)
    assert again == level
    assert again.to_ascii() == written, "to_ascii is not a fixed point"
    rows = written.split("\n")
    assert len(rows) == 2 * level.height + 1 and {len(r) for r in rows} == {2 * level.width + 1}


@FUZZ
@given(mutated_texts())
def test_mutated_level_texts_parse_and_round_trip_or_raise_a_positioned_value_error(text):
    check_text(text)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(RANDOM_TEXTS)
def test_random_texts_parse_and_round_trip_or_raise_a_positioned_value_error(text):
    check_text(text)


@FUZZ
@given(slot_texts())
def test_random_slot_by_slot_texts_parse_and_round_trip_or_raise_a_positioned_value_error(text):
    check_text(text)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(small_level_texts(), st.sampled_from(["", "\n", "\n\n"]), st.integers(0, 6), st.sampled_from(["\n", "\r\n"]))
def test_valid_texts_parse_whatever_the_indent_blank_lines_and_line_ends(text, head, indent, sep):
    level = Level.from_ascii(text)
    shifted = head + sep.join(" " * indent + line for line in text.split("\n")) + sep
    assert Level.from_ascii(shifted) == level
    trimmed = "\n".join(line.rstrip() for line in text.split("\n"))  # editors trim trailing spaces
    assert Level.from_ascii(trimmed) == level


@pytest.mark.parametrize("name_index", range(len(base_texts())))
def test_every_single_character_change_of_a_builtin_level_is_handled(name_index):
    """Exhaustive on the smallest built-ins, sampled on the others: each character swapped for each level character."""
    text = base_texts()[name_index]
    positions = range(len(text)) if len(text) < 200 else range(0, len(text), 7)
    for k in positions:
        if text[k] == "\n":
            continue
        for ch in "+-|#* .SEpP019x":
            check_text(text[:k] + ch + text[k + 1 :])


@pytest.mark.parametrize("text", ["", "\n", "   \n \t \n", "\r\n\r\n"])
def test_the_empty_text_is_the_one_error_without_a_position(text):
    with pytest.raises(ValueError) as info:
        Level.from_ascii(text)
    assert str(info.value) in WHOLE_TEXT_ERRORS


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(grid_levels())
def test_random_levels_up_to_32x32_round_trip_through_their_text(level):
    """Levels built as Level(...) (random grids, decorated mazes), custom rewards aside, survive the text format."""
    level = dataclasses.replace(level, starts=level.starts[:10], rewards=())
    text = level.to_ascii()
    assert Level.from_ascii(text) == level
    assert Level.from_ascii(text).to_ascii() == text
    assert Level.from_ascii("\n".join("   " + row.rstrip() for row in text.split("\n"))) == level
