"""``rgb_array`` frames in pure numpy, drawn from the same operations as the live canvas.

A frame is ``uint8[height * cell_size (+ panel), width * cell_size, 3]``, bottom to top:

1. the level (``picture.level_ops``) with the overlay's tints, arrows and numbers
   (``annotate``) and the START / EXIT labels: one static image per overlay, drawn once;
2. the robots (``scene``): each pose is rasterised once per size into an anti-aliased sprite
   and blended at its cell;
3. the labels again over any robot, and the marks of collisions;
4. the panel under the grid (``panel``): the overlay's text lines, the colour bar of the
   values, the race legend; drawn once per content.

The same state always gives the same bytes. Themes are data (``palette``).
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Sequence

import numpy as np

from ..core.level import Cell, Level
from . import annotate
from .checks import (  # noqa: F401  (the limits and checks are read from here too)
    MAX_CELL_SIZE,
    MAX_FRAME_PIXELS,
    MIN_CELL_SIZE,
    auto_cell_size,
    check_cell_size,
    check_frame_size,
    check_overlay_frame,
)
from .overlay import Overlay
from .paint import Patch, blend, paint, patch, to_uint8
from .palette import THEMES, Theme, resolve_theme
from .panel import panel_sections
from .picture import feature_ops, floor_ops, label_band, label_ops, level_ops
from .scene import Scene, as_scene, glide, robot_sprites
from .shapes import Op, Text

__all__ = ["MAX_CELL_SIZE", "MAX_FRAME_PIXELS", "MIN_CELL_SIZE", "THEMES", "RgbRenderer", "Theme", "resolve_theme"]



class RgbRenderer:
    """Draws one level at one cell size and theme; ``frame(scene_or_robots, overlay)`` returns a fresh image."""

    def __init__(self, level: Level, cell_size: int | None = None, theme: str | Theme = "light"):
        self.level = level
        self.cell_size = cs = check_cell_size(cell_size, level)
        self.theme = resolve_theme(theme)
        self.width, self.grid_height = level.width * cs, level.height * cs
        self.labels: list[Op] = label_ops(level, cs, self.theme)
        self.labelled = frozenset((int(op.x // cs), int(op.y // cs)) for op in self.labels if isinstance(op, Text))
        self.label_top = label_band(cs)[1] / cs  # robots sharing a labelled cell stand below this
        self.background = self._draw([*level_ops(level, cs, self.theme), *self.labels])
        self._label_patches = self._patches(self.labels)
        self._static: tuple[Overlay | None, np.ndarray] = (None, self.background)
        self._panels: OrderedDict[object, np.ndarray] = OrderedDict()
        self._tiles: OrderedDict[tuple, tuple] = OrderedDict()  # cells with a robot drawn in, by content

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.background.shape  # type: ignore[return-value]

    # ------------------------------------------------------------------ frames
    def frame(self, robots: Scene | Sequence[Cell | None] = (), overlay: Overlay | None = None, t: float = 1.0) -> np.ndarray:
        """The level with the scene's robots (or robot ``i`` at ``robots[i]``; None: not drawn),
        under the overlay's labels and over its tints, and the panel below when there is one.
        ``t`` < 1: the robots that moved this step a fraction ``t`` of the way (in-between
        frames for smooth GIFs, as the live canvas glides)."""
        scene = as_scene(robots)
        self.check_frame(overlay, scene)
        static = self.static(overlay)
        strips = self._panel_strips(overlay, scene)
        h = static.shape[0]
        img = np.empty((h + sum(st.shape[0] for st in strips), self.width, 3), dtype=np.uint8)
        img[:h] = static
        for st in strips:
            img[h : h + st.shape[0]] = st
            h += st.shape[0]
        grid = img[: static.shape[0]]
        at, poses = glide(scene, t, self.labelled, self.label_top) if t < 1.0 else ({}, {})
        drawn = [(sprite, cx, cy, patch(sprite, cx, cy)) for sprite, cx, cy in robot_sprites(
            scene, self.cell_size, self.theme, poses, at, self.labelled)]  # fmt: skip
        boxes = [_box(p, cx, cy) for _, cx, cy, p in drawn]
        touched: dict[tuple[int, int], int] = {}
        for box in boxes:
            for c in self._cells_of(box):
                touched[c] = touched.get(c, 0) + 1
        blended = []
        for (sprite, cx, cy, p), box in zip(drawn, boxes):
            cells = self._cells_of(box)
            if len(cells) == 1 and touched[cells[0]] == 1:  # alone in its cell: a cached tile
                x, y = cells[0]
                cs = self.cell_size
                grid[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs] = self._tile(static, cells[0], sprite, p, cx, cy)
            else:
                blend(grid, p, cx, cy)
                blended.append(box)
        for y0, x0, label in self._label_patches:  # labels stay on top
            lb = (x0, y0, x0 + label.rgb.shape[1], y0 + label.rgb.shape[0])
            if any(_overlap(lb, box) for box in blended):
                blend(grid, label, x0, y0)
        return img

    def check_frame(self, overlay: Overlay | None, scene: Scene) -> None:
        """The frame of ``overlay`` and ``scene`` (grid, panel, legend) within the limit, before drawing it."""
        if overlay is not None or scene.legend:
            check_overlay_frame(self.level, self.cell_size, overlay or Overlay(), len(scene.legend))

    def _cells_of(self, box: tuple[int, int, int, int]) -> list[tuple[int, int]]:
        cs = self.cell_size
        x0, y0, x1, y1 = box
        return [(x, y) for y in range(y0 // cs, (y1 - 1) // cs + 1) for x in range(x0 // cs, (x1 - 1) // cs + 1)]

    def _tile(self, static: np.ndarray, cell: tuple[int, int], sprite, p: Patch, cx: float, cy: float) -> np.ndarray:
        """The cell of ``static`` with the sprite and the labels over it, cached: robots come back to
        the same cells in the same poses, and a copy is far cheaper than a blend."""
        key = (id(static), cell, id(sprite), int(round((cx % 1) * 4)), int(round((cy % 1) * 4)))
        hit = self._tiles.get(key)
        if hit is not None and hit[0] is static and hit[1] is sprite:
            self._tiles.move_to_end(key)
            return hit[2]
        cs = self.cell_size
        x, y = cell
        tile = static[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs].copy()
        blend(tile, p, cx - x * cs, cy - y * cs)
        for y0, x0, label in self._label_patches:
            if y0 // cs == y and x0 // cs == x or _overlap((x0, y0, x0 + label.rgb.shape[1], y0 + label.rgb.shape[0]),
                                                           (x * cs, y * cs, (x + 1) * cs, (y + 1) * cs)):  # fmt: skip
                blend(tile, label, x0 - x * cs, y0 - y * cs)
        self._tiles[key] = (static, sprite, tile)
        if len(self._tiles) > 1024:
            self._tiles.popitem(last=False)
        return tile

    def static(self, overlay: Overlay | None) -> np.ndarray:
        """The level with ``overlay``'s tints, arrows and numbers, and the labels (read-only; the
        live canvas's bottom layer). The same cell parts give the same image object back."""
        if overlay is None or not overlay.has_cells:
            return self.background
        if not _same_cells(self._static[0], overlay):
            cs, th = self.cell_size, self.theme
            lv = self.level
            img = self._draw([*floor_ops(lv, cs, th), *annotate.tint_ops(overlay, cs, th), *feature_ops(lv, cs, th),
                              *annotate.ink_ops(overlay, cs, th, self.labelled), *self.labels])  # fmt: skip
            self._static = (overlay, img)
        return self._static[1]

    def panel(self, overlay: Overlay | None, scene: Scene) -> np.ndarray | None:
        """The panel image under the grid, or None; its strips are cached by content."""
        strips = self._panel_strips(overlay, scene)
        return np.concatenate(strips, axis=0) if strips else None

    def _panel_strips(self, overlay: Overlay | None, scene: Scene) -> list[np.ndarray]:
        lines = overlay.panel if overlay is not None else ()
        vr = annotate.value_range(overlay) if overlay is not None else None
        sections = panel_sections(self.width, self.cell_size, self.theme, lines, vr, scene.legend)
        strips = []
        for sec in sections:
            if sec.parts:
                strip = np.empty((sec.height, self.width, 3), dtype=np.uint8)
                for x0, x1, key, build in sec.parts:
                    strip[:, x0:x1] = self._strip((sec.height, *key), sec.height, x1 - x0, sec.background, build, x0)
                strips.append(strip)
            else:
                strips.append(self._strip(sec.key, sec.height, self.width, sec.background, sec.build))
        return strips

    def _strip(self, key: tuple, height: int, width: int, bg: tuple, build, x0: int = 0) -> np.ndarray:
        """A piece of the panel drawn from ``build()`` (operations from ``x0``), cached by ``key``."""
        img = self._panels.get(key)
        if img is not None:
            self._panels.move_to_end(key)
            return img
        buf = np.empty((height, width, 3), dtype=np.float32)
        buf[:] = bg
        ops = build()
        paint(buf, [shifted_x(op, -x0) for op in ops] if x0 else ops)
        img = self._panels[key] = to_uint8(buf)
        if len(self._panels) > 512:
            self._panels.popitem(last=False)
        return img

    # ------------------------------------------------------------------ helpers
    def _draw(self, ops: Sequence[Op]) -> np.ndarray:
        img = np.empty((self.grid_height, self.width, 3), dtype=np.float32)
        img[:] = self.theme.floor
        paint(img, ops)
        out = to_uint8(img)
        out.setflags(write=False)
        return out

    def _patches(self, ops: Sequence[Op]) -> list[tuple[int, int, Patch]]:
        """Each label's pixels as a premultiplied patch (labels come as 3 ops: edge, pill, word)."""
        out = []
        cs = self.cell_size
        for k in range(0, len(ops), 3):
            group = ops[k : k + 3]
            x0 = int(min(float(op.points[:, 0].min()) for op in group if hasattr(op, "points"))) - 1
            y0 = int(min(float(op.points[:, 1].min()) for op in group if hasattr(op, "points"))) - 1
            x0, y0 = max(0, x0), max(0, y0)
            w, h = min(cs + 2, self.width - x0), min(cs // 2 + 2, self.grid_height - y0)
            rgb = np.zeros((h, w, 3), dtype=np.float32)
            alpha = np.zeros((h, w), dtype=np.float32)
            paint(rgb, [_moved(op, -x0, -y0) for op in group], alpha)
            out.append((y0, x0, Patch(rgb, alpha[..., None], 0, 0)))
        return out



def _box(p: Patch, cx: float, cy: float) -> tuple[int, int, int, int]:
    """The pixels a patch centred on ``(cx, cy)`` covers: (x0, y0, x1, y1), x1 and y1 exclusive."""
    x0, y0 = int(math.floor(cx + 1e-9)) + p.dx, int(math.floor(cy + 1e-9)) + p.dy
    return x0, y0, x0 + p.rgb.shape[1], y0 + p.rgb.shape[0]


def _overlap(a: tuple[int, int, int, int], b: tuple[int, int, int, int]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _same_cells(a: Overlay | None, b: Overlay) -> bool:
    """The same cell parts (values, action values, arrows, text): the same objects (an overlay
    keeps the parts not given to ``set_overlay``)."""
    return a is not None and all(getattr(a, k) is getattr(b, k) for k in ("values", "q_values", "arrows", "text"))


def shifted_x(op: Op, dx: float) -> Op:
    return _moved(op, dx, 0.0)


def _moved(op: Op, dx: float, dy: float) -> Op:
    from dataclasses import replace

    from .paint import Stamp
    from .shapes import Fill

    if isinstance(op, Fill):
        return Fill(op.points + (dx, dy), op.colour, op.alpha)
    if isinstance(op, Stamp):
        return Stamp(op.sprite, op.x + dx, op.y + dy)
    return replace(op, x=op.x + dx, y=op.y + dy)
