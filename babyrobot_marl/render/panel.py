"""The panel under the grid: the overlay's text lines, the colour bar of the values, the race legend.

``panel_sections(width, ...)`` lays them out top to bottom in a panel ``width`` pixels wide
(the grid's width: long lines wrap rather than being cut), as strips each drawn from its own
top; ``rgb_array`` caches the strips' images, the live canvas redraws only the strips that
changed. ``panel_height`` gives the panel's height without laying it out (the frame limit is
checked on it before anything is drawn).

The legend lists every robot of a race of up to ``LEGEND_ROWS`` robots, a row each in robot
order (icon and name, return, rank). A larger race's legend is compact (``compact_layout``):
entries side by side in as many columns as the width holds, at most ``COMPACT_LINES`` lines
(a small icon with its number, the return, the rank badge), every robot in robot order when
they fit, else the leaders (finished ones by rank, then racing ones by return) and a last
entry counting the rest ("+1,193 more").
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from .glyphs import advances, cap_height, fit, size_at_most, text_width
from .paint import Sprite, Stamp, flatten
from .palette import Theme, colour_map
from .shapes import Colour, Fill, Op, Text, rect, round_rect
from .sprites import MEDALS, OTHER_RANK, robot_sprite


@dataclass(frozen=True)
class LegendRow:
    """One robot in the legend: its number, a name (its policy, when known), return and rank (0: racing)."""

    number: int
    name: str
    ret: float
    rank: int
    racing: bool


LEGEND_ROWS = 8  # robots listed one a row; a larger race: its leaders, then a row counting the rest


COMPACT_LINES = 3  # beyond LEGEND_ROWS robots: entries side by side, on at most this many lines


def legend_rows(legend: Sequence[LegendRow], room: int = LEGEND_ROWS) -> tuple[list[LegendRow], str]:
    """The robots the legend lists in its ``room`` places, and the text of the place that counts
    the others ("" if none): all in robot order when they fit, else the leaders."""
    if len(legend) <= room:
        return list(legend), ""
    order = sorted(legend, key=lambda r: (r.rank == 0, r.rank, -r.ret, r.number))  # finished by rank, then by return
    shown, rest = order[: room - 1], order[room - 1 :]
    racing = sum(1 for r in rest if r.racing)
    finished = sum(1 for r in rest if r.rank)
    counts = [f"{k:,} {what}" for k, what in ((racing, "racing"), (finished, "finished")) if k]
    return shown, f"+{len(rest):,} more" + (f": {', '.join(counts)}" if counts else "")


@lru_cache(maxsize=64)
def compact_layout(width: int, cs: int, robots: int, ratio: int = 1) -> tuple[int, int]:
    """A compact legend's columns and lines for ``robots`` robots: as many columns as entries of
    a small icon, a return and a rank badge fit across ``width``, at most ``COMPACT_LINES`` lines."""
    m = metrics(cs, ratio)
    entry = 4 * m.pad + m.row_h + text_width("00 -000", m.size) + text_width("10th", m.size) + m.cap * 1.2
    cols = int(max(1, min(8, width // entry)))
    return cols, min(COMPACT_LINES, -(-robots // cols))


def ordinal(rank: int) -> str:
    return f"{rank}{'th' if 10 <= rank % 100 <= 20 else {1: 'st', 2: 'nd', 3: 'rd'}.get(rank % 10, 'th')}"


def text_size(cs: int) -> int:
    """The panel's type size for a grid of ``cs``-pixel cells."""
    return int(np.clip(round(cs * 0.21), 11, 16))


def wrap(line: str, width: float, size: int) -> list[str]:
    """``line`` broken at spaces (or anywhere, for a long word) into lines no wider than ``width``."""
    out: list[str] = []
    cur = ""
    for word in line.split(" "):
        trial = f"{cur} {word}" if cur else word
        if text_width(trial, size) <= width:
            cur = trial
            continue
        if cur:
            out.append(cur)
        if text_width(word, size) > width and len(word) > 1:  # pieces that fit, in one pass
            *pieces, word = _cut(word, width, size)
            out += pieces
        cur = word
    out.append(cur)
    return out


