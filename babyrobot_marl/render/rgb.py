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
from collections.abc import Sequence

import numpy as np

from ..core.level import Cell, Level
from . import annotate
from .cellgroups import any_overlap, overlap, rect_groups
from .checks import (  # noqa: F401  (the limits and checks are read from here too)
    MAX_CELL_SIZE,
    MAX_FRAME_PIXELS,
    MIN_CELL_SIZE,
    auto_cell_size,
    check_cell_size,
    check_frame_size,
    check_overlay_frame,
)
from .crowd import CellBlocks
from .memo import ENTRY_BYTES, MB, ByteCache
from .overlay import Overlay
from .paint import Patch, blend, paint, patch, to_uint8
from .palette import THEMES, Theme, resolve_theme, robot_colour
from .panel import LEGEND_ROWS, legend_row_section, metrics, panel_sections
from .picture import edge_depths, feature_ops, floor_ops, label_band, label_ops, level_ops
from .scene import (
    BURST,
    RobotView,
    Scene,
    as_scene,
    burst_centre,
    glide,
    lone_placement,
    placement_sprites,
    placements,
    robot_sprites,
)
from .shapes import Op, Text
from .sprites import burst, goal_mark

__all__ = ["MAX_CELL_SIZE", "MAX_FRAME_PIXELS", "MIN_CELL_SIZE", "THEMES", "RgbRenderer", "Theme", "resolve_theme"]

# What a renderer keeps to draw again by a copy, in bytes (``memo``): cells with robots drawn in,
# by content and by a lone robot's view; panel strips; legend rows; placed robots and bursts.
BLOCK_BYTES, LONE_BYTES, PANEL_BYTES, ROW_BYTES, PLACED_BYTES, MARK_BYTES = 24 * MB, 24 * MB, 10 * MB, 4 * MB, 3 * MB, MB
RENDERER_BYTES = BLOCK_BYTES + LONE_BYTES + PANEL_BYTES + ROW_BYTES + PLACED_BYTES + MARK_BYTES


