"""The panel's room a live canvas keeps for an episode, so that it does not grow mid-episode."""

from __future__ import annotations

from collections.abc import Sequence

from .annotate import value_range
from .overlay import Overlay
from .panel import LegendRow, panel_sections
from .rgb import RgbRenderer


def panel_room(r: RgbRenderer, overlay: Overlay, legend: Sequence[LegendRow], ratio: int, lines: int) -> int:
    """The panel's height, in ``r``'s pixels, for an episode that starts under ``overlay`` with
    ``legend``: its text lines, colour bar and legend; with ``lines`` > 0, at least room for a
    colour bar under its lines, or for ``lines`` lines of text (a program may show values or a
    step's lines mid-episode)."""
    text, bar = overlay.panel, value_range(overlay) is not None

    def height(text: Sequence[str], bar: bool) -> int:
        sections = panel_sections(r.width, r.cell_size, r.theme, text, (0.0, 1.0) if bar else None, legend, ratio)
        return sum(sec.height for sec in sections)

    if lines <= 0:
        return height(text, bar)
    return max(height(text, True), height(text or ("0",) * lines, False))
