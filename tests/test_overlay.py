"""Overlays on rgb_array frames: values in boxes, arrows under them, action values in their
triangles, text, the panel and colour bar; checks and clearing."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

from babyrobot_marl import Action, race_v0
from babyrobot_marl.envs.single import BabyRobotEnv
from babyrobot_marl.render import annotate
from babyrobot_marl.render.overlay import Overlay, update_overlay
from babyrobot_marl.render.paint import Fill
from babyrobot_marl.render.palette import THEMES, colour_map
from babyrobot_marl.render.picture import wall_width

CS = 64
LIGHT = THEMES["light"]


def env_with(level="maze-8x8", cs=CS, **kw) -> BabyRobotEnv:
    env = BabyRobotEnv(level=level, render_mode="rgb_array", cell_size=cs, **kw)
    env.reset(seed=0)
    return env


def px(img, x, y, u, v, cs=CS):
    """Pixel at fraction (u, v) of cell (x, y)."""
    return tuple(int(c) for c in img[int((y + v) * cs), int((x + u) * cs)])


def cell(img, x, y, cs=CS):
    return img[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs]


def has(pixels, colour) -> bool:
    return bool((pixels.reshape(-1, 3) == colour).all(axis=1).any())


def tinted(floor, colour, alpha=0.82):
    return tuple(int(f * (1 - alpha) + c * alpha + 0.5) for f, c in zip(floor, colour))


def test_values_tint_cells_by_the_colour_map_from_lowest_to_highest():
    env = env_with()
    values = np.zeros((8, 8))
    values[6, 6], values[2, 2] = 5.0, -5.0
    env.set_overlay(values=values)
    img = env.render()
    top, bottom = (tuple(c) for c in colour_map(np.array([1.0, 0.0]), "viridis", 0.0, 1.0).tolist())
    # a corner of the cell, away from the box and arrows: the tint over the floor
    assert np.allclose(px(img, 6, 6, 0.2, 0.9), tinted(LIGHT.floor, top), atol=2)
    assert np.allclose(px(img, 2, 2, 0.2, 0.9), tinted(LIGHT.floor, bottom), atol=2)


def test_value_numbers_sit_in_dark_boxes_with_light_text():
    env = env_with()
    env.set_overlay(values=np.full((8, 8), -3.5))
    img = env.render()
    box = cell(img, 3, 3)
    assert has(box, LIGHT.value_text)  # the text's solid pixels
    dark = (np.abs(box.astype(int) - LIGHT.value_box).sum(axis=2) < 60).sum()
    assert dark > 40  # the box behind it


def test_nan_values_leave_the_cell_as_it_was():
    env = env_with()
    plain = env.render()
    values = np.full((8, 8), np.nan)
    values[0, 5] = 1.0
    env.set_overlay(values=values)
    img = env.render()
    grid = plain.shape[0]
    assert (cell(img[:grid], 3, 3) == cell(plain, 3, 3)).all()
    assert not (cell(img[:grid], 5, 0) == cell(plain, 5, 0)).all()


@pytest.mark.parametrize(
    ("action", "dx", "dy"), [(Action.EAST, 1, 0), (Action.WEST, -1, 0), (Action.NORTH, 0, -1), (Action.SOUTH, 0, 1)]
)
def test_an_arrow_is_centred_in_its_cell_and_its_head_points_its_way(action, dx, dy):
    from babyrobot_marl.render.annotate import ROBOT_RIGHT, ROBOT_TOP

    env = env_with()
    arrows = np.zeros((8, 8), dtype=int)
    arrows[3, 4] = int(action)
    env.set_overlay(arrows=arrows)
    white = (cell(env.render(), 4, 3) == LIGHT.arrow).all(axis=2)
    ys, xs = np.nonzero(white)
    along = (xs - CS / 2) * dx + (ys - CS / 2) * dy  # pixels along the arrow, from the cell's centre
    assert abs(along.min() + along.max()) < 0.15 * CS  # centred
    if dx:  # E and W: clear of the robot in its corner
        assert not ((xs < ROBOT_RIGHT * CS) & (ys > ROBOT_TOP * CS)).any()
    axis = (ys.min() + ys.max()) / 2 if dx else (xs.min() + xs.max()) / 2  # E and W: above the robot's corner
    across = np.abs((xs - axis) * dy - (ys - axis) * dx)
    assert across[along > along.max() - 0.2 * CS].max() >= 1.8 * across[along < along.min() + 0.15 * CS].max()  # the head


def arrow_shapes(ops):
    return [op for op in ops if isinstance(op, Fill) and op.colour == LIGHT.arrow]


@pytest.mark.parametrize("cs", [32, 48, 64])
@pytest.mark.parametrize("values", [False, True])
def test_arrows_are_at_least_a_third_of_the_cell_and_ties_are_distinct_arrows(cs, values):
    """Every arrow, alone or tied (two, three, four ways), is at least cs / 3 long; tied arrows
    do not touch (they are not drawn from one point); on mixed-8x8, cell (3, 0) has a tie."""
    level = env_with().level
    ties = [(a,) for a in (1, 2, 3, 4)] + [(1, 3), (2, 4), (2, 3), (1, 4), (3, 4), (1, 2), (1, 2, 3), (1, 2, 3, 4)]
    for actions in ties:
        arrows = np.zeros((8, 8, 5), dtype=bool)
        arrows[4, 4, list(actions)] = True
        vals = np.full((8, 8), -12.5) if values else None
        ov = update_overlay(Overlay(), level, arrows=arrows, values=vals)
        shapes = arrow_shapes(annotate.ink_ops(ov, cs, LIGHT))
        assert len(shapes) == len(actions)
        for s in shapes:
            ext = s.points.max(axis=0) - s.points.min(axis=0)
            if len(actions) <= 2:
                assert ext.max() >= cs / 3 - 1, (actions, cs, ext)
            assert (s.points >= 4 * cs - 0.5).all() and (s.points <= 5 * cs + 0.5).all()  # inside its cell
        boxes = [(s.points.min(axis=0), s.points.max(axis=0)) for s in shapes]
        for i in range(len(boxes)):
            for j in range(i + 1, len(boxes)):
                (a0, a1), (b0, b1) = boxes[i], boxes[j]
                gap = np.maximum(b0 - a1, a0 - b1).max()  # > 0: apart along some axis
                assert gap > 0 or _apart(shapes[i].points, shapes[j].points), (actions, cs)


def _apart(a, b) -> bool:
    """No corner of either shape within 1 pixel of the other's corners (two arrows, not a scribble)."""
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return bool(d.min() > 1.0)


