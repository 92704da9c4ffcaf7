"""The panel under the grid: the overlay's text lines, the colour bar of the values, the race legend.

``panel_sections(width, ...)`` lays them out top to bottom in a panel ``width`` pixels wide
(the grid's width: long lines wrap rather than being cut), as strips each drawn from its own
top; ``rgb_array`` caches the strips' images, the live canvas redraws only the strips that
changed. ``panel_height`` gives the panel's height without laying it out (the frame limit is
checked on it before anything is drawn).

The legend lists every robot of a race of up to ``LEGEND_ROWS`` robots, in robot order; a
larger race's legend stays as tall: its ``LEGEND_ROWS - 1`` leaders (finished ones by rank,
then racing ones by return), then one row counting the rest ("+1,193 more: ...").
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from .glyphs import advances, cap_height, fit, text_width
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


def legend_rows(legend: Sequence[LegendRow]) -> tuple[list[LegendRow], str]:
    """The rows the legend lists, and the text of the row that counts the others ("" if none)."""
    if len(legend) <= LEGEND_ROWS:
        return list(legend), ""
    order = sorted(legend, key=lambda r: (r.rank == 0, r.rank, -r.ret, r.number))  # finished by rank, then by return
    shown, rest = order[: LEGEND_ROWS - 1], order[LEGEND_ROWS - 1 :]
    racing = sum(1 for r in rest if r.racing)
    finished = sum(1 for r in rest if r.rank)
    counts = [f"{k:,} {what}" for k, what in ((racing, "racing"), (finished, "finished")) if k]
    return shown, f"+{len(rest):,} more" + (f": {', '.join(counts)}" if counts else "")


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
    h += m.head_h + (min(robots, LEGEND_ROWS) * m.row_h) if robots else 0
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
    if legend:
        rh, head = m.row_h, m.head_h
        cols = _columns(width, size, rh)
        out.append(_section(("legend",), head, width, bg, lambda: _legend_head(cols, head, size, theme)))
        rows, more = legend_rows(legend)
        for row in rows:
            out.append(_legend_row(cols, width, rh, size, row, theme))
        if more:
            out.append(_section(("more", more, rh), rh, width, bg, lambda: _legend_more(cols, width, rh, size, more, theme)))
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
    from .overlay import Scale, format_value

    scale = vr if isinstance(vr, Scale) else Scale(float(vr[0]), float(vr[1]), "value", 0)
    lo, hi = scale.lo, scale.hi
    cap = cap_height(size)[1]
    pad = max(4, size // 2)
    small = max(7, int(size * 0.85))
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
    for v in ticks(lo, hi, max(2, min(6, int((x1 - x0) // room) + 1))):
        x = x0 if hi == lo else x0 + (v - lo) / (hi - lo) * (x1 - x0)
        ops.append(Fill(rect(x - 0.5, top + bar_h + 1, x + 0.5, top + bar_h + 1 + tick), theme.text))
        ops.append(Text(x, label_y, scale.format(v) if v in (lo, hi) else format_value(v, scale.digits), small, theme.text))
    return ops


def ticks(lo: float, hi: float, most: int) -> list[float]:
    """At most ``most`` round values from ``lo`` to ``hi``, both ends included (1, 2 or 5 times a power of ten apart)."""
    if hi <= lo:
        return [lo]
    raw = (hi - lo) / max(1, most - 1)
    mag = 10 ** np.floor(np.log10(raw))
    step = next(m * mag for m in (1, 2, 5, 10) if m * mag >= raw)
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


def _legend_more(cols: tuple[float, float, float, float], width: int, rh: int, size: int, text: str, theme: Theme) -> list[Op]:
    """The row that counts the robots the legend does not list."""
    _, x_name, _, _ = cols
    room, cap = width - x_name - max(4, size // 2), cap_height(size)[1]
    s = fit(text, room, cap, largest=size, smallest=7)
    if s is None:  # too narrow for the counts: the number alone
        text = text.split(":")[0]
        s = fit(text, room, cap, largest=size, smallest=7) or 7
    return [Text(x_name, rh / 2, text, s, theme.text, align="left", alpha=0.7)]


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
