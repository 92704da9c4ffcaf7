"""``babyrobot-marl levels``: the built-in levels as a table, or one level's text."""

from __future__ import annotations

import argparse
from typing import TextIO

from ..core.level import Level
from ..levels import get, names
from ..levels.files import load_level
from ..levels.sources import parse_level_family
from .common import PROG


def level_of(spec: str, seed: int | None) -> Level:
    """The one level of ``--level`` for a command that runs one: a name or a file, or for a family spec
    (``maze:A..B``) the level drawn from it by a generator seeded with ``seed``, as an env seeded so draws it."""
    family = parse_level_family(spec)
    if family is None:
        return load_level(spec)
    from ..envs.starts import new_generator

    return family(new_generator(seed))


def level_label(level: Level, spec: str) -> str:
    """How a summary names the level of ``--level spec``: its name, else the spec when it is one short line
    (a file's path), else "a grid map" (the rows given on the command line)."""
    if level.name:
        return level.name
    return spec if "\n" not in spec and len(spec) <= 80 else f"a {level.width}x{level.height} grid map"


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "levels",
        help="list the built-in levels, or show one",
        description="List the built-in levels, or print one level's text.",
    )
    p.add_argument(
        "name", nargs="?", metavar="NAME", help="print this level's text (a built-in name, maze-WxH[-sSEED] or a file)"
    )
    p.add_argument("--show", metavar="NAME", help="the same as giving NAME")
    p.set_defaults(func=run)


def _features(level: Level) -> str:
    kinds = [
        ("walls", level.walls),
        ("glass", level.glass),
        ("puddles", level.small_puddles | level.large_puddles),
        ("blocked", level.blocked),
    ]
    return ", ".join(name for name, items in kinds if items) or "-"


def run(args: argparse.Namespace, out: TextIO) -> int:
    if args.name and args.show and args.name != args.show:
        raise ValueError(f"levels: give one level to show, got {args.name!r} and --show {args.show!r}")
    name = args.name or args.show
    if name:
        out.write(load_level(name).to_ascii() + "\n")
        return 0
    rows = [("name", "size", "starts", "exits", "features")]
    for n in names():
        lv = get(n)
        rows.append((n, f"{lv.width}x{lv.height}", str(len(lv.starts)), str(len(lv.exits)), _features(lv)))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]
    for r in rows:
        out.write("  ".join(c.ljust(w) for c, w in zip(r[:-1], widths, strict=True)) + "  " + r[-1] + "\n")
    out.write(f"\nalso maze-WxH and maze-WxH-sSEED for any size and seed; show one with '{PROG} levels NAME'\n")
    return 0