def test_cell_3_0_of_mixed_8x8_draws_its_tie_as_two_separate_arrows():
    from babyrobot_marl import planning

    env = env_with(level="mixed-8x8")
    sol = planning.value_iteration(planning.model(env.level), gamma=1.0)
    assert sol.best_actions[0, 3].sum() >= 2  # a tie there
    ov = update_overlay(Overlay(), env.level, arrows=sol.best_actions, values=sol.value_grid)
    shapes = [s for s in arrow_shapes(annotate.ink_ops(ov, CS, LIGHT)) if (s.points.mean(axis=0) // CS == (3, 0)).all()]
    assert len(shapes) == sol.best_actions[0, 3].sum()
    tails = [s.points[[0, -1]].mean(axis=0) for s in shapes]
    assert np.linalg.norm(tails[0] - tails[1]) > CS / 6  # not from one point


def test_arrows_never_cover_the_value_boxes():
    """Where values are shown the arrows are drawn under the box, not across it."""
    level = env_with().level
    rng = np.random.default_rng(0)
    for cs in (32, 48, 64, 96):
        ov = update_overlay(Overlay(), level, values=rng.normal(size=(8, 8)) * 10, arrows=np.ones((8, 8, 5), dtype=bool))
        ops = annotate.ink_ops(ov, cs, LIGHT)
        arrows = [op for op in ops if isinstance(op, Fill) and len(op.points) == 7]  # the arrow shapes: 7 corners
        boxes = [op for op in ops if isinstance(op, Fill) and len(op.points) != 7 and op.colour == LIGHT.value_box]
        assert boxes and arrows
        box_bottom = {(int(b.points[:, 0].mean() // cs), int(b.points[:, 1].mean() // cs)): b.points[:, 1].max() for b in boxes}
        for a in arrows:
            key = (int(a.points[:, 0].mean() // cs), int(a.points[:, 1].mean() // cs))
            assert a.points[:, 1].min() >= box_bottom[key] - 0.5, (cs, key)


def test_q_values_tint_the_four_triangles_by_action_and_show_their_numbers():
    env = env_with(cs=96)
    q = np.zeros((8, 8, 5))
    q[:, :, Action.NORTH] = 1.0  # the best: the top colour
    q[:, :, Action.SOUTH] = -1.0
    env.set_overlay(q_values=q)
    img = env.render()
    top, bottom = (tuple(c) for c in colour_map(np.array([1.0, 0.0]), "viridis", 0.0, 1.0).tolist())
    assert np.allclose(px(img, 3, 3, 0.5, 0.32, 96), tinted(LIGHT.floor, top), atol=2)
    assert np.allclose(px(img, 3, 3, 0.5, 0.68, 96), tinted(LIGHT.floor, bottom), atol=2)
    assert has(cell(img, 3, 3, 96), LIGHT.value_text)


def test_text_is_drawn_in_its_cell_only():
    env = env_with()
    plain = env.render()
    env.set_overlay(text={(6, 1): "hi"})
    img = env.render()
    changed = np.argwhere((img != plain).any(axis=2))
    assert len(changed) > 0
    (x0, y0), exits = env.robot_cell, env.level.exits
    moved = {(y0, x0), *((y, x) for x, y in [*env.level.starts, *exits])}  # the robot and icons go to their corners
    assert set(map(tuple, changed // CS)) - moved == {(1, 6)}  # (row, column) of cell (6, 1)
    assert has(cell(img, 6, 1), LIGHT.value_text)


def test_a_panel_adds_rows_below_the_grid_wraps_long_lines_and_the_grid_is_unchanged():
    env = env_with(level="default")
    plain = env.render()
    env.set_overlay(panel=["step 3", "return -2.5 " + "and a long line that cannot fit in a 3x3 grid " * 2])
    img = env.render()
    assert img.shape[0] > plain.shape[0] + 60 and img.shape[1:] == plain.shape[1:]  # wrapped onto several lines
    assert (img[: plain.shape[0]] == plain).all()
    panel = img[plain.shape[0] :]
    assert has(panel, LIGHT.text)
    assert (panel[:, -2:] == LIGHT.panel).all()  # nothing reaches the right edge: no text cut


def test_values_come_with_a_colour_bar_from_lowest_to_highest():
    env = env_with()
    plain = env.render()
    env.set_overlay(values=np.arange(64.0).reshape(8, 8))
    panel = env.render()[plain.shape[0] :]
    stops = colour_map(np.array([0.0, 1.0]), "viridis", 0.0, 1.0)
    for colour in stops:
        assert has(panel, tuple(colour.tolist()))
    xs = [np.nonzero((panel == c).all(axis=2))[1].mean() for c in stops]
    assert xs[0] < xs[1]  # low on the left


def test_parts_not_given_are_kept_none_clears_one_and_clear_overlay_clears_all():
    env = env_with()
    plain = env.render()
    env.set_overlay(values=np.ones((8, 8)))
    env.set_overlay(arrows=np.full((8, 8), int(Action.EAST)))
    assert env.overlay.values is not None and env.overlay.arrows is not None
    env.set_overlay(values=None)
    assert env.overlay.values is None and env.overlay.arrows is not None
    env.clear_overlay()
    assert env.overlay.empty
    assert (env.render() == plain).all()


def test_overlays_lie_under_the_robot_and_the_start_label_over_it():
    env = env_with()
    env.set_overlay(values=np.arange(64.0).reshape(8, 8), arrows=np.full((8, 8), int(Action.SOUTH)))
    a, b = env.render(), env.render()
    assert (a == b).all()
    x, y = env.robot_cell
    robot_cell = cell(a, x, y)
    assert has(robot_cell, LIGHT.robots[0]) and has(robot_cell, LIGHT.eye)
    assert has(robot_cell[: CS // 4], LIGHT.label_bg)  # the START pill, over the robot


BAD = [
    (dict(values=np.zeros((3, 3))), "values"),
    (dict(values="high"), "values"),
    (dict(values=np.full((8, 8), "1.5")), "values"),
    (dict(values=np.full((8, 8), 1 + 2j)), "values"),
    (dict(values=np.full((8, 8), np.inf)), "values"),
    (dict(values=np.zeros((8, 8), dtype=bool)), "values"),
    (dict(q_values=np.zeros((8, 8, 3))), "q_values"),
    (dict(q_values=np.full((8, 8, 5), 1j)), "q_values"),
    (dict(arrows=np.full((8, 8), 7)), "arrows"),
    (dict(arrows=np.zeros((8, 8), dtype=float)), "arrows"),
    (dict(arrows=np.zeros((8, 8, 2), dtype=bool)), "arrows"),
    (dict(text={(9, 0): "x"}), "text"),
    (dict(text={(0, 0): 5}), "text"),
    (dict(text=["x"]), "text"),
    (dict(panel=5), "panel"),
    (dict(panel=["ok", 3]), "panel"),
    (dict(names={3: "x"}), "names"),
    (dict(names={0: 5}), "names"),
]


@pytest.mark.parametrize("kwargs, name", BAD)
def test_bad_overlay_arguments_are_value_errors_naming_them_and_change_nothing(kwargs, name):
    env = env_with()
    env.set_overlay(values=np.ones((8, 8)))
    before = env.render()
    with pytest.raises(ValueError, match=f"^{name}"):
        env.set_overlay(**kwargs)
    assert (env.render() == before).all()


def test_the_race_draws_overlays_and_names_in_its_legend():
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=48)
    env.reset(seed=0)
    plain = env.render()
    h, w = env.unwrapped.level.height, env.unwrapped.level.width
    env.unwrapped.set_overlay(values=np.arange(h * w, dtype=float).reshape(h, w), panel="race")
    img = env.render()
    assert img.shape[0] > plain.shape[0]
    assert not (img[: h * 48] == plain[: h * 48]).all()
    env.unwrapped.set_overlay(names={"robot_0": "shortest", 1: "random"})
    assert env.unwrapped.overlay.names == {0: "shortest", 1: "random"}
    assert env.unwrapped._scene().legend[0].name == "shortest"


def test_overlays_work_through_gymnasium_make():
    env = gymnasium.make("babyrobot_marl/BabyRobot-v0", level="maze-8x8", render_mode="rgb_array")
    env.reset(seed=0)
    env.unwrapped.set_overlay(arrows=np.full((8, 8), int(Action.EAST)))
    assert env.render().shape == (8 * 64, 8 * 64, 3)


def test_value_boxes_leave_the_walls_clear():
    for cs in (32, 64):
        ov = update_overlay(Overlay(), env_with().level, values=np.full((8, 8), -188.8))
        for op in annotate.ink_ops(ov, cs, LIGHT):
            if isinstance(op, Fill):
                x, _y = int(op.points[:, 0].mean() // cs), int(op.points[:, 1].mean() // cs)
                m = wall_width(cs) / 2
                assert op.points[:, 0].min() >= x * cs + m - 0.5 and op.points[:, 0].max() <= (x + 1) * cs - m + 0.5


def test_values_near_the_float_maximum_draw_without_a_warning_and_keep_their_order():
    import warnings

    top = np.finfo(np.float64).max
    env = BabyRobotEnv(level="default", render_mode="rgb_array")
    env.reset(seed=0)
    values = np.array([[-top, 0.0, top], [top / 2, -top / 2, 1.0], [np.nan, top, -top]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's "overflow encountered in subtract" fails the test
        env.set_overlay(values=values, q_values=np.stack([values] * 5, axis=2), panel="huge")
        env.render()
        colours = colour_map(values, THEMES["light"].colour_map)
    assert (colours[0, 0] == colour_map(np.array([0.0, 1.0]), THEMES["light"].colour_map)[0]).all()  # lowest
    assert (colours[0, 2] == colour_map(np.array([0.0, 1.0]), THEMES["light"].colour_map)[1]).all()  # highest
    assert (colours[0, 1] == colour_map(np.array([0.0, 0.5, 1.0]), THEMES["light"].colour_map)[1]).all()  # the middle


def test_one_number_format_per_overlay_chosen_from_the_range():
    """Values from -8.8 to -0.69: one decimal for every number (not -8.8, -.69 and 0 mixed)."""
    level = env_with().level
    vals = np.full((8, 8), -3.0)
    vals[0, 0], vals[0, 1], vals[0, 2] = -8.8, -0.69, 0.0
    ov = update_overlay(Overlay(), level, values=vals)
    texts = {op.text for op in annotate.ink_ops(ov, CS, LIGHT) if hasattr(op, "text")}
    assert texts == {"-8.8", "-0.7", "0.0", "-3.0"}
    assert update_overlay(Overlay(), level, values=vals * 10).scale.format(-6.9) == "-7"  # whole numbers from 10 up
    assert update_overlay(Overlay(), level, values=vals / 10).scale.format(-0.069) == "-0.07"


def test_the_colour_bar_has_ticks_and_the_overlays_own_label():
    env = env_with()
    env.set_overlay(values=np.round(np.linspace(-17, 0, 64)).reshape(8, 8))  # whole numbers: ticks without decimals
    from babyrobot_marl.render.panel import _colour_bar

    ops = _colour_bar(512, 40, 13, env.unwrapped.overlay.scale, LIGHT)
    words = [op.text for op in ops if hasattr(op, "text")]
    assert words[0] == "value" and {"-17", "-10", "-5", "0"} <= set(words)
    ov = update_overlay(env.unwrapped.overlay, env.level, label="gap")
    assert [op.text for op in _colour_bar(512, 40, 13, ov.scale, LIGHT) if hasattr(op, "text")][0] == "gap"
    with pytest.raises(ValueError, match="^label: "):
        update_overlay(ov, env.level, label=3)


@pytest.mark.parametrize("cs", [32, 48, 64])
def test_action_values_sit_in_their_triangles_clear_of_walls_labels_and_the_robot_and_none_in_the_exit(cs):
    """Each number's box is inside its triangle, off the wall band, below a START label, outside
    the robot's corner; the exit shows none."""
    from babyrobot_marl.render.picture import label_band
    from babyrobot_marl.render.robot import CORNER
    from babyrobot_marl.render.shapes import Text

    env = env_with(level="mixed-8x8", cs=cs)
    q = np.random.default_rng(0).normal(size=(8, 8, 5)) * 9
    if cs == 32:  # one type size in every cell or none: only whole numbers of one digit fit 32 pixels
        q = np.clip(np.round(q / 3), -9, 9)
    env.set_overlay(q_values=q)
    r = env.unwrapped.drawing.renderer
    ops = annotate.ink_ops(env.unwrapped.overlay, cs, LIGHT, r.labelled, r.exits)
    texts = [op for op in ops if isinstance(op, Text)]
    assert texts
    m = wall_width(cs) / 2
    s, ux, uy = CORNER
    for t in texts:
        x, y = int(t.x // cs), int(t.y // cs)
        u, v = t.x / cs - x, t.y / cs - y
        assert (x, y) not in r.exits
        half = annotate.text_width(t.text, t.size) / 2 / cs
        assert m / cs < u - half and u + half < 1 - m / cs  # clear of the walls
        assert not (abs(u - ux) < s / 2 and abs(v - uy) < s / 2)  # not on the robot's corner
        if (x, y) in r.labelled:
            assert v * cs > label_band(cs)[1]
        # inside its triangle: the centre is nearer its own edge than any other
        d = {"N": v, "S": 1 - v, "W": u, "E": 1 - u}
        assert min(d.values()) < 0.5


@pytest.mark.parametrize("theme", ["light", "dark"])
@pytest.mark.parametrize("cs", [32, 48, 64])
@pytest.mark.parametrize("action", [Action.EAST, Action.WEST])
@pytest.mark.parametrize("values", [True, False])
def test_a_horizontal_arrow_does_not_run_under_the_robot_in_its_corner(cs, action, theme, values):
    """Issue 26 (follow-up): in the start cell an E or W arrow ran partly under the robot."""
    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=cs, theme=theme)
    env.reset(seed=0)
    u = env.unwrapped
    u.set_overlay(values=np.linspace(-9, 0, 64).reshape(8, 8) if values else None, arrows=np.full((8, 8), int(action)))
    x, y = u.robot_cell
    th = THEMES[theme]
    under = u.rgb_renderer.static(u.overlay)[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs]
    shown = env.render()[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs]
    arrow = (under == th.arrow).all(axis=2)
    assert arrow.sum() >= cs // 4  # there is an arrow
    assert ((shown == th.arrow).all(axis=2) & arrow).sum() == arrow.sum()  # all of it still shows


def _q_case(name: str, cs: int, theme: str) -> BabyRobotEnv:
    """An env with action values and the best actions as arrows: value iteration's on a level,
    or ("ties") every tie on maze-8x8 with the widest numbers that show at that size (one
    decimal, ``-8.8``, from 48 px; at 32 px only whole numbers of one digit fit beside the walls,
    so there the values are scaled into -9..0: numbers show in every cell or in none)."""
    from babyrobot_marl import planning

    env = BabyRobotEnv(level="maze-8x8" if name == "ties" else name, render_mode="rgb_array", cell_size=cs, theme=theme)
    env.reset(seed=0)
    h, w = env.level.height, env.level.width
    if name == "ties":
        rng = np.random.default_rng(1)
        q = np.round(rng.uniform(-9.9, -1.1, size=(h, w, 5)), 1) if cs >= 48 else rng.integers(-9, 0, size=(h, w, 5)) * 1.0
        combos = [(a,) for a in (1, 2, 3, 4)] + [(1, 3), (2, 4), (2, 3), (1, 4), (3, 4), (1, 2), (1, 2, 3), (1, 2, 3, 4)]
        arrows = np.zeros((h, w, 5), dtype=bool)
        for k, (y, x) in enumerate(np.ndindex(h, w)):
            arrows[y, x, list(combos[k % len(combos)])] = True
    else:
        sol = planning.value_iteration(planning.model(env.level), gamma=1.0)
        q = sol.q.reshape(h, w, 5).copy()
        q[np.isnan(sol.value_grid)] = np.nan
        if cs == 32:  # the numbers in every cell or in none: at 32 px one digit, so the values scaled into -9..0
            q = np.round(q * 9 / max(9.0, -np.nanmin(q)))
        arrows = sol.best_actions
    env.set_overlay(q_values=q, arrows=arrows)
    return env


def _number_boxes(ops) -> list:
    """The boxes drawn under each number (the fills just before its text, an edge included; not arrows)."""
    from babyrobot_marl.render.shapes import Text

    out = []
    for i, op in enumerate(ops):
        j = i - 1
        while isinstance(op, Text) and j >= 0 and isinstance(ops[j], Fill) and len(ops[j].points) != 7:
            out.append(ops[j])
            j -= 1
    return out


def _touched(points, w: int, h: int) -> tuple[tuple[slice, slice], np.ndarray]:
    """The pixels of a ``w`` x ``h`` frame that the rasteriser touches for a polygon: a window of the
    frame (``(rows, columns)`` slices) and its mask. A pixel whose centre lies more than half a pixel
    outside the polygon's bounding box gets no ink, so the window is the box grown by a pixel; the
    coverage of a pixel does not depend on the window, so the mask is the whole frame's, cut."""
    from babyrobot_marl.render.paint import coverage

    (ax, ay), (bx, by) = points.min(axis=0), points.max(axis=0)
    x0, y0 = max(int(np.floor(ax)) - 1, 0), max(int(np.floor(ay)) - 1, 0)
    x1, y1 = min(int(np.ceil(bx)) + 2, w), min(int(np.ceil(by)) + 2, h)
    if x1 <= x0 or y1 <= y0:
        return (slice(0, 0), slice(0, 0)), np.zeros((0, 0), dtype=bool)
    return (slice(y0, y1), slice(x0, x1)), coverage(points, x0, y0, x1 - x0, y1 - y0) > 0


@pytest.mark.parametrize("level", ["mixed-8x8", "walls", "ties"])
@pytest.mark.parametrize("theme", ["light", "dark"])
@pytest.mark.parametrize("cs", [32, 48, 64])
def test_action_value_boxes_never_lie_under_arrows(cs, theme, level):
    """Issue 26 (review): the longer arrows ran over the action values' numbers. No pixel the
    rasteriser touches for an arrow (its dark edge included) is touched by a number's box."""
    env = _q_case(level, cs, theme)
    r = env.unwrapped.drawing.renderer
    ops = annotate.ink_ops(env.unwrapped.overlay, cs, THEMES[theme], r.labelled, r.exits)
    h, w = env.level.height * cs, env.level.width * cs
    arrows = np.zeros((h, w), dtype=bool)
    for op in ops:
        if isinstance(op, Fill) and len(op.points) == 7:  # the arrow shapes: 7 corners
            window, mask = _touched(op.points, w, h)
            arrows[window] |= mask
    boxes = _number_boxes(ops)
    assert arrows.sum() > 0 and len(boxes) >= 8
    for b in boxes:
        window, covered = _touched(b.points, w, h)
        at = b.points.mean(axis=0) // cs
        assert not (covered & arrows[window]).any(), (level, cs, theme, "cell", tuple(at.astype(int)))


def test_the_touched_window_holds_every_pixel_the_whole_frame_inks():
    """The windowed masks the test above reads equal the whole frame's coverage, for arrows,
    rectangles and shapes at the frame's edges."""
    from babyrobot_marl.render.paint import coverage

    w, h = 40, 30
    shapes = [np.array([[3.2, 4.7], [20.5, 4.7], [20.5, 9.1], [3.2, 9.1]]),  # a rectangle
              np.array([[0.0, 0.0], [12.3, 2.0], [5.5, 11.9]]),  # a triangle at the corner
              np.array([[30.0, 20.0], [41.5, 22.0], [39.0, 31.0], [33.0, 29.5], [31.0, 27.0], [29.5, 24.0], [30.5, 21.0]])]
    for points in shapes:
        whole = coverage(points, 0, 0, w, h) > 0
        window, mask = _touched(points, w, h)
        cut = np.zeros((h, w), dtype=bool)
        cut[window] = mask
        assert whole.any() and (cut == whole).all()


@pytest.mark.parametrize("cs", [32, 48, 64])
def test_with_action_values_the_best_numbers_are_ringed_and_lone_vertical_arrows_stay_a_third_of_the_cell(cs):
    """Where the arrows must stay short (the E and W numbers share the middle row), each best
    action's number is ringed in the arrow's white, and only those; a lone N or S arrow still
    spans a third of the cell from 48 px (at 32 px two-digit numbers leave it room or none)."""
    from babyrobot_marl.render.shapes import Text

    env = _q_case("mixed-8x8", cs, "light")
    r = env.unwrapped.drawing.renderer
    ov = env.unwrapped.overlay
    ops = annotate.ink_ops(ov, cs, LIGHT, r.labelled, r.exits)
    ringed, plain = 0, 0
    for i, t in enumerate(ops):
        if not isinstance(t, Text):
            continue
        x, y = int(t.x // cs), int(t.y // cs)
        u, v = t.x / cs - x, t.y / cs - y
        action = min({Action.NORTH: v, Action.SOUTH: 1 - v, Action.WEST: u, Action.EAST: 1 - u}.items(), key=lambda kv: kv[1])[0]
        ring = isinstance(ops[i - 2], Fill) and ops[i - 2].colour == LIGHT.arrow and len(ops[i - 2].points) != 7
        assert ring == bool(ov.arrows[y, x, action]), ((x, y), action)
        ringed, plain = ringed + ring, plain + (not ring)
    assert ringed >= 8 and plain >= 8
    if cs >= 48:
        lone = [(x, y) for y, x in zip(*np.nonzero(ov.arrows[:, :, 1:].sum(axis=2) == 1)) if ov.arrows[y, x, [1, 3]].any()]
        shapes = [s for s in arrow_shapes(ops) if len(s.points) == 7]  # not the rings
        assert len(lone) >= 4
        for x, y in lone:
            (s,) = [s for s in shapes if (s.points.mean(axis=0) // cs == (x, y)).all()]
            assert np.ptp(s.points[:, 1]) >= cs / 3 - 1, ((x, y), cs)
