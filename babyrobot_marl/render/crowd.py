"""A crowd's frame at rest: each cell's robots as one block, found by what the cell looks like.

A frame of thousands of robots is mostly cells holding one robot each. Such a cell's block (the
level's pixels there with the robot blended in) depends on the robot's look (colour, heading,
pose, rank, number shown) and on the level's pixels in the cell, not on where the cell is: most
cells of a level are alike (plain floor). So the level's cells are numbered by their pixels
(``tiles``), and a lone robot's block is cached by its cell's number and its look: a robot
stepping onto a new cell costs a lookup, not a blend. Cells under a START / EXIT label, and the
placements whose sub-pixel offset could differ from cell to cell, are keyed by the cell itself.
Cells whose drawings reach into another's (a bump's stars, a burst) are drawn the general way.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .cellgroups import any_overlap, overlap, rect_groups
from .paint import blend
from .robot import number_size
from .scene import RobotView, Scene, at_rest, drawing_order, lone_placement, placements, with_numbers

Rect = tuple[int, int, int, int]
REACHES = 1 << 15  # the looks whose reach a renderer keeps (colours, headings, poses, ranks, numbers shown)


def tiles(static: np.ndarray, cs: int, unique: Sequence[tuple[int, int]] = ()) -> list[list[int]]:
    """Each cell's tile number, ``[y][x]``: cells of the same pixels share one (>= 0); the cells in
    ``unique`` get numbers of their own (< 0)."""
    h, w = static.shape[0] // cs, static.shape[1] // cs
    flat = np.ascontiguousarray(static.reshape(h, cs, w, cs, 3).transpose(0, 2, 1, 3, 4)).reshape(h * w, -1)
    # a fingerprint by random weights (one matrix product), then each cell checked against its group's first
    weights = np.random.default_rng(0).random(flat.shape[1])
    _, first, ids = np.unique(flat @ weights, return_index=True, return_inverse=True)
    ids = ids.reshape(-1)
    same = (flat == flat[first[ids]]).all(axis=1)
    out = np.where(same, ids, -1 - np.arange(h * w)).reshape(h, w)
    for x, y in unique:
        out[y, x] = -1 - (y * w + x)
    return out.tolist()


def same_offset(u: float, cs: int, n: int) -> bool:
    """Whether a centre ``u`` cells into a cell lands at the same pixel and quarter pixel (what
    ``paint.patch`` and ``blend`` read of it) in each of ``n`` cells: ``(x + u) * cs`` rounds."""
    c = (np.arange(n) + u) * cs  # as ``lone_placement`` then ``placement_sprites`` compute it
    quarter = np.round((c % 1) * 4) % 4
    pixel = np.floor(c + 1e-9) - np.arange(n) * cs
    return bool((quarter == quarter[0]).all() and (pixel == pixel[0]).all())


class CellBlocks:
    """``RgbRenderer``'s robots at rest (its caches: ``_lone``, ``_blocks``, ``_placed``)."""

    def _robots_at_rest(self, grid: np.ndarray, static: np.ndarray, scene: Scene) -> None:
        """Each cell's robots from a block by the cell's views alone; the cells whose drawings
        reach into another's (a bump's stars, a burst), and only those, drawn the general way."""
        cs = self.cell_size
        (units, views), marks = self._cell_units(static, scene), self._marks(scene)
        if self._apart(units, marks):  # the usual frame: the blocks, the bursts over them, the labels over those
            for (x0, y0, x1, y1), block, *_ in units:
                grid[y0 * cs : y1 * cs, x0 * cs : x1 * cs] = block
            for _, cx, cy, p, box, _, _ in marks:
                blend(grid, p, cx, cy)
                for ly, lx, label in self._labels_over([box]):
                    blend(grid, label, lx, ly)
            return
        n = len(units)
        for rect, members in rect_groups([u[0] for u in units] + [m[5] for m in marks]):
            x0, y0, x1, y1 = rect
            if len(members) == 1 and members[0] < n:  # a cell clear of all others: its own block
                grid[y0 * cs : y1 * cs, x0 * cs : x1 * cs] = units[members[0]][1]
                continue
            entries = [e for k in members if k < n
                       for e in with_numbers(self.unit_entries(units[k], views[k], scene.corner), views[k])]  # fmt: skip
            grid[y0 * cs : y1 * cs, x0 * cs : x1 * cs] = self._block(
                static, rect, drawing_order(entries, [marks[k - n] for k in members if k >= n]))

    def _apart(self, units: list[tuple], marks: list[tuple]) -> bool:
        """No cell's robots reach into another's cells and no rank badge lies under a burst: the
        blocks can be copied and the bursts drawn over them."""
        rects = [u[0] for u in units]
        wide = any(r[2] - r[0] != 1 or r[3] - r[1] != 1 for r in rects)  # a bump's stars reach a neighbour
        if wide and any_overlap(rects):
            return False
        ranked = [u[0] for u in units if u[3]]
        return not (ranked and any(overlap(m[4], r) for m in marks for r in ranked))  # else the general order

    def _cell_units(self, static: np.ndarray, scene: Scene) -> tuple[list[tuple], list[list]]:
        """Each cell's robots as ``(cells, block, [(number, placed robot, placed badge or None)] or
        None, ranked)``, and each cell's views. Blocks are cached by the cell's look (where a robot
        came from does not change its picture; a lone robot's entry may be another robot's that
        looks the same); a lone robot on a tile is cached by the tile, its entries (None) drawn
        only when the general way needs them (``unit_entries``)."""
        if self._lone_static is not static:
            for c in self._lone:
                c.clear()
            self._lone_static, self._tiles, self._reach = static, self._tile_numbers(static), {}
        corner = scene.corner
        cache, on_tiles = self._lone[corner], self._on_tiles[corner]
        by_cell: dict[tuple, list] = {}
        for v in scene.robots:
            by_cell.setdefault(v.cell, []).append(v)
        out = []
        for cell, views in by_cell.items():
            if len(views) > 1:
                key = tuple(map(at_rest, views))
            else:
                look = self._look(views[0], corner)
                found = self._tile_key(cell, look, corner) if on_tiles else None
                if found is not None:
                    rect, tkey = found
                    hit = cache.get(tkey)
                    if hit is None:
                        hit = cache.put(tkey, (None, *self._cell_block(static, tuple(views), corner)[1:]))
                    out.append((rect, hit[1], None, hit[3]))
                    continue
                key = (cell, look)
            hit = cache.get(key)
            if hit is None:
                hit = cache.put(key, self._cell_block(static, tuple(views), corner))
                if len(views) == 1 and on_tiles:
                    self._learn_reach(cell, look, corner, hit[0])
            out.append(hit)
        return out, list(by_cell.values())

    def _tile_key(self, cell: tuple[int, int], look: tuple, corner: bool) -> tuple | None:
        """A lone robot's cells and its block's key by the tiles of those cells, or None (its reach
        not known yet, past the grid's edge, or a cell of its own)."""
        rel = self._reach.get((corner, look))
        if rel is None:
            return None
        x, y = cell
        x0, y0, x1, y1 = x + rel[0], y + rel[1], x + rel[2], y + rel[3]
        if x0 < 0 or y0 < 0 or x1 > self.level.width or y1 > self.level.height:
            return None
        tile_of = self._tiles
        ts = (tile_of[y][x],) if x1 - x0 == 1 and y1 - y0 == 1 else tuple(
            t for row in tile_of[y0:y1] for t in row[x0:x1])  # fmt: skip
        return ((x0, y0, x1, y1), (ts, look)) if min(ts) >= 0 else None

    def _learn_reach(self, cell: tuple[int, int], look: tuple, corner: bool, rect: Rect) -> None:
        """The cells a lone robot's look covers, relative to its cell (the same in every cell
        without a label: its place in the cell is), learnt from a block clear of the grid's edges."""
        if cell in self.labelled or len(self._reach) >= REACHES:
            return
        if rect[0] > 0 and rect[1] > 0 and rect[2] < self.level.width and rect[3] < self.level.height:
            x, y = cell
            self._reach[corner, look] = (rect[0] - x, rect[1] - y, rect[2] - x, rect[3] - y)

    def _tiled(self) -> tuple[bool, bool]:
        """Whether a lone robot's place in its cell is the same in every cell, without and with
        an overlay's corner (else its blocks are keyed by cell)."""
        lv, cs = self.level, self.cell_size
        out = []
        for corner in (False, True):
            pl = lone_placement(RobotView(0, (0, 0)), corner, 0.0)
            out.append(same_offset(pl.cx, cs, lv.width) and same_offset(pl.cy, cs, lv.height))
        return out[0], out[1]

    def _tile_numbers(self, static: np.ndarray) -> list[list[int]]:
        """``tiles`` of ``static``, the cells a label's pixels reach counted apart (labels are drawn
        over the robots in them)."""
        cs, near = self.cell_size, []
        for ly, lx, label in self._label_patches:
            h, w = label.rgb.shape[:2]
            near += [(x, y) for y in range(ly // cs, (ly + h - 1) // cs + 1) for x in range(lx // cs, (lx + w - 1) // cs + 1)]
        gw, gh = self.level.width, self.level.height
        return tiles(static, cs, [(x, y) for x, y in near if 0 <= x < gw and 0 <= y < gh])

    def _look(self, v: RobotView, corner: bool) -> tuple:
        """What the block of a robot alone in its cell shows besides the cell: the robot's colour,
        heading, pose and rank, and its number if one is drawn on its chest (below the size a number
        is drawn at, robots of one colour share their blocks)."""
        numbered = v.numbered and not v.rank  # as ``placement_sprites`` and ``robot_sprite`` decide
        shown = None
        if numbered and number_size(v.number, self._lone_size[corner, v.cell in self.labelled]) is not None:
            shown = v.number
        return v.number % len(self.theme.robots), v.heading, v.pose, v.rank, numbered, shown

    def _cell_block(self, static: np.ndarray, views: tuple, corner: bool) -> tuple:
        """The robots of one cell drawn as ``_still`` draws them (robots, then their badges)."""
        entries = self._cell_entries(views, corner)
        items = [e[1] for e in entries] + [e[2] for e in entries if e[2] is not None]
        rs = [it[5] for it in items]
        rect = (min(r[0] for r in rs), min(r[1] for r in rs), max(r[2] for r in rs), max(r[3] for r in rs))
        return rect, self._block(static, rect, items), entries, any(v.rank for v in views)

    def _cell_entries(self, views: Sequence[RobotView], corner: bool) -> list[tuple]:
        """A cell's robots ``(number, placed robot, placed badge or None)``."""
        v = views[0]
        pls = ([lone_placement(v, corner, self.label_top if v.cell in self.labelled else 0.0)] if len(views) == 1
               else placements(Scene(tuple(views), corner=corner), self.labelled, self.label_top))  # fmt: skip
        entries = []
        for pl in pls:
            hit = self._placed_of(pl)
            entries.append((pl.view.number, hit[1], hit[2] if len(hit) > 2 else None))
        return entries

    def unit_entries(self, unit: tuple, views: Sequence[RobotView], corner: bool) -> list[tuple]:
        """A unit's entries, placed in its own cell (a unit found by its tile has none kept)."""
        return unit[2] if unit[2] is not None else self._cell_entries(views, corner)
