"""Action values and arrows at the sizes a browser shows them (cells of 92 to 184 pixels):
numbers clear of walls and labels, arrows clear of numbers and of the start's flag, tied
arrows of comparable length, numbers as large as their triangles allow, and no two values
that differ printed alike. Measured on the drawing operations (pixels of the image)."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import levels, planning
from babyrobot_marl.render import annotate, qlabels
from babyrobot_marl.render.overlay import Overlay, update_overlay
from babyrobot_marl.render.palette import THEMES
from babyrobot_marl.render.picture import feature_ops
from babyrobot_marl.render.rgb import RgbRenderer
from babyrobot_marl.render.shapes import Fill, Text

LIGHT = THEMES["light"]
BIG = (92, 144, 184)


def solved(name: str, kind: str) -> tuple:
    """A level and value iteration's overlay on it: ``values`` or action values (``q``), with the best actions as arrows."""
    level = levels.get(name)
    sol = planning.value_iteration(planning.model(level), gamma=1.0)
    h, w = level.height, level.width
    if kind == "values":
        return level, update_overlay(Overlay(), level, values=sol.value_grid, arrows=sol.best_actions)
    q = sol.q.reshape(h, w, 5).copy()
    q[np.isnan(sol.value_grid)] = np.nan
    return level, update_overlay(Overlay(), level, q_values=q, arrows=sol.best_actions)


def drawn(level, ov: Overlay, cs: int) -> tuple[RgbRenderer, list]:
    r = RgbRenderer(level, cs, LIGHT)
    return r, annotate.ink_ops(ov, cs, LIGHT, r.labelled, r.exits, r.starts, r.depths)


def bounds(points: np.ndarray) -> tuple[float, float, float, float]:
    (x0, y0), (x1, y1) = points.min(axis=0), points.max(axis=0)
    return float(x0), float(y0), float(x1), float(y1)


def apart(a, b) -> float:
    """How far apart two rectangles are along the axis that separates them most (<= 0: they overlap)."""
    return max(b[0] - a[2], a[0] - b[2], b[1] - a[3], a[1] - b[3])


