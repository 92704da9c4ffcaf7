"""What the commands share: the program's name and exit statuses, the one-line-error parser, the
``--level``, ``--seed`` and display arguments, and how frames are shown (``play.screen``)."""

from __future__ import annotations

import argparse
import os
import re
from typing import NoReturn, TextIO

from ..core.goals import GOAL_MODES
from ..play.screen import DEFAULT_DELAY, Display, isatty
from ..training.checks import CELL_CHOICES
from .checks import SEED_HELP, level_spec, positive_int, seconds, seed_int

PROG = "babyrobot-marl"
EXIT_USAGE = 2  # bad input, as argparse uses
EXIT_INTERRUPTED = 130  # Ctrl-C, as a shell reports it


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are one line: no usage block, no traceback."""

    def error(self, message: str) -> NoReturn:
        # argparse quotes the arguments it rejects: keep a newline or a huge argument from breaking the one line.
        # One shape for every error line, argparse's and the commands' own: "babyrobot-marl: error: --flag: ..."
        text = re.sub(r"^argument (\S+?)(?:/\S+)?: ", r"\1: ", one_line(message))
        self.exit(EXIT_USAGE, f"{PROG}: error: {text} (see '{self.prog} --help')\n")


def add_memory_args(p: argparse.ArgumentParser) -> None:
    """``train``'s ways for a robot to remember: its last action (``--memory``), its trail (``--trail``), or a
    recurrent net."""
    p.add_argument("--memory", action="store_true",
                   help="--observe local: the net also reads the robot's own last action (it can tell the way it came)")
    p.add_argument("--trail", action="store_true",
                   help="--observe local: the net also reads the robot's trail, the order in which it stood on the "
                   "cells next to it this episode (it can tell where it has not been)")
    p.add_argument("--recurrent", action="store_true",
                   help="--observe local: a recurrent net (a GRU between the input layers and the heads): each robot "
                   "remembers its whole episode")
    p.add_argument("--hidden", type=positive_int, default=None, metavar="N",
                   help="--recurrent: the cell's hidden units (default: 32)")
    p.add_argument("--cell", choices=CELL_CHOICES, default=None,
                   help="--recurrent: the cell, a GRU (default) or a minGRU, whose gates read the input alone (several "
                   "times the steps per second)")


def one_line(err: BaseException | str, limit: int = 1000) -> str:
    """The message on one line, at most ``limit`` characters."""
    text = " ".join(str(err).split()) or type(err).__name__
    return text if len(text) <= limit else f"{text[: limit - 40]}... ({len(text):,} characters)"


# The envs' and trainers' argument names, as the command line spells them: an error from below names the flag
FLAGS = {
    "n_robots": "--robots", "max_cycles": "--max-cycles", "max_steps": "--max-steps", "view_radius": "--view-radius",
    "near_radius": "--near-radius", "collisions": "--collisions", "start": "--start", "observe": "--observe",
    "hint": "--hint", "memory": "--memory", "trail": "--trail", "imitate": "--imitate", "recurrent": "--recurrent",
    "hidden": "--hidden", "cell": "--cell",
    "seed": "--seed", "level": "--level", "goals": "--goals", "lifelong": "--lifelong", "finished": "--finished",
}
# the flag that names a policy, by command (a saved policy's errors start "policy:"); `levels` takes a NAME
POLICY_FLAGS = {"play": "--policy", "race": "--policies", "evaluate": "POLICY", "train": "--load"}
LEVEL_FLAGS = {"levels": "NAME"}


def _flag_value(m: re.Match) -> str:
    return f"{FLAGS[m[1]]} {m[2] if m[2] is not None else m[3]}"


def flag_words(message: str, command: str | None = None) -> str:
    """An error of the Python API in the command line's words: ``n_robots: ...`` becomes ``--robots: ...``,
    ``start='fill'`` becomes ``--start fill``, ``hint=True`` becomes ``--hint``."""
    names = "|".join(FLAGS)
    text = re.sub(rf"\b({names})=(True|False)\b", lambda m: FLAGS[m[1]] if m[2] == "True" else f"no {FLAGS[m[1]]}", message)
    text = re.sub(rf"\b({names})=(?:'([^']*)'|([^\s,;)]+))", _flag_value, text)
    text = re.sub(r"\b(n_robots|max_cycles|max_steps|view_radius|near_radius)\b", lambda m: FLAGS[m[1]], text)
    level = LEVEL_FLAGS.get(command or "", "--level")
    text = re.sub(r"^level( file| text)?\b", lambda m: level + (m[1] or ""), text)
    text = re.sub(r"^((?:--level|NAME) '[^']*'): (width|height): ", r"\1: ", text)  # a maze name's side
    text = text.removesuffix(", or pass a Level or a level text")  # Python's other ways to give a level
    first, colon, rest = text.partition(":")
    if colon and first in FLAGS:
        return FLAGS[first] + colon + rest
    if colon and first == "policy" and command in POLICY_FLAGS:
        return POLICY_FLAGS[command] + colon + rest
    return text


# ------------------------------------------------------------------------ shared arguments
def add_level_arg(p: argparse.ArgumentParser, default: str = "default", family: str = "a new square maze of side A..B "
                  "for every episode, drawn from --seed") -> None:
    """``--level``; ``family`` says what ``maze:A..B`` gives this command (a command of one level: that level)."""
    p.add_argument(
        "--level",
        default=default,
        type=level_spec,
        metavar="NAME|FILE|maze:A..B",
        help=f"a built-in level (see '{PROG} levels'), maze-WxH[-sSEED], the path of a level text file or of a "
        f"MovingAI .map file, a grid map (rows of '.' and '#'; it has no exit), or maze:A..B: {family}; gridmaze:A..B "
        f"the same with grid mazes (blocked cells, loops, no exit: --goals own) (default: {default})",
    )


def add_goal_args(p: argparse.ArgumentParser, what: str = "race", policy_default: bool = False) -> None:
    """``--goals`` and ``--lifelong``; ``what`` names the command's run in their help (a race, an episode);
    ``policy_default``: ``--goals`` left out is the saved policy's own task (None here; the command reads it)."""
    default = "the task a saved policy was trained for, else exit" if policy_default else "default"
    p.add_argument("--goals", choices=GOAL_MODES, default=None if policy_default else "exit",
                   help=f"exit: the robots {what} to the level's exits ({default}); own: each robot has its own target "
                   "cell (drawn from --seed, free, distinct, reachable; the exits are floor), POGEMA's task")
    p.add_argument("--lifelong", action="store_true",
                   help="with --goals own: a robot on its target gets a new one and keeps going until the step limit "
                   "(POGEMA's lifelong task: throughput, targets reached per step)")


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
    p.add_argument("--all-frames", action="store_true",
                   help="into a file or pipe, print every frame (default there: the first and the last)")
    p.add_argument("--no-color", action="store_true", help="no ANSI colours (also: set the NO_COLOR environment variable)")


def display_of(args: argparse.Namespace, out: TextIO) -> Display:
    tty = isatty(out)
    colour = tty and not args.no_color and not os.environ.get("NO_COLOR")
    delay = args.delay if args.delay is not None else (DEFAULT_DELAY if tty else 0.0)
    return Display(colour=colour, clear=tty, delay=delay, ends_only=not tty and not args.all_frames)


def fresh_seed() -> int:
    return int.from_bytes(os.urandom(4), "little") >> 1  # < 2**31: short enough to retype
