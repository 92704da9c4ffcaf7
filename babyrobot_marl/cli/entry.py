"""The command line's entry point: the parser of every command (``build_parser``) and ``main``, which turns
any error into one line on stderr and an exit status."""

from __future__ import annotations

import argparse
import os
import sys
from importlib import metadata

from ..training.deps import MissingTrainExtraError
from . import evaluate, levels, play, race, solve, train
from .common import EXIT_INTERRUPTED, EXIT_USAGE, PROG, Parser, flag_words, one_line

COMMANDS = (levels, play, race, solve, train, evaluate)  # each: add_parser(sub) and run(args, out)


def _version() -> str:
    """The installed distribution's version (the package root's ``__version__``), without importing the root."""
    try:
        return metadata.version("babyrobot_marl")
    except metadata.PackageNotFoundError:  # run from a checkout that was never installed
        return "unknown (not installed)"


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``babyrobot-marl`` with all subcommands."""
    parser = Parser(prog=PROG, description="Baby Robot grid worlds: levels, and episodes watched in the terminal.")
    parser.add_argument("--version", action="version", version=f"{PROG} {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in COMMANDS:  # each further subcommand: a module with add_parser and run, named here
        command.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 bad input, 130 interrupted)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    out = sys.stdout
    if args.command is None:
        parser.print_help(out)
        return 0
    try:
        return args.func(args, out)
    except MissingTrainExtraError as err:  # e.g. a saved policy without torch: how to install it, on one line
        print(f"{PROG}: error: {one_line(err)}", file=sys.stderr)
        return EXIT_USAGE
    except (ValueError, TypeError) as err:  # the library names its arguments: say the flags instead
        print(f"{PROG}: error: {flag_words(one_line(err), args.command)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # The reader went away (e.g. '| head'): stop quietly; point stdout at devnull so that
        # Python's flush at exit does not raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except OSError as err:  # e.g. an output path that cannot be written
        print(f"{PROG}: error: {one_line(err)}", file=sys.stderr)
        return EXIT_USAGE
    except MemoryError:  # the last resort: the limits (README "Limits") should stop large inputs before this
        print(f"{PROG}: error: out of memory; try a smaller level or fewer robots", file=sys.stderr)
        return EXIT_USAGE
