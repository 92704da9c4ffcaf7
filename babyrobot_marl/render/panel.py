"""The panel under the grid: the overlay's text lines, the colour bar of the values, the race legend.

``panel_ops(width, ...)`` lays them out top to bottom in a panel ``width`` pixels wide (the
grid's width: long lines wrap rather than being cut) and returns the operations with the
panel's height; the panel's own top is y = 0.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .glyphs import cap_height, fit, text_width
from .paint import Fill, Op, Text, circle, rect, round_rect
from .palette import Theme, colour_map, robot_colour
from .robot import robot


@dataclass(frozen=True)
class LegendRow:
    """One robot in the legend: its number, a name (its policy, when known), return and rank (0: racing)."""

    number: int
    name: str
    ret: float
    rank: int
    racing: bool


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
        while text_width(word, size) > width and len(word) > 1:
            k = len(word)
            while k > 1 and text_width(word[:k], size) > width:
                k -= 1
            out.append(word[:k])
            word = word[k:]
        cur = word
    out.append(cur)
    return out


def panel_ops(
    width: int,
    cs: int,
    theme: Theme,
    lines: Sequence[str] = (),
    value_range: tuple[float, float] | None = None,
    legend: Sequence[LegendRow] = (),
    ratio: int = 1,
) -> tuple[list[Op], int]:
    """The panel's operations and height in pixels (0: no panel); ``ratio``: device pixels per
    CSS pixel (the canvas draws at 2: ``cs`` is then twice the cell size and so is the type)."""
    if not lines and value_range is None and not legend:
        return [], 0
    size = text_size(cs // ratio) * ratio
    cap = cap_height(size)[1]
    pad = max(4, size // 2)
    line_h = int(round(cap * 2.0))
    ops: list[Op] = []
    y = pad
    for line in lines:
        for part in wrap(line, width - 2 * pad, size):
            ops.append(Text(pad, y + line_h / 2, part, size, theme.text, align="left"))
            y += line_h
    if value_range is not None:
        y += _colour_bar(ops, width, y, size, value_range, theme)
    if legend:
        y += _legend(ops, width, y, size, legend, theme, ratio)
    height = int(y + pad)
    height += (-height) % ratio  # whole CSS pixels
    return [Fill(rect(0, 0, width, height), theme.panel), *ops], height


def _colour_bar(ops: list[Op], width: int, y: float, size: int, vr: tuple[float, float], theme: Theme) -> float:
    from .overlay import format_value

    lo, hi = vr
    cap = cap_height(size)[1]
    h = cap * 2.2
    pad = max(4, size // 2)
    left, right = f"{format_value(lo)}", f"{format_value(hi)}"
    title = "value"
    x0 = pad + text_width(title, size) + pad + text_width(left, size) + pad
    x1 = width - pad - text_width(right, size) - pad
    cy = y + h / 2
    ops.append(Text(pad, cy, title, size, theme.text, align="left"))
    if x1 - x0 < 20:  # too narrow for a bar: the range in words
        ops.append(Text(x0 - pad, cy, f"{left} .. {right}", size, theme.text, align="left"))
        return h
    ops.append(Text(x0 - pad / 2, cy, left, size, theme.text, align="right"))
    ops.append(Text(x1 + pad / 2, cy, right, size, theme.text, align="left"))
    n = 48
    colours = colour_map(np.linspace(0.0, 1.0, n), theme.colour_map, 0.0, 1.0)
    bar_h = cap * 1.3
    ops.append(Fill(rect(x0 - 1, cy - bar_h / 2 - 1, x1 + 1, cy + bar_h / 2 + 1), theme.text))
    step = (x1 - x0) / n
    for k in range(n):
        ops.append(
            Fill(rect(x0 + k * step, cy - bar_h / 2, x0 + (k + 1) * step + 0.6, cy + bar_h / 2), tuple(colours[k].tolist()))
        )
    return h


def _legend(ops: list[Op], width: int, y: float, size: int, rows: Sequence[LegendRow], theme: Theme, ratio: int) -> float:
    cap = cap_height(size)[1]
    rh = max(cap * 2.6, 20.0 * ratio)
    pad = max(4, size // 2)
    x_rank = width - pad
    x_ret = width - pad - max(text_width("racing", size), text_width("10th", size)) - 2 * pad
    x_name = pad + rh + pad
    ops.append(Text(x_name, y + cap, "robot", size, theme.text, align="left", baseline="middle", alpha=0.7))
    ops.append(Text(x_ret, y + cap, "return", size, theme.text, align="right", alpha=0.7))
    ops.append(Text(x_rank, y + cap, "rank", size, theme.text, align="right", alpha=0.7))
    header = cap * 2.2
    y += header
    for k, row in enumerate(rows):
        cy = y + (k + 0.5) * rh
        colour = robot_colour(theme, row.number)
        ops.extend(robot(pad + rh / 2, cy, rh * 1.05, theme, colour, 0, "finished" if row.rank else "idle", row.number))
        name = f"{row.number} {row.name}" if row.name else f"robot {row.number}"
        room = x_ret - text_width("-000", size) - pad - x_name
        s = fit(name, room, cap, largest=size, smallest=7) or 7
        ops.append(Text(x_name, cy, name, s, theme.text, align="left"))
        ops.append(Text(x_ret, cy, f"{row.ret + 0.0:g}", size, theme.text, align="right"))
        if row.rank:
            ops += _badge(x_rank - text_width("10th", size) / 2, cy, size, row.rank, theme)
        else:
            ops.append(Text(x_rank, cy, "racing" if row.racing else "-", size, theme.text, align="right", alpha=0.7))
    return header + len(rows) * rh


MEDALS = {1: (240, 190, 40), 2: (190, 196, 206), 3: (205, 130, 70)}


def _badge(cx: float, cy: float, size: int, rank: int, theme: Theme) -> list[Op]:
    """A rank in a rounded badge: gold, silver, bronze, then grey."""
    label = ordinal(rank)
    cap = cap_height(size)[1]
    w, h = text_width(label, size) + cap * 1.2, cap * 1.9
    fill = MEDALS.get(rank, (150, 154, 166))
    return [
        Fill(round_rect(cx - w / 2 - 1, cy - h / 2 - 1, cx + w / 2 + 1, cy + h / 2 + 1, h / 2), theme.robot_ink),
        Fill(round_rect(cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2, h / 2), fill),
        Text(cx, cy, label, size, (20, 20, 24)),
    ]


def rank_badge(cx: float, cy: float, r: float, rank: int, theme: Theme) -> list[Op]:
    """The round rank badge pinned to a finished robot on the board."""
    fill = MEDALS.get(rank, (150, 154, 166))
    ops: list[Op] = [Fill(circle(cx, cy, r + max(1.0, r * 0.15)), theme.robot_ink), Fill(circle(cx, cy, r), fill)]
    s = fit(str(rank), r * 1.5, r * 1.1, largest=30, smallest=6)
    if s is not None:
        ops.append(Text(cx, cy, str(rank), s, (20, 20, 24)))
    return ops


def swatch(cx: float, cy: float, r: float, number: int, theme: Theme) -> list[Op]:
    colour = robot_colour(theme, number)
    return [Fill(round_rect(cx - r, cy - r, cx + r, cy + r, r * 0.3), theme.robot_ink), Fill(circle(cx, cy, r * 0.8), colour)]
