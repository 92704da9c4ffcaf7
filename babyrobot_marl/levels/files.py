"""Levels from what a user types: a built-in name, ``maze-WxH[-sSEED]``, a level text, a grid map, or a file.

``read_level_file`` reads at most ``MAX_LEVEL_TEXT_CHARS`` bytes of a regular file and refuses
anything else (a directory, a FIFO that would block, ``/dev/zero`` that never ends, a binary
file) with one clear ``ValueError``; ``load_level`` decides what a spec means. Used by the
command line; the error messages never echo a huge input in full.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from ..core.checks import MAX_LEVEL_TEXT_CHARS, shown
from ..core.grid import looks_like_grid_map
from ..core.level import Level, looks_like_level_text
from . import builtin
from .checks import PATH_SHOWN, cannot_read, check_regular_file, too_large

# os.stat errors that mean "no file by that name" rather than "a file we may not read"
_NOT_A_FILE = {errno.ENOENT, errno.ENOTDIR, errno.ENAMETOOLONG, errno.ELOOP}


def read_level_file(path: str | os.PathLike) -> Level:
    """The level in a text file (UTF-8, a BOM allowed), its name the file's stem: a MovingAI ``.map``
    file or a grid map's rows are read as grid maps (``Level.from_grid``), anything else as a level text."""
    spec = os.fspath(path)
    text = _read_text(spec)
    try:
        if spec.endswith(".map") or looks_like_grid_map(text):
            return Level.from_grid(text, name=Path(spec).stem)
        return Level.from_ascii(text, name=Path(spec).stem)
    except ValueError as err:
        raise ValueError(f"level file {_path(spec)}: {err}") from None


def _read_text(spec: str) -> str:
    try:
        info = os.stat(spec)
    except (OSError, ValueError) as err:  # ValueError: an embedded NUL character
        raise ValueError(cannot_read(spec, _reason(err))) from None
    check_regular_file(spec, info)
    try:
        # O_NONBLOCK: should the path have become a FIFO since the stat, opening it does not hang
        fd = os.open(spec, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as err:
        raise ValueError(cannot_read(spec, _reason(err))) from None
    with os.fdopen(fd, "rb") as f:
        check_regular_file(spec, os.fstat(f.fileno()))
        data = f.read(MAX_LEVEL_TEXT_CHARS + 1)  # bounded, whatever the file claims its size is
    if len(data) > MAX_LEVEL_TEXT_CHARS:
        raise ValueError(too_large(spec))
    if b"\0" in data:
        raise ValueError(cannot_read(spec, "it is a binary file (it holds NUL bytes), not a level text"))
    try:
        return data.decode("utf-8-sig")  # a BOM from some editors is not part of the level
    except UnicodeDecodeError as err:
        raise ValueError(cannot_read(spec, f"it is not UTF-8 text (byte {data[err.start]:#04x} at offset {err.start})")) from None


def _path(spec: str) -> str:
    return spec if len(spec) <= PATH_SHOWN else shown(spec, PATH_SHOWN)


def _reason(err: Exception) -> str:
    return err.strerror if isinstance(err, OSError) and err.strerror else str(err)


def _looks_like_path(spec: str) -> bool:
    return bool(Path(spec).suffix) or os.sep in spec or "/" in spec


def load_level(spec: str) -> Level:
    """A level from a built-in name, ``maze-WxH[-sSEED]``, a level text (several lines), a grid map, or a
    file path (a level text, or a MovingAI ``.map`` file)."""
    if not isinstance(spec, str):
        raise TypeError(f"level: expected a level name, a level text or a file path (str), got {type(spec).__name__}")
    if looks_like_grid_map(spec):  # rows of "." and "#" (one row too): POGEMA's maps
        try:
            return Level.from_grid(spec, name="(grid map)")
        except ValueError as err:
            raise ValueError(f"level: grid map: {err}") from None
    if looks_like_level_text(spec):  # "+-+-+\r|S E|\r+-+-+" is a text, not a name
        try:
            return Level.from_ascii(spec, name="(level text)")  # the name summaries print, not the text
        except ValueError as err:
            raise ValueError(f"level text: {err}") from None
    try:
        info = os.stat(spec)
    except OSError as err:
        if err.errno not in _NOT_A_FILE:
            raise ValueError(cannot_read(spec, _reason(err))) from None
        info = None
    except ValueError:  # an embedded NUL character: no file has that name
        info = None
    if info is not None and (stat.S_ISREG(info.st_mode) or _looks_like_path(spec)):
        return read_level_file(spec)  # a regular file, or a path that is a directory, FIFO or device: say so
    if info is None and _looks_like_path(spec):  # meant as a file: say so rather than "unknown level"
        raise ValueError(f"level: no such level file {shown(spec, PATH_SHOWN)}")
    try:
        return builtin.get(spec)
    except ValueError as err:
        if not str(err).startswith("level: unknown level"):
            raise  # e.g. a maze size out of range: the message names the level already
        raise ValueError(
            f"level: unknown level {shown(spec)} and no file of that name; known levels: {', '.join(builtin.names())} "
            "(and maze-WxH or maze-WxH-sSEED for any size and seed)"
        ) from None