def _cut(word: str, width: float, size: int) -> list[str]:
    """``word`` in pieces each as wide as fits ``width`` (at least one character)."""
    ends = np.cumsum(advances(word, size))
    out, start, base = [], 0, 0.0
    while start < len(word):
        k = max(start + 1, int(np.searchsorted(ends, base + width, side="right")))
        out.append(word[start:k])
        base, start = float(ends[k - 1]), k
    return out


@lru_cache(maxsize=64)
def _wrapped(lines: tuple[str, ...], width: float, size: int) -> tuple[str, ...]:
    """The panel's lines wrapped (cached: the frame check and the drawing wrap them once)."""
    return tuple(part for line in lines for part in wrap(line, width, size))


@dataclass(frozen=True)
class Metrics:
    """The panel's type size and strip heights for a cell size (``ratio``: device pixels per CSS pixel)."""

    size: int
    cap: int
    pad: int
    line_h: int  # a text line
    bar_h: int  # the colour bar
    row_h: int  # a legend row
    head_h: int  # the legend's heading


@lru_cache(maxsize=64)
def metrics(cs: int, ratio: int = 1) -> Metrics:
    size = text_size(cs // ratio) * ratio
    cap = cap_height(size)[1]
    return Metrics(size, cap, max(4, size // 2), int(round(cap * 2.0)), int(round(cap * 3.6)),
                   int(round(max(cap * 2.6, 20.0 * ratio))), int(round(cap * 2.2)))  # fmt: skip


def panel_height(width: int, cs: int, lines: Sequence[str] = (), bar: bool = False, robots: int = 0, ratio: int = 1) -> int:
    """The height of ``panel_sections``' strips for these parts (``robots``: the legend's robots)."""
    if not lines and not bar and not robots:
        return 0
    m = metrics(cs, ratio)
    h = m.pad + len(_wrapped(tuple(lines), width - 2 * m.pad, m.size)) * m.line_h if lines else m.pad
    h += m.bar_h if bar else 0
    if robots > LEGEND_ROWS:
        h += compact_layout(width, cs, robots, ratio)[1] * m.row_h
    elif robots:
        h += m.head_h + robots * m.row_h
    return h + m.pad + (-(h + m.pad)) % ratio


@dataclass(frozen=True, eq=False)
class Section:
    """A horizontal strip of the panel, ``height`` whole pixels tall: ``build()`` gives its
    operations from its own top. The same ``key`` always builds the same strip (rgb_array
    caches strips by key: a legend row is drawn again only when its robot's row changes)."""

    key: tuple
    height: int
    background: Colour
    build: Callable[[], list[Op]]  # the operations over the background
    # or side by side pieces (x0, x1, key, build), each cached on its own (a legend row: its
    # robot and name, its return, its rank); ``build`` then draws them all
    parts: tuple[tuple[int, int, tuple, Callable[[], list[Op]]], ...] = ()


def panel_sections(
    width: int,
    cs: int,
    theme: Theme,
    lines: Sequence[str] = (),
    value_range: tuple[float, float] | None = None,
    legend: Sequence[LegendRow] = (),
    ratio: int = 1,
) -> list[Section]:
    """The panel's strips, top to bottom (none: no panel); ``ratio``: device pixels per CSS
    pixel (the canvas draws at 2: ``cs`` is then twice the cell size and so is the type)."""
    if not lines and value_range is None and not legend:
        return []
    m = metrics(cs, ratio)
    size, pad, line_h = m.size, m.pad, m.line_h
    bg = theme.panel
    out: list[Section] = []
    if lines:
        parts = _wrapped(tuple(lines), width - 2 * pad, size)

        def text_lines() -> list[Op]:
            return [Text(pad, pad + (k + 0.5) * line_h, part, size, theme.text, align="left") for k, part in enumerate(parts)]

        out.append(_section(("lines", tuple(parts)), pad + len(parts) * line_h, width, bg, text_lines))
    else:
        out.append(_section(("top",), pad, width, bg, list))
    if value_range is not None:
        h = m.bar_h
        out.append(_section(("bar", value_range), h, width, bg, lambda: _colour_bar(width, h, size, value_range, theme)))
    if len(legend) > LEGEND_ROWS:
        out += _compact_legend(width, cs, ratio, legend, theme)
    elif legend:
        rh, head = m.row_h, m.head_h
        cols = _columns(width, size, rh)
        out.append(_section(("legend",), head, width, bg, lambda: _legend_head(cols, head, size, theme)))
        for row in legend:
            out.append(_legend_row(cols, width, rh, size, row, theme))
    total = sum(sec.height for sec in out) + pad
    out.append(_section(("bottom", pad + (-total) % ratio), pad + (-total) % ratio, width, bg, list))  # whole CSS pixels
    return out


def legend_row_section(width: int, cs: int, theme: Theme, row: LegendRow, ratio: int = 1) -> Section:
    """The strip of one legend row, as ``panel_sections`` lays it out (to redraw a row alone)."""
    m = metrics(cs, ratio)
    return _legend_row(_columns(width, m.size, m.row_h), width, m.row_h, m.size, row, theme)


def _section(key: tuple, height: int, width: int, bg: Colour, build: Callable[[], list[Op]]) -> Section:
    return Section(key, height, bg, build)


def shifted(op: Op, dy: float) -> Op:
    """``op`` moved down by ``dy`` pixels."""
    if isinstance(op, Fill):
        return Fill(op.points + (0.0, dy), op.colour, op.alpha)
    if isinstance(op, Stamp):
        return Stamp(op.sprite, op.x, op.y + dy)
    return replace(op, y=op.y + dy)


def _colour_bar(width: int, h: int, size: int, vr: tuple, theme: Theme) -> list[Op]:
    """The colour bar: the overlay's label, then the colours from lowest to highest with ticks
    and their numbers under them (in the overlay's number format)."""
    from .overlay import Scale

    scale = vr if isinstance(vr, Scale) else Scale(float(vr[0]), float(vr[1]), "value", 0)
    lo, hi = scale.lo, scale.hi
    cap = cap_height(size)[1]
    pad = max(4, size // 2)
    small = size_at_most(max(7, size * 0.85))  # a 2x canvas asks for sizes the atlas lacks (27, 45)
    title = scale.label
    ends = [scale.format(lo), scale.format(hi)]
    x0 = pad + text_width(title, size) + 2 * pad + text_width(ends[0], small) / 2
    x1 = width - pad - text_width(ends[1], small) / 2
    bar_h = cap * 1.2
    top = pad * 0.6
    ops: list[Op] = [Text(pad, top + bar_h / 2, title, size, theme.text, align="left")]
    if x1 - x0 < 20:  # too narrow for a bar: the range in words
        ops.append(Text(x0 - text_width(ends[0], small) / 2, top + bar_h / 2, f"{ends[0]} .. {ends[1]}", size, theme.text,
                        align="left"))  # fmt: skip
        return ops
    n = 48
    colours = colour_map(np.linspace(0.0, 1.0, n), theme.colour_map, 0.0, 1.0)
    ops.append(Fill(rect(x0 - 1, top - 1, x1 + 1, top + bar_h + 1), theme.text))
    step = (x1 - x0) / n
    for k in range(n):
        ops.append(Fill(rect(x0 + k * step, top, x0 + (k + 1) * step + 0.6, top + bar_h), tuple(colours[k].tolist())))
    tick = max(2.0, cap * 0.45)
    label_y = top + bar_h + tick + 1 + cap_height(small)[1] / 2 + 1
    room = text_width(max(ends, key=len), small) + 2 * pad
    for v in ticks(lo, hi, max(2, min(6, int((x1 - x0) // room) + 1)), scale.digits):
        x = x0 if hi == lo else x0 + (v - lo) / (hi - lo) * (x1 - x0)
        ops.append(Fill(rect(x - 0.5, top + bar_h + 1, x + 0.5, top + bar_h + 1 + tick), theme.text))
        ops.append(Text(x, label_y, scale.format(v), small, theme.text))
    return ops


def ticks(lo: float, hi: float, most: int, digits: int | None = None) -> list[float]:
    """At most ``most`` round values from ``lo`` to ``hi``, both ends included (1, 2 or 5 times a power of ten apart;
    with ``digits``, the decimals they are written with, at least one unit of the last apart: no two print alike)."""
    if hi <= lo:
        return [lo]
    raw = (hi - lo) / max(1, most - 1)
    mag = 10 ** np.floor(np.log10(raw))
    step = next(m * mag for m in (1, 2, 5, 10) if m * mag >= raw)
    if digits is not None:
        step = max(step, 10.0**-digits)
    inner = [k * step for k in range(int(np.ceil(lo / step)), int(np.floor(hi / step)) + 1)]
    keep = [v for v in inner if min(v - lo, hi - v) >= step * 0.45]  # not crowding an end
    return [lo, *keep, hi]


@lru_cache(maxsize=64)
def _columns(width: int, size: int, rh: int) -> tuple[float, float, float, float]:
    """x of the robot icon's centre, the name (left), the return and the rank (right edges)."""
    pad = max(4, size // 2)
    x_rank = width - pad
    x_ret = width - pad - max(text_width("racing", size), text_width("10th", size)) - 2 * pad
    return pad + rh / 2, pad + rh + pad, x_ret, x_rank


def _legend_head(cols: tuple[float, float, float, float], h: int, size: int, theme: Theme) -> list[Op]:
    _, x_name, x_ret, x_rank = cols
    return [
        Text(x_name, h / 2, "robot", size, theme.text, align="left", alpha=0.7),
        Text(x_ret, h / 2, "return", size, theme.text, align="right", alpha=0.7),
        Text(x_rank, h / 2, "rank", size, theme.text, align="right", alpha=0.7),
    ]


@lru_cache(maxsize=2048)
def _legend_row(cols: tuple[float, float, float, float], width: int, rh: int, size: int, row: LegendRow, theme: Theme) -> Section:
    """A robot's row: icon and name, return, rank (three pieces: the return changes every step);
    cached: a race's rows come back (the same returns at the same step of every race)."""
    x_icon, x_name, x_ret, x_rank = cols
    cap = cap_height(size)[1]
    cy = rh / 2
    pad = max(4, size // 2)
    split_ret = min(max(int(x_ret - text_width("-0000", size) - pad), 0), width)  # the name ends before
    split_rank = min(max(int(x_ret + 2), split_ret), width)  # the return ends before; the rank after
    name = f"{row.number} {row.name}" if row.name else f"robot {row.number}"
    pose = "finished" if row.rank else "idle"
    ret = f"{row.ret + 0.0:g}"

    def who() -> list[Op]:
        s = fit(name, split_ret - x_name - 2, cap, largest=size, smallest=7) or 7
        icon = robot_sprite(theme, row.number, 0, pose, True, round(rh * 1.05, 2))
        return [Stamp(icon, x_icon, cy), Text(x_name, cy, name, s, theme.text, align="left")]

    def score() -> list[Op]:
        return [Text(x_ret, cy, ret, size, theme.text, align="right")]

    def rank() -> list[Op]:
        if row.rank:
            return [Stamp(_badge(size, row.rank, theme), x_rank - text_width("10th", size) / 2, cy)]
        return [Text(x_rank, cy, "racing" if row.racing else "-", size, theme.text, align="right", alpha=0.7)]

    parts = (
        (0, split_ret, ("who", row.number, name, pose), who),
        (split_ret, split_rank, ("return", ret), score),
        (split_rank, width, ("rank", row.rank, row.racing), rank),
    )
    return Section(("row", row), rh, theme.panel, lambda: [*who(), *score(), *rank()], parts)


def _compact_legend(width: int, cs: int, ratio: int, legend: Sequence[LegendRow], theme: Theme) -> list[Section]:
    """The compact legend's lines: entries side by side, the last place counting the others."""
    m = metrics(cs, ratio)
    cols, lines = compact_layout(width, cs, len(legend), ratio)
    shown, more = legend_rows(legend, cols * lines)
    edges = [round(j * width / cols) for j in range(cols + 1)]
    out = []
    for line in range(lines):
        parts = []
        for j in range(cols):
            k, x0, x1 = line * cols + j, edges[j], edges[j + 1]
            if k < len(shown):
                key, draw = ("entry", x1 - x0, shown[k]), _entry(x1 - x0, m.row_h, m.size, shown[k], theme)
            elif k == len(shown) and more:
                key, draw = ("count", x1 - x0, more), _count(x1 - x0, m.row_h, m.size, more, theme)
            else:
                key, draw = ("blank",), list
            parts.append((x0, x1, key, _at(draw, x0)))
        key = ("entries", *(part[2] for part in parts))

        def build(parts: list = parts) -> list[Op]:
            return [op for *_, b in parts for op in b()]

        out.append(Section(key, m.row_h, theme.panel, build, tuple(parts)))
    return out


def _entry(w: int, rh: int, size: int, row: LegendRow, theme: Theme) -> Callable[[], list[Op]]:
    """A compact entry, from its own left edge: the robot's icon, its number (and name, if it has
    one and room is left), its return, its rank badge (a dash: out without finishing)."""
    pad = max(4, size // 2)
    cap, cy = cap_height(size)[1], rh / 2
    x_rank = w - pad - (text_width("10th", size) + cap * 1.2) / 2
    x_ret = w - 2 * pad - text_width("10th", size) - cap * 1.2

    def build() -> list[Op]:
        pose = "finished" if row.rank else "idle"
        ops: list[Op] = [Stamp(robot_sprite(theme, row.number, 0, pose, True, round(rh * 1.05, 2)), pad + rh / 2, cy)]
        ret = f"{row.ret + 0.0:g}"
        ops.append(Text(x_ret, cy, ret, size, theme.text, align="right"))
        room = x_ret - text_width(ret, size) - pad - (pad + rh)
        label = f"{row.number} {row.name}" if row.name else str(row.number)
        s = fit(label, room, cap, largest=size, smallest=7) if room > 0 else None
        if s is None:  # no room for the name: the number alone
            label, s = str(row.number), fit(str(row.number), max(room, 1.0), cap, largest=size, smallest=7) or 7
        ops.append(Text(pad + rh, cy, label, s, theme.text, align="left"))
        if row.rank:
            ops.append(Stamp(_badge(size, row.rank, theme), x_rank, cy))
        elif not row.racing:
            ops.append(Text(x_rank, cy, "-", size, theme.text, alpha=0.7))
        return ops

    return build


def _count(w: int, rh: int, size: int, text: str, theme: Theme) -> Callable[[], list[Op]]:
    """The compact legend's last place: how many robots it does not list (the counts if they fit)."""
    pad = max(4, size // 2)

    def build() -> list[Op]:
        cap = cap_height(size)[1]
        words = text
        s = fit(words, w - 2 * pad, cap, largest=size, smallest=7)
        if s is None:
            words = text.split(":")[0]
            s = fit(words, w - 2 * pad, cap, largest=size, smallest=7) or 7
        return [Text(pad, rh / 2, words, s, theme.text, align="left", alpha=0.7)]

    return build


def _at(build: Callable[[], list[Op]], x0: int) -> Callable[[], list[Op]]:
    """``build``'s operations moved right to ``x0`` (the pieces of a section draw in its coordinates)."""
    return lambda: [shifted_x(op, x0) for op in build()]


def shifted_x(op: Op, dx: float) -> Op:
    """``op`` moved right by ``dx`` pixels."""
    if isinstance(op, Fill):
        return Fill(op.points + (dx, 0.0), op.colour, op.alpha)
    if isinstance(op, Stamp):
        return Stamp(op.sprite, op.x + dx, op.y)
    return replace(op, x=op.x + dx)


@lru_cache(maxsize=128)
def _badge(size: int, rank: int, theme: Theme) -> Sprite:
    """A rank in a rounded badge: gold, silver, bronze, then grey."""
    label = ordinal(rank)
    cap = cap_height(size)[1]
    w, h = text_width(label, size) + cap * 1.2, cap * 1.9
    fill = MEDALS.get(rank, OTHER_RANK)
    return flatten(
        [
            Fill(round_rect(-w / 2 - 1, -h / 2 - 1, w / 2 + 1, h / 2 + 1, h / 2), theme.robot_ink),
            Fill(round_rect(-w / 2, -h / 2, w / 2, h / 2, h / 2), fill),
            Text(0.0, 0.0, label, size, (20, 20, 24)),
        ]
    )
