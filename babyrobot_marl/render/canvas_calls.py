"""What the live canvas sends: operations as ipycanvas calls, with the fewest style changes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .glyphs import baseline_y, css_font, origin
from .paint import Stamp
from .shapes import Fill, Op, Text


def _css(colour: Sequence[int], alpha: float = 1.0) -> str:
    if alpha >= 1.0:
        return f"rgb({int(colour[0])}, {int(colour[1])}, {int(colour[2])})"
    return f"rgba({int(colour[0])}, {int(colour[1])}, {int(colour[2])}, {alpha:.3f})"


def _frame_bars(x0: int, y0: int, x1: int, y1: int, t: int) -> list[np.ndarray]:
    from .shapes import rect

    return [rect(x0, y0, x1, y0 + t), rect(x0, y1 - t, x1, y1),
            rect(x0, y0 + t, x0 + t, y1 - t), rect(x1 - t, y0 + t, x1, y1 - t)]  # fmt: skip


def marked_frame(r: Any, scene: Any, marked: int | None) -> list[Fill]:
    """The frame round the ``marked`` robot's cell in ``r``'s pixels, in its colour (under the robots)."""
    from .palette import robot_colour

    view = next((v for v in scene.robots if v.number == marked), None)
    if view is None:
        return []
    cs = r.cell_size
    x0, y0, t = view.cell[0] * cs, view.cell[1] * cs, max(2, cs // 16)
    return [Fill(p, robot_colour(r.theme, view.number)) for p in _frame_bars(x0 + t, y0 + t, x0 + cs - t, y0 + cs - t, t)]


class _Styles:
    """The font and fill style each layer was last given: setting an ipycanvas attribute costs
    tens of microseconds (a traitlet and a command), so unchanged ones are not sent again."""

    def __init__(self) -> None:
        self.last: dict[int, tuple[str, str]] = {}

    def reset(self) -> None:
        self.last.clear()

    def set(self, layer: Any, font: str, fill: str) -> None:
        old_font, old_fill = self.last.get(id(layer), ("", ""))
        if font != old_font:
            layer.font = font
            if not old_font:
                layer.text_align, layer.text_baseline = "left", "alphabetic"
        if fill != old_fill:
            layer.fill_style = fill
        self.last[id(layer)] = (font, fill)


def _rect(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    from .shapes import rect

    return rect(x0, y0, x1, y1)


def _send(layer: Any, ops: Sequence[Op], styles: _Styles) -> None:
    """``ops`` as canvas calls: all polygons in one ``fill_styled_polygons`` call (in order), then
    the texts (each element's text lies over its own shapes; elements do not overlap)."""
    fills: list[Fill] = []
    texts: list[Text] = []
    for op in ops:
        if isinstance(op, Stamp):
            for part in op.sprite.ops(op.x, op.y):
                (fills if isinstance(part, Fill) else texts).append(part)  # type: ignore[arg-type]
        elif isinstance(op, Fill):
            fills.append(op)
        else:
            texts.append(op)
    if fills:
        layer.fill_styled_polygons(
            np.concatenate([f.points for f in fills]),
            np.array([f.colour for f in fills], dtype=np.uint8),
            np.array([f.alpha for f in fills], dtype=np.float64),
            points_per_polygon=np.array([len(f.points) for f in fills]),
        )
    for t in sorted(texts, key=lambda t: (t.size, t.colour, t.alpha)):  # texts do not overlap: fewest style changes
        styles.set(layer, css_font(t.size), _css(t.colour, t.alpha))
        layer.fill_text(t.text, float(origin(t)[0]), float(baseline_y(t)))