def cell_of(box, cs: int) -> tuple[int, int]:
    return int((box[0] + box[2]) / 2 // cs), int((box[1] + box[3]) / 2 // cs)


def number_boxes(level, ov: Overlay, cs: int, r: RgbRenderer, ops: list) -> list[tuple]:
    """The box round every number (an action value's with its white ring where it has one)."""
    if ov.q_values is not None:
        labels = annotate.q_labels(ov.q_values, cs, r.labelled, r.exits, ov.scale.format, r.depths)
        return [lb.box(qlabels.RING if ov.arrows[y, x, lb.action] else 0.0) for (x, y), lbs in labels.items() for lb in lbs]
    return [bounds(op.points) for op in ops if isinstance(op, Fill) and op.colour == LIGHT.value_box and len(op.points) != 7]


def arrow_outlines(ops: list) -> list[tuple]:
    """The bounds of each arrow's dark outline (the whole arrow)."""
    return [bounds(op.points) for op in ops if isinstance(op, Fill) and len(op.points) == 7 and op.colour == LIGHT.arrow_edge]


def arrow_parts(ops: list) -> list[tuple]:
    """The bounds of each arrow's shaft and of its head (dark outline included): the arrow lies inside them."""
    outlines = [op.points for op in ops if isinstance(op, Fill) and len(op.points) == 7 and op.colour == LIGHT.arrow_edge]
    return [bounds(pts[idx]) for pts in outlines for idx in ([0, 1, 5, 6], [2, 3, 4])]


@pytest.mark.parametrize("kind", ["q", "values"])
@pytest.mark.parametrize("cs", BIG)
@pytest.mark.parametrize("name", ["mixed-8x8", "glass"])
def test_numbers_keep_two_pixels_from_walls_panes_and_the_border(name, cs, kind):
    """West and east numbers touched the grid's border (0 px apart)."""
    level, ov = solved(name, kind)
    r, ops = drawn(level, ov, cs)
    walls = [bounds(op.points) for op in feature_ops(level, cs, LIGHT, corner=True)
             if isinstance(op, Fill) and op.colour in (LIGHT.wall, LIGHT.glass_frame)]  # fmt: skip
    boxes = number_boxes(level, ov, cs, r, ops)
    assert len(boxes) > 20 and len(walls) > 4
    for box in boxes:
        for wall in walls:
            assert apart(box, wall) >= 2 - 1e-9, (name, cs, kind, cell_of(box, cs), box, wall)


@pytest.mark.parametrize("kind", ["q", "values"])
@pytest.mark.parametrize("cs", BIG)
def test_numbers_under_a_label_keep_two_pixels_below_its_pill(cs, kind):
    """The START cell's north number lay under the pill."""
    level, ov = solved("mixed-8x8", kind)
    r, ops = drawn(level, ov, cs)
    pills = [bounds(op.points) for op in r.labels if isinstance(op, Fill)]
    boxes = number_boxes(level, ov, cs, r, ops)
    assert pills and r.labelled
    below = 0
    for pill in pills:
        for box in (b for b in boxes if cell_of(b, cs) == cell_of(pill, cs)):
            assert apart(box, pill) >= 2 - 1e-9, (cs, kind, cell_of(box, cs))
            below += 1
    assert below >= 1  # the start cell has numbers under its pill


@pytest.mark.parametrize("cs", BIG)
@pytest.mark.parametrize("name", ["mixed-8x8", "default", "walls"])
def test_arrows_keep_two_pixels_from_every_number(name, cs):
    """Arrow tips ran up to a number's box (1.5 px, less than the ring)."""
    level, ov = solved(name, "q")
    r, ops = drawn(level, ov, cs)
    arrows, boxes = arrow_parts(ops), number_boxes(level, ov, cs, r, ops)
    assert len(arrows) > 20 and len(boxes) > 30
    for a in arrows:
        for b in boxes:
            if cell_of(a, cs) == cell_of(b, cs):
                assert apart(a, b) >= 2 - 1e-9, (name, cs, cell_of(a, cs))


@pytest.mark.parametrize("kind", ["q", "values"])
@pytest.mark.parametrize("cs", (64, 92, 184))
@pytest.mark.parametrize("name", ["mixed-8x8", "default", "glass", "blocked"])
def test_tied_arrows_are_all_drawn_and_none_under_half_the_longest(name, cs, kind):
    """A tied arrow was drawn at a quarter of the other's length, or not at all."""
    level, ov = solved(name, kind)
    _, ops = drawn(level, ov, cs)
    lengths: dict[tuple[int, int], list[float]] = {}
    for a in arrow_outlines(ops):
        lengths.setdefault(cell_of(a, cs), []).append(max(a[2] - a[0], a[3] - a[1]))
    ties = [(int(x), int(y)) for y, x in zip(*np.nonzero(ov.arrows[:, :, 1:].sum(axis=2) >= 2))]
    assert ties
    for cell in ties:
        got = lengths.get(cell, [])
        assert len(got) == ov.arrows[cell[1], cell[0]].sum(), (name, cs, kind, cell)
        assert min(got) >= 0.5 * max(got), (name, cs, kind, cell, got)


@pytest.mark.parametrize("kind", ["q", "values"])
@pytest.mark.parametrize("cs", BIG)
@pytest.mark.parametrize("name", ["mixed-8x8", "default", "blocked"])
def test_no_arrow_covers_the_start_flag(name, cs, kind):
    """The START cell's arrow was drawn over its flag."""
    level, ov = solved(name, kind)
    _, ops = drawn(level, ov, cs)
    start = level.starts[0]
    flag = [bounds(op.points) for op in feature_ops(level, cs, LIGHT, corner=True)
            if isinstance(op, Fill) and op.colour == LIGHT.start_ink and cell_of(bounds(op.points), cs) == start]  # fmt: skip
    arrows = [a for a in arrow_outlines(ops) if cell_of(a, cs) == start]
    assert flag and arrows
    for a in arrows:
        for f in flag:
            assert apart(a, f) > 0, (name, cs, kind)


@pytest.mark.parametrize("cs", BIG)
def test_action_values_are_as_large_as_their_triangles_allow(cs):
    """Numbers stayed at 22 px type in large cells: the next size up (within 0.16 of the cell)
    must not fit every number in its triangle."""
    level = levels.get("maze-8x8")
    sol = planning.value_iteration(planning.model(level), gamma=1.0)
    q = np.round(sol.q.reshape(level.height, level.width, 5))
    q[np.isnan(sol.value_grid)] = np.nan
    labels = annotate.q_labels(q, cs)
    (size,) = {lb.size for lbs in labels.values() for lb in lbs}
    bigger = [s for s in qlabels._sizes_down(int(cs * 0.16)) if s > size]
    assert bigger or size == max(qlabels._sizes_down(int(cs * 0.16)))
    if bigger:
        depths = qlabels.border_depths(q.shape[:2], cs)
        fits = all(qlabels._q_label(lb.action, cell, lb.text, cs, (min(bigger),), qlabels.clearance(*cell, depths, cs))
                   for cell, lbs in labels.items() for lb in lbs)  # fmt: skip
        assert not fits, (cs, size, min(bigger))


def test_two_values_that_differ_never_print_alike():
    """-8.8 and -9 both printed as -9 (the array beside the picture shows -8.8)."""
    level = levels.get("mixed-8x8")
    sol = planning.value_iteration(planning.model(level), gamma=1.0)
    ov = update_overlay(Overlay(), level, values=sol.value_grid)
    texts = {}
    for op in annotate.ink_ops(ov, 92, LIGHT):
        if isinstance(op, Text):
            value = float(sol.value_grid[int(op.y // 92), int(op.x // 92)])
            texts.setdefault(op.text, set()).add(round(value, 1))
    assert len(texts) > 20
    assert all(len(values) == 1 for values in texts.values()), {t: v for t, v in texts.items() if len(v) > 1}
    assert {"-8.8", "-9.0"} <= set(texts)
    rng = np.random.default_rng(0)
    for _ in range(20):  # any picture: values apart at one decimal never share a text
        vals = np.round(rng.uniform(-30, 30, size=(8, 8)), rng.integers(0, 3))
        fmt = update_overlay(Overlay(), level, values=vals).scale.format
        assert len({fmt(v) for v in np.round(vals, 1).ravel()}) == len(np.unique(np.round(vals, 1)))
