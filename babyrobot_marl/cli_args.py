"""Argument types of the ``babyrobot-marl`` command: each turns one command-line string into a
checked value or raises ``argparse.ArgumentTypeError`` with a one-line reason (argparse then
exits with status 2). Bad text of any length or digit count gets this reason, never a traceback.
"""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable

from . import policies
from .checks import MAX_RACES, shown
from .training.policy import is_policy_spec


def int_at_least(minimum: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``minimum``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:  # not an integer, or more than Python's 4,300 digits
            value = minimum - 1
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be an integer >= {minimum}, got {shown(text)}")
        return value

    return parse


non_negative_int = int_at_least(0)
positive_int = int_at_least(1)


def int_in(minimum: int, maximum: int, why: str = "") -> Callable[[str], int]:
    """An argparse type: an integer in ``minimum..maximum``; ``why`` says where the maximum comes from."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:  # not an integer, or more than Python's 4,300 digits
            value = minimum - 1
        if not minimum <= value <= maximum:
            raise argparse.ArgumentTypeError(f"must be an integer in {minimum}..{maximum:,}{why}, got {shown(text)}")
        return value

    return parse


# `race --races N`: every race is kept for the metrics table, one after another
race_count = int_in(1, MAX_RACES, " (races run one after another: split a larger experiment into seeded runs)")


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def seconds(text: str) -> float:
    value = _number(text)
    if not math.isfinite(value) or value < 0:  # nan, inf and negative delays make no animation
        raise argparse.ArgumentTypeError(f"must be a number of seconds >= 0, got {shown(text)}")
    return value


def probability(text: str) -> float:
    value = _number(text)
    if not 0.0 < value <= 1.0:
        raise argparse.ArgumentTypeError(f"must be a number in (0, 1], got {shown(text)}")
    return value


def positive_float(text: str) -> float:
    value = _number(text)
    if not 0.0 < value < math.inf:
        raise argparse.ArgumentTypeError(f"must be a number > 0, got {shown(text)}")
    return value


def non_negative_float(text: str) -> float:
    value = _number(text)
    if not 0.0 <= value < math.inf:
        raise argparse.ArgumentTypeError(f"must be a number >= 0, got {shown(text)}")
    return value


def unit_real(text: str) -> float:
    """A number in [0, 1] (a discount, GAE's lambda)."""
    value = _number(text)
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"must be a number in [0, 1], got {shown(text)}")
    return value


def output_path(text: str) -> str:
    """A file to write after a long run (``train --save``, ``--gif``, ``--curve``): its folder must exist
    and be writable now, and the path must not be a folder, so that nothing is lost at the end."""
    folder = os.path.dirname(text) or "."
    try:
        is_dir, folder_ok, writable = os.path.isdir(text), os.path.isdir(folder), os.access(folder, os.W_OK)
    except (OSError, ValueError):  # a NUL byte, a name too long
        is_dir, folder_ok, writable = False, False, False
    if not text or is_dir:
        raise argparse.ArgumentTypeError(f"must be a file's path, got {shown(text)}" + (" (a folder)" if is_dir else ""))
    if not folder_ok:
        raise argparse.ArgumentTypeError(f"no such folder {shown(folder)} for {shown(text)}; create it first")
    if not writable:
        raise argparse.ArgumentTypeError(f"the folder {shown(folder)} is not writable")
    return text


def policy_spec(text: str) -> str:
    """``--policy``: a scripted policy, ``keys`` (you drive), or the path of a saved policy."""
    if text != "keys" and not is_policy_spec(text):
        raise argparse.ArgumentTypeError(
            f"invalid choice: {shown(text)} (choose from {', '.join(policies.POLICY_NAMES)}, keys, or the path of a saved policy)"
        )
    return text


def policy_list(text: str) -> list[str]:
    """``random,shortest,...``: scripted policy names or saved policies' paths, comma-separated."""
    names = [p.strip() for p in text.split(",")]
    bad = [p for p in names if not is_policy_spec(p)]
    if bad:
        raise argparse.ArgumentTypeError(
            f"unknown policy {shown(bad[0])}; give a comma-separated list of {', '.join(policies.POLICY_NAMES)} "
            "or paths of saved policies"
        )
    return names