class RgbRenderer(CellBlocks):
    """Draws one level at one cell size and theme; ``frame(scene_or_robots, overlay)`` returns a fresh image.
    ``panel_ratio``: device pixels per CSS pixel of the panel (2: the picture of a canvas drawn
    at twice its CSS size, whose panel is laid out for its CSS size and drawn twice as large)."""

    def __init__(self, level: Level, cell_size: int | None = None, theme: str | Theme = "light", panel_ratio: int = 1):
        self.level = level
        self.panel_ratio = panel_ratio
        self.cell_size = cs = check_cell_size(cell_size, level)
        self.theme = resolve_theme(theme)
        self.width, self.grid_height = level.width * cs, level.height * cs
        self.labels: list[Op] = label_ops(level, cs, self.theme)
        self.labelled = frozenset((int(op.x // cs), int(op.y // cs)) for op in self.labels if isinstance(op, Text))
        self.exits = frozenset(level.exits)
        self.starts = frozenset(level.starts)  # their flags: in the corner under an overlay
        self.depths = edge_depths(level, cs)  # how far walls reach into cells: numbers keep clear
        self.label_top = label_band(cs)[1] / cs  # robots sharing a labelled cell stand below this
        self._lone_size = {(c, lab): round(cs * lone_placement(RobotView(0, (0, 0)), c, self.label_top * lab).scale, 2)
                           for c in (False, True) for lab in (False, True)}  # a lone robot's size, by corner and label
        self.background = self._draw([*level_ops(level, cs, self.theme), *self.labels])
        self._label_patches = self._patches(self.labels)
        self._static: tuple[Overlay | None, np.ndarray] = (None, self.background)
        self._panels: ByteCache[np.ndarray] = ByteCache(PANEL_BYTES, _array_bytes)
        self._lone = (ByteCache(LONE_BYTES, _lone_bytes), ByteCache(LONE_BYTES, _lone_bytes))  # lone robots' cells
        self._lone_static: np.ndarray | None = None  # and blocks by view, without and with an overlay, on this
        self._tiles: list[list[int]] = []  # its cells numbered by their pixels (``crowd.tiles``)
        self._reach: dict[tuple, tuple] = {}  # the cells a lone robot's look covers, relative to its cell
        self._on_tiles = self._tiled()
        self._mark_cache: ByteCache[tuple] = ByteCache(MARK_BYTES, _ref_bytes)  # bursts placed, by their two cells
        self._row_h = metrics(cs, panel_ratio).row_h
        self._rows: ByteCache[list] = ByteCache(ROW_BYTES, _row_bytes)  # legend rows' layouts, by content
        self._blocks: ByteCache[np.ndarray] = ByteCache(BLOCK_BYTES, _array_bytes)  # cells with robots drawn in,
        self._blocks_static: np.ndarray | None = None  # by content, on this static image
        self._placed: ByteCache[tuple] = ByteCache(PLACED_BYTES, _placed_bytes)  # placed robots' sprites, patches, cells
        self._checked: tuple | None = None
        self._goal_layer: tuple = (None, (), None)  # the last static image with targets: its cells, targets, image
        self._legend_y: int | None = None  # the first legend row's top, from the panel's
        self._base_img: np.ndarray | None = None  # the last frame without robots, its panel strips, its key
        self._base_strips: list[np.ndarray] = []
        self._base_key: tuple = (None, None, None)

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
        static = self.static(overlay, scene.goals)
        img = self._base(static, overlay, scene).copy()
        grid = img[: static.shape[0]]
        if t >= 1.0:
            self._robots_at_rest(grid, static, scene)
            return img
        at, poses = glide(scene, t, self.labelled, self.label_top)
        drawn = [self._placed_sprite(sprite, cx, cy) for sprite, cx, cy in robot_sprites(
            scene, self.cell_size, self.theme, poses, at, self.labelled)]  # fmt: skip
        self._paste_groups(grid, static, drawn)
        return img

    def _paste_groups(self, grid: np.ndarray, static: np.ndarray, drawn: list[tuple]) -> None:
        """The general way: the sprites in groups of cells, each group a cached block."""
        cs = self.cell_size
        for (x0, y0, x1, y1), items in _groups(drawn):
            grid[y0 * cs : y1 * cs, x0 * cs : x1 * cs] = self._block(static, (x0, y0, x1, y1), items)

    def _general(self, static: np.ndarray, scene: Scene) -> np.ndarray:
        """The robots at rest over ``static`` drawn all the general way (what ``frame`` draws)."""
        grid = static.copy()
        self._paste_groups(grid, static, self._still(scene))
        return grid

    def _marks(self, scene: Scene) -> list[tuple]:
        """The bursts of the scene's collisions, placed (cached by the two cells)."""
        out = []
        for mark in scene.marks:
            hit = self._mark_cache.get(mark)
            if hit is None:
                cs = self.cell_size
                hit = self._mark_cache.put(mark, self._placed_sprite(burst(self.theme, round(cs * BURST[0], 2)),
                                                                     *burst_centre(*mark, cs)))  # fmt: skip
            out.append(hit)
        return out

    def _placed_sprite(self, sprite, cx: float, cy: float) -> tuple:
        """A sprite at ``(cx, cy)`` pixels: it, its patch, the pixels and the cells it covers."""
        p = patch(sprite, cx, cy)
        box = _box(p, cx, cy)
        cs = self.cell_size  # the cells it covers: x0, y0, x1, y1 (exclusive); what a block's key holds of it
        w, h = self.level.width, self.level.height  # (clipped to the grid: a bump's stars may reach past it)
        rect = (max(0, box[0] // cs), max(0, box[1] // cs), min(w, (box[2] - 1) // cs + 1), min(h, (box[3] - 1) // cs + 1))
        return sprite, cx, cy, p, box, rect, (p.serial, box[0], box[1])

    def _still(self, scene: Scene) -> list[tuple]:
        """``_placed_sprite`` of the scene's robots, marks and badges at rest (``robot_sprites``'
        order), each placed robot's cached: robots stand in the same places again and again."""
        robots, badges = [], []
        for pl in placements(scene, self.labelled, self.label_top):
            hit = self._placed_of(pl)
            robots.append(hit[1])
            badges += hit[2:]
        return robots + self._marks(scene) + badges

    def _placed_of(self, pl) -> tuple:
        """``(pl, placed robot, placed badge if ranked)``, cached by the placement (the entry keeps
        ``pl`` alive: its id is its own)."""
        hit = self._placed.get(id(pl))
        if hit is None or hit[0] is not pl:
            hit = self._placed.put(id(pl), (pl, *(self._placed_sprite(*sp) for sp in placement_sprites(
                pl, self.cell_size, self.theme, pl.view.pose, pl.cx, pl.cy) if sp is not None)))  # fmt: skip
        return hit

    def check_frame(self, overlay: Overlay | None, scene: Scene) -> None:
        """The frame of ``overlay`` and ``scene`` (grid, panel, legend) within the limit, before drawing it
        (checked once per overlay and legend length)."""
        if overlay is None and not scene.legend:
            return
        checked = self._checked
        if checked is not None and checked[0] is overlay and checked[1] == len(scene.legend):
            return
        check_overlay_frame(self.level, self.cell_size, overlay or Overlay(), len(scene.legend))
        self._checked = (overlay, len(scene.legend))

    def _base(self, static: np.ndarray, overlay: Overlay | None, scene: Scene) -> np.ndarray:
        """The frame without robots: ``static`` over the panel, kept from frame to frame; only
        the panel strips that changed are copied in (a legend row's return, say)."""
        key = (overlay.panel, overlay.scale) if overlay is not None else None
        last = self._base_key
        if last[0] is static and last[1] == key:
            if last[2] == scene.legend:
                return self._base_img
            if self._rows_only(last[2], scene.legend):
                self._base_key = (static, key, scene.legend)
                return self._base_img
        strips = self._panel_strips(overlay, scene)
        h = static.shape[0] + sum(st.shape[0] for st in strips)
        img, old = self._base_img, self._base_strips
        if img is None or img.shape[0] != h or self._base_key[0] is not static or len(old) != len(strips):
            img = np.empty((h, self.width, 3), dtype=np.uint8)
            img[: static.shape[0]] = static
            old = [None] * len(strips)
        y = static.shape[0]
        for k, st in enumerate(strips):
            if old[k] is not st:
                img[y : y + st.shape[0]] = st
            y += st.shape[0]
        self._base_img, self._base_strips, self._base_key = img, strips, (static, key, scene.legend)
        return img

    def _labels_over(self, boxes: Sequence[tuple[int, int, int, int]]) -> list[tuple[int, int, Patch]]:
        """The labels' patches ``(y, x, patch)`` that overlap any of ``boxes`` (x0, y0, x1, y1 in pixels):
        drawn again over the sprites there."""
        return [(ly, lx, label) for ly, lx, label in self._label_patches
                if any(overlap((lx, ly, lx + label.rgb.shape[1], ly + label.rgb.shape[0]), box) for box in boxes)]

    def _block(self, static: np.ndarray, rect: tuple[int, int, int, int], items: list[tuple]) -> np.ndarray:
        """The cells ``rect`` (x0, y0, x1, y1, in cells) of ``static`` with the sprites ``items``
        blended in order and the labels over them, cached by exact content: robots come back to
        the same cells in the same poses (a burst beside the same two robots), and a copy is far
        cheaper than blends. The cache holds one static image's blocks (patches by serial number)."""
        if self._blocks_static is not static:
            self._blocks.clear()
            self._blocks_static = static
        key = (rect, *[it[6] for it in items])
        hit = self._blocks.get(key)
        if hit is not None:
            return hit
        cs = self.cell_size
        x0, y0, x1, y1 = rect
        ox, oy = x0 * cs, y0 * cs
        block = static[oy : y1 * cs, ox : x1 * cs].copy()
        for _, cx, cy, p, *_ in items:
            blend(block, p, cx - ox, cy - oy)
        for ly, lx, label in self._labels_over([it[4] for it in items]):  # labels stay on top of the robots under them
            blend(block, label, lx - ox, ly - oy)
        return self._blocks.put(key, block)

    def static(self, overlay: Overlay | None, goals: tuple = ()) -> np.ndarray:
        """The level with ``overlay``'s tints, arrows and numbers, the robots' own targets
        (``Scene.goals``) and the labels (read-only; the live canvas's bottom layer). The same
        cell parts and targets give the same image object back."""
        cells = self._cells_static(overlay)
        return self._with_goals(cells, goals) if goals else cells

    def _with_goals(self, cells: np.ndarray, goals: tuple) -> np.ndarray:
        """``cells`` with each robot's target marked in its colour, under the labels (the last kept)."""
        kept = self._goal_layer
        if kept[0] is cells and kept[1] == goals:
            return kept[2]
        img, cs = cells.copy(), self.cell_size
        boxes = []
        for number, (x, y) in goals:
            p = patch(goal_mark(self.theme, robot_colour(self.theme, number), cs), (x + 0.5) * cs, (y + 0.5) * cs)
            blend(img, p, (x + 0.5) * cs, (y + 0.5) * cs)
            boxes.append(_box(p, (x + 0.5) * cs, (y + 0.5) * cs))
        for ly, lx, label in self._labels_over(boxes):
            blend(img, label, lx, ly)
        img.setflags(write=False)
        self._goal_layer = (cells, goals, img)
        return img

    def _cells_static(self, overlay: Overlay | None) -> np.ndarray:
        """``static`` without the targets."""
        if overlay is self._static[0]:  # the same overlay as the last frame's (the usual case)
            return self._static[1]
        if overlay is None or not overlay.has_cells:
            return self.background
        if not _same_cells(self._static[0], overlay):
            cs, th = self.cell_size, self.theme
            lv = self.level
            img = self._draw([*floor_ops(lv, cs, th), *annotate.tint_ops(overlay, cs, th, self.exits),
                              *feature_ops(lv, cs, th, corner=True),
                              *annotate.ink_ops(overlay, cs, th, self.labelled, self.exits, self.starts, self.depths),
                              *self.labels])  # fmt: skip
            self._static = (overlay, img)
        return self._static[1]

    def panel(self, overlay: Overlay | None, scene: Scene) -> np.ndarray | None:
        """The panel image under the grid, or None; its strips are cached by content."""
        strips = self._panel_strips(overlay, scene)
        return np.concatenate(strips, axis=0) if strips else None

    def _rows_only(self, old: tuple, new: tuple) -> bool:
        """Redraw in the kept frame only the legend rows that changed, when nothing else did (a
        legend of a row per robot, the same robots); False: the panel must be laid out again.
        Each row's strip is cached by its exact content: returns repeat from race to race."""
        if self._legend_y is None or len(old) != len(new) or not new or len(new) > LEGEND_ROWS:
            return False
        self._base_strips = [None] * len(self._base_strips)  # the kept strips will not all show
        img = self._base_img
        y = self.grid_height + self._legend_y
        for a, b in zip(old, new):
            if a is not b and a != b:  # only its pieces that changed (its return, mostly)
                if a.number != b.number:
                    return False
                for (_, _, was, *_), (x0, x1, key, h, bg, build) in zip(self._row_layout(a), self._row_layout(b)):
                    if was != key:
                        img[y : y + h, x0:x1] = self._strip((h, *key), h, x1 - x0, bg, build, x0)
            y += self._row_h
        return True

    def _row_layout(self, row) -> list[tuple]:
        """A legend row's pieces side by side, ``(x0, x1, key, height, background, build)``, cached by
        the row's content (thousands: rows repeat from race to race); their pictures are ``_strip``'s."""
        hit = self._rows.get(row)
        if hit is None:
            sec = legend_row_section(self.width, self.cell_size, self.theme, row, self.panel_ratio)
            hit = self._rows.put(row, [(x0, x1, key, sec.height, sec.background, build) for x0, x1, key, build in sec.parts])
        return hit

    def _panel_strips(self, overlay: Overlay | None, scene: Scene) -> list[np.ndarray]:
        lines = overlay.panel if overlay is not None else ()
        vr = annotate.value_range(overlay) if overlay is not None else None
        sections = panel_sections(self.width, self.cell_size, self.theme, lines, vr, scene.legend, self.panel_ratio)
        strips = []
        self._legend_y, y = None, 0
        for sec in sections:
            if sec.key[0] == "row" and self._legend_y is None:
                self._legend_y = y  # where the rows start: ``_rows_only`` redraws them there
            y += sec.height
            if sec.parts:
                strips.append(self._section_strip(sec))
            else:
                strips.append(self._strip(sec.key, sec.height, self.width, sec.background, sec.build))
        return strips

    def _section_strip(self, sec) -> np.ndarray:
        """A section of side by side pieces: its pieces cached one by one, and the strip they make."""
        whole = ("whole", sec.height, *(key for _, _, key, _ in sec.parts))
        strip = self._panels.get(whole)
        if strip is None:
            strip = np.empty((sec.height, self.width, 3), dtype=np.uint8)
            for x0, x1, key, build in sec.parts:
                strip[:, x0:x1] = self._strip((sec.height, *key), sec.height, x1 - x0, sec.background, build, x0)
            self._panels.put(whole, strip)
        return strip

    def _strip(self, key: tuple, height: int, width: int, bg: tuple, build, x0: int = 0) -> np.ndarray:
        """A piece of the panel drawn from ``build()`` (operations from ``x0``), cached by ``key``."""
        img = self._panels.get(key)
        if img is not None:
            return img
        buf = np.empty((height, width, 3), dtype=np.float32)
        buf[:] = bg
        ops = build()
        paint(buf, [shifted_x(op, -x0) for op in ops] if x0 else ops)
        return self._panels.put(key, to_uint8(buf))

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


def _array_bytes(a: np.ndarray) -> int:
    return a.nbytes + ENTRY_BYTES


def _lone_bytes(hit: tuple) -> int:
    return hit[1].nbytes + ENTRY_BYTES


def _row_bytes(layout: list) -> int:
    return ENTRY_BYTES * (1 + len(layout))  # keys and closures: no pictures


def _ref_bytes(_: object) -> int:
    return ENTRY_BYTES  # references to what another cache counts (a burst's few patches)


def _placed_bytes(hit: tuple) -> int:
    return sum(it[3].nbytes for it in hit[1:]) + ENTRY_BYTES  # the patches it keeps alive


def _groups(drawn: list[tuple]) -> list[tuple[tuple[int, int, int, int], list[tuple]]]:
    """The drawn sprites in groups whose cell rectangles do not overlap (``rect_groups``), each
    group's sprites in drawing order: each group is one cached block."""
    return [(rect, [drawn[k] for k in members]) for rect, members in rect_groups([item[5] for item in drawn])]


_any_overlap, _overlap = any_overlap, overlap


def _box(p: Patch, cx: float, cy: float) -> tuple[int, int, int, int]:
    """The pixels a patch centred on ``(cx, cy)`` covers: (x0, y0, x1, y1), x1 and y1 exclusive."""
    x0, y0 = int(math.floor(cx + 1e-9)) + p.dx, int(math.floor(cy + 1e-9)) + p.dy
    return x0, y0, x0 + p.rgb.shape[1], y0 + p.rgb.shape[0]


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
