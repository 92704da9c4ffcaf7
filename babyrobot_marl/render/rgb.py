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
from dataclasses import dataclass

import numpy as np

from ..core.level import Cell, Level
from . import annotate
from .overlay import Overlay
from .paint import Op, paint, to_uint8
from .palette import THEMES, Theme, resolve_theme
from .panel import panel_ops
from .picture import feature_ops, floor_ops, label_ops, level_ops
from .scene import Scene, Sprite, as_scene, robot_sprites

__all__ = ["MAX_CELL_SIZE", "MAX_FRAME_PIXELS", "MIN_CELL_SIZE", "THEMES", "RgbRenderer", "Theme", "resolve_theme"]

MIN_CELL_SIZE, MAX_CELL_SIZE = 8, 256
MAX_FRAME_PIXELS = 4096 * 4096  # a 256x256 maze at 16-pixel cells; larger frames ask for a smaller cell_size
DEFAULT_MAX_CELL, COLUMN_WIDTH, COLUMN_HEIGHT = 64, 896, 768  # a notebook column


def auto_cell_size(level: Level) -> int:
    """About 64-pixel cells, smaller for large levels so the grid fits a notebook column."""
    return int(np.clip(min(COLUMN_WIDTH // level.width, COLUMN_HEIGHT // level.height), MIN_CELL_SIZE, DEFAULT_MAX_CELL))


def check_cell_size(cell_size: object, level: Level | None = None) -> int | None:
    """``cell_size`` as an int in ``MIN_CELL_SIZE..MAX_CELL_SIZE`` (None: chosen for the level)."""
    if cell_size is None:
        return auto_cell_size(level) if level is not None else None
    try:
        cs = None if isinstance(cell_size, (bool, float)) else int(cell_size.__index__())  # type: ignore[attr-defined]
    except (AttributeError, TypeError):
        cs = None
    if cs is None or not MIN_CELL_SIZE <= cs <= MAX_CELL_SIZE:
        raise ValueError(
            f"cell_size: must be None (about 64, fitted to the level) or an integer in {MIN_CELL_SIZE}..{MAX_CELL_SIZE} "
            f"(pixels), got {cell_size!r}"
        )
    if level is not None:
        check_frame_size(level, cs)
    return cs


def check_frame_size(level: Level, cs: int) -> None:
    pixels = level.width * level.height * cs * cs
    if pixels > MAX_FRAME_PIXELS:
        fit = max(MIN_CELL_SIZE, math.isqrt(MAX_FRAME_PIXELS // (level.width * level.height)))
        raise ValueError(
            f"cell_size: a {level.width}x{level.height} level at {cs} pixels a cell is a {level.width * cs}x{level.height * cs} "
            f"frame, over the limit of {MAX_FRAME_PIXELS:,} pixels; use cell_size <= {fit} (or None)"
        )


@dataclass(frozen=True, eq=False)
class _Patch:
    """A rasterised sprite: premultiplied colour and coverage, and its offset from the sprite's centre."""

    rgb: np.ndarray  # float32[h, w, 3]
    alpha: np.ndarray  # float32[h, w, 1]
    dx: int
    dy: int


class RgbRenderer:
    """Draws one level at one cell size and theme; ``frame(scene_or_robots, overlay)`` returns a fresh image."""

    def __init__(self, level: Level, cell_size: int | None = None, theme: str | Theme = "light"):
        self.level = level
        self.cell_size = cs = check_cell_size(cell_size, level)
        self.theme = resolve_theme(theme)
        self.width, self.grid_height = level.width * cs, level.height * cs
        self.labels: list[Op] = label_ops(level, cs, self.theme)
        self.background = self._draw([*level_ops(level, cs, self.theme), *self.labels])
        self._label_patches = self._patches(self.labels)
        self._static: tuple[Overlay | None, np.ndarray] = (None, self.background)
        self._panels: OrderedDict[object, np.ndarray] = OrderedDict()
        self._sprites: OrderedDict[tuple[int, int, int], _Patch] = OrderedDict()

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.background.shape  # type: ignore[return-value]

    # ------------------------------------------------------------------ frames
    def frame(self, robots: Scene | Sequence[Cell | None] = (), overlay: Overlay | None = None) -> np.ndarray:
        """The level with the scene's robots (or robot ``i`` at ``robots[i]``; None: not drawn),
        under the overlay's labels and over its tints, and the panel below when there is one."""
        scene = as_scene(robots)
        img = self.static(overlay).copy()
        drawn = robot_sprites(scene, self.cell_size, self.theme)
        for sprite, cx, cy in drawn:
            self._blend(img, self._patch(sprite, cx, cy), cx, cy)
        if drawn:  # labels stay on top
            for y0, x0, patch in self._label_patches:
                region = img[y0 : y0 + patch.rgb.shape[0], x0 : x0 + patch.rgb.shape[1]]
                region[:] = to_uint8(region * (1.0 - patch.alpha) + patch.rgb)
        panel = self.panel(overlay, scene)
        return img if panel is None else np.concatenate([img, panel], axis=0)

    def static(self, overlay: Overlay | None) -> np.ndarray:
        """The level with ``overlay``'s tints, arrows and numbers, and the labels (read-only; the
        live canvas's bottom layer). The same cell parts give the same image object back."""
        if overlay is None or not overlay.has_cells:
            return self.background
        if not _same_cells(self._static[0], overlay):
            cs, th = self.cell_size, self.theme
            lv = self.level
            img = self._draw([*floor_ops(lv, cs, th), *annotate.tint_ops(overlay, cs, th), *feature_ops(lv, cs, th),
                              *annotate.ink_ops(overlay, cs, th), *self.labels])  # fmt: skip
            self._static = (overlay, img)
        return self._static[1]

    def panel(self, overlay: Overlay | None, scene: Scene) -> np.ndarray | None:
        """The panel image under the grid, or None (cached by content)."""
        lines = overlay.panel if overlay is not None else ()
        vr = annotate.value_range(overlay) if overlay is not None else None
        if not lines and vr is None and not scene.legend:
            return None
        key = (lines, vr, scene.legend)
        if key not in self._panels:
            ops, height = panel_ops(self.width, self.cell_size, self.theme, lines, vr, scene.legend)
            img = np.zeros((height, self.width, 3), dtype=np.float32)
            paint(img, ops)
            self._panels[key] = to_uint8(img)
            if len(self._panels) > 64:
                self._panels.popitem(last=False)
        return self._panels[key]

    # ------------------------------------------------------------------ helpers
    def _draw(self, ops: Sequence[Op]) -> np.ndarray:
        img = np.empty((self.grid_height, self.width, 3), dtype=np.float32)
        img[:] = self.theme.floor
        paint(img, ops)
        out = to_uint8(img)
        out.setflags(write=False)
        return out

    def _patches(self, ops: Sequence[Op]) -> list[tuple[int, int, _Patch]]:
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
            out.append((y0, x0, _Patch(rgb, alpha[..., None], 0, 0)))
        return out

    def _patch(self, sprite: Sprite, cx: float, cy: float) -> _Patch:
        """The sprite rasterised at the sub-pixel offset of ``(cx, cy)`` (a quarter pixel), cached."""
        fx, fy = int(round((cx % 1) * 4)) % 4, int(round((cy % 1) * 4)) % 4
        key = (id(sprite), fx, fy)
        patch = self._sprites.get(key)
        if patch is not None and patch.rgb is not None:
            self._sprites.move_to_end(key)
            return patch
        pts = sprite.points
        m = 3 + max((t.size for t in sprite.texts), default=0) // 2
        lo = np.floor(pts.min(axis=0)).astype(int) - m if len(pts) else np.array([-m, -m])
        hi = np.ceil(pts.max(axis=0)).astype(int) + m if len(pts) else np.array([m, m])
        w, h = int(hi[0] - lo[0]), int(hi[1] - lo[1])
        rgb = np.zeros((h, w, 3), dtype=np.float32)
        alpha = np.zeros((h, w), dtype=np.float32)
        paint(rgb, sprite.ops(-lo[0] + fx / 4, -lo[1] + fy / 4), alpha)
        patch = _Patch(rgb, alpha[..., None], int(lo[0]), int(lo[1]))
        self._sprites[key] = patch
        self._sprite_refs = getattr(self, "_sprite_refs", {})
        self._sprite_refs[key] = sprite  # keep the sprite alive while its id is a key
        if len(self._sprites) > 512:
            old, _ = self._sprites.popitem(last=False)
            self._sprite_refs.pop(old, None)
        return patch

    def _blend(self, img: np.ndarray, patch: _Patch, cx: float, cy: float) -> None:
        x0, y0 = int(math.floor(cx + 1e-9)) + patch.dx, int(math.floor(cy + 1e-9)) + patch.dy
        h, w = patch.rgb.shape[:2]
        gx0, gy0 = max(0, x0), max(0, y0)
        gx1, gy1 = min(self.width, x0 + w), min(self.grid_height, y0 + h)
        if gx1 <= gx0 or gy1 <= gy0:
            return
        sl = (slice(gy0 - y0, gy1 - y0), slice(gx0 - x0, gx1 - x0))
        region = img[gy0:gy1, gx0:gx1]
        region[:] = to_uint8(region * (1.0 - patch.alpha[sl]) + patch.rgb[sl])


def _same_cells(a: Overlay | None, b: Overlay) -> bool:
    """The same cell parts (values, action values, arrows, text): the same objects (an overlay
    keeps the parts not given to ``set_overlay``)."""
    return a is not None and all(getattr(a, k) is getattr(b, k) for k in ("values", "q_values", "arrows", "text"))


def _moved(op: Op, dx: float, dy: float) -> Op:
    from dataclasses import replace

    from .paint import Fill

    if isinstance(op, Fill):
        return Fill(op.points + (dx, dy), op.colour, op.alpha)
    return replace(op, x=op.x + dx, y=op.y + dy)
