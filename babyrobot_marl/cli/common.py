"""What the commands share: the program's name and exit statuses, the one-line-error parser, the
``--level``, ``--seed`` and display arguments, and how frames are shown (``play.screen``)."""

from __future__ import annotations

import argparse
import os
from typing import NoReturn, TextIO

from ..play.screen import DEFAULT_DELAY, Display, isatty
from .checks import SEED_HELP, level_spec, seconds, seed_int

PROG = "babyrobot-marl"
EXIT_USAGE = 2  # bad input, as argparse uses
EXIT_INTERRUPTED = 130  # Ctrl-C, as a shell reports it


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are one line: no usage block, no traceback."""

    def error(self, message: str) -> NoReturn:
        # argparse quotes the arguments it rejects: keep a newline or a huge argument from breaking the one line
        self.exit(EXIT_USAGE, f"{self.prog}: error: {one_line(message)} (see '{self.prog} --help')\n")


def one_line(err: BaseException | str, limit: int = 1000) -> str:
    """The message on one line, at most ``limit`` characters."""
    text = " ".join(str(err).split()) or type(err).__name__
    return text if len(text) <= limit else f"{text[: limit - 40]}... ({len(text):,} characters)"


# ------------------------------------------------------------------------ shared arguments
def add_level_arg(p: argparse.ArgumentParser, default: str = "default") -> None:
    p.add_argument(
        "--level",
        default=default,
        type=level_spec,
        metavar="NAME|FILE|maze:A..B",
        help=f"a built-in level (see '{PROG} levels'), maze-WxH[-sSEED], the path of a level text file or of a "
        "MovingAI .map file, a grid map (rows of '.' and '#'; it has no exit), or maze:A..B: "
        f"a new square maze of side A..B for every episode, drawn from --seed (default: {default})",
    )


def add_seed_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--seed",
        type=seed_int,
        default=None,
        metavar="N",
        help=f"seed of the episode and of random policies, {SEED_HELP} (default: a fresh one, printed at the end so it "
        "can be replayed)",
    )


def add_display_args(p: argparse.ArgumentParser) -> None:
    delay = p.add_mutually_exclusive_group()
    delay.add_argument(
        "--delay",
        type=seconds,
        default=None,
        metavar="SECONDS",
        help=f"pause between frames (default: {DEFAULT_DELAY} on a terminal, 0 when the output is a file or pipe)",
    )
    delay.add_argument("--no-delay", dest="delay", action="store_const", const=0.0, help="no pause between frames")
    p.add_argument("--no-color", action="store_true", help="no ANSI colours (also: set the NO_COLOR environment variable)")


def display_of(args: argparse.Namespace, out: TextIO) -> Display:
    tty = isatty(out)
    colour = tty and not args.no_color and not os.environ.get("NO_COLOR")
    delay = args.delay if args.delay is not None else (DEFAULT_DELAY if tty else 0.0)
    return Display(colour=colour, clear=tty, delay=delay)


def fresh_seed() -> int:
    return int.from_bytes(os.urandom(4), "little") >> 1  # < 2**31: short enough to retype
