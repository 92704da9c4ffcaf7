"""The picture's promises, measured: text inside its cell at every size, contrast in every theme,
colour-blind-safe robots, the font, the robot's poses, PNG snapshots, bounded caches."""

from __future__ import annotations

import io
import itertools

import numpy as np
import pytest

from babyrobot_marl import levels, planning
from babyrobot_marl.core.actions import Action
from babyrobot_marl.render import annotate, glyphs, sprites
from babyrobot_marl.render.canvas import png_bytes
from babyrobot_marl.render.overlay import Overlay, update_overlay
from babyrobot_marl.render.paint import Text, raster
from babyrobot_marl.render.palette import ROBOT_COLOURS, THEMES, contrast_ratio, delta_e, simulate_cvd
from babyrobot_marl.render.picture import label_ops
from babyrobot_marl.render.robot import POSES, robot
from babyrobot_marl.render.sprites import robot_sprite as sprite

SIZES = (32, 48, 64, 96)


def full_overlay(level) -> Overlay:
    """Values, action values, arrows (ties included) and text on every cell a robot can stand on."""
    sol = planning.value_iteration(planning.model(level), gamma=0.95)
    h, w = level.height, level.width
    q = np.asarray(sol.q, dtype=float).reshape(h, w, -1) * 11.37  # longer numbers
    text = {(x, y): "visited" for x, y in list(level.free_cells())[:6]}
    return update_overlay(
        Overlay(), level, values=sol.value_grid * 11.37, q_values=q, arrows=np.ones((h, w, 5), dtype=bool), text=text
    )


def cell_of(op: Text, cs: int) -> tuple[int, int]:
    return int(op.x // cs), int(op.y // cs)


@pytest.mark.parametrize("name", levels.names())
def test_every_text_stays_inside_its_cell_at_every_cell_size(name):
    """Values, action values, cell text and START/EXIT: the inked pixels of each lie in its own cell."""
    level = levels.get(name)
    ov = full_overlay(level)
    theme = THEMES["light"]
    for cs in SIZES:
        texts = [op for op in annotate.ink_ops(ov, cs, theme) + label_ops(level, cs, theme) if isinstance(op, Text)]
        assert texts, (name, cs)
        for op in texts:
            x, y = cell_of(op, cs)
            box = glyphs.ink_box(op)
            assert box is not None
            x0, y0, x1, y1 = box
            assert x * cs <= x0 and x1 <= (x + 1) * cs and y * cs <= y0 and y1 <= (y + 1) * cs, (name, cs, op.text, box)


def q_number_ops(q: np.ndarray, cs: int, labelled: frozenset = frozenset()) -> list:
    """What the action values' numbers draw (their boxes and texts), light theme."""
    return [op for labels in annotate.q_labels(q, cs, labelled).values() for label in labels for op in label.ops(THEMES["light"])]


@pytest.mark.parametrize("cs", SIZES)
@pytest.mark.parametrize("scale", [1.0, 0.04])  # numbers like -192 and like -8
def test_action_values_are_printed_inside_their_own_triangle(cs, scale):
    level = levels.get("maze-8x8")
    q = full_overlay(level).q_values * scale
    numbers = [op for op in q_number_ops(np.round(q) if scale < 1 else q, cs)]
    texts = [op for op in numbers if isinstance(op, Text)]
    long_numbers = scale == 1 and cs <= 48  # "-192" fits no east or west triangle of a 48-pixel cell
    assert len(texts) == 0 if long_numbers else len(texts) > 40
    for op in texts:
        x, y = cell_of(op, cs)
        u0, v0, u1, v1 = (np.array(glyphs.ink_box(op)) - (x * cs, y * cs, x * cs, y * cs)) / cs
        corners = [(u0, v0), (u1, v0), (u0, v1), (u1, v1)]
        # which triangle: the one whose edge is nearest the text's centre
        u, v = (u0 + u1) / 2, (v0 + v1) / 2
        action = min([(v, Action.NORTH), (1 - u, Action.EAST), (1 - v, Action.SOUTH), (u, Action.WEST)], key=lambda t: t[0])[1]
        for cu, cv in corners:
            inside = {
                Action.NORTH: cv <= min(cu, 1 - cu),
                Action.SOUTH: 1 - cv <= min(cu, 1 - cu),
                Action.WEST: cu <= min(cv, 1 - cv),
                Action.EAST: 1 - cu <= min(cv, 1 - cv),
            }[action]
            assert inside, (cs, op.text, action, (cu, cv))


@pytest.mark.parametrize("cs", SIZES)
@pytest.mark.parametrize("scale", [1.0, 0.04])
def test_action_values_show_in_every_cell_in_one_type_size_or_in_none(cs, scale):
    """Numbers in some cells and not in others read as a mistake: every cell a robot can stand on
    gets its four numbers, all in one type size, or (too long for the cell) no cell gets any."""
    level = levels.get("maze-8x8")
    q = full_overlay(level).q_values * scale
    q = np.round(q) if scale < 1 else q
    labels = annotate.q_labels(q, cs)
    free = {(x, y) for x, y in level.free_cells()}
    if labels:
        assert free <= set(labels) and all(len(v) == 4 for v in labels.values())
        assert len({lb.size for v in labels.values() for lb in v}) == 1
    assert bool(labels) == (not (cs <= 48 and scale == 1))  # "-192" fits no east or west triangle of a 48-pixel cell


def test_text_that_cannot_fit_is_left_out_never_cut():
    level = levels.get("maze-16x16")
    ov = update_overlay(Overlay(), level, values=np.full((16, 16), -123456.7))
    texts = [op for op in annotate.ink_ops(ov, 8, THEMES["light"]) if isinstance(op, Text)]
    assert texts == []


# ---------------------------------------------------------------------- contrast
GRAPHIC_PAIRS = [  # must be told apart at a glance: WCAG 3:1 for lines and ink
    ("floor", "wall"),
    ("floor", "glass_frame"),
    ("glass", "glass_frame"),
    ("floor", "robot_ink"),
    ("visor", "eye"),
    ("arrow", "arrow_edge"),
]
TEXT_PAIRS = [("label_text", "label_bg"), ("value_text", "value_box"), ("text", "panel")]  # 4.5:1
FILL_PAIRS = [  # areas: a clear colour difference (CIE76 delta E)
    ("floor", "small_puddle"),
    ("small_puddle", "large_puddle"),
    ("floor", "large_puddle"),
    ("floor", "blocked"),
    ("floor", "exit"),
    ("floor", "start"),
    ("wall", "glass"),
    ("exit", "start"),
]


@pytest.mark.parametrize("name", sorted(THEMES))
def test_every_pair_a_learner_must_tell_apart_passes_a_contrast_test(name):
    t = THEMES[name]
    for a, b in GRAPHIC_PAIRS:
        assert contrast_ratio(getattr(t, a), getattr(t, b)) >= 3.0, (name, a, b)
    for a, b in TEXT_PAIRS:
        assert contrast_ratio(getattr(t, a), getattr(t, b)) >= 4.5, (name, a, b)
    for a, b in FILL_PAIRS:
        assert delta_e(getattr(t, a), getattr(t, b)) >= 10.0, (name, a, b)


def test_the_contrast_measures_are_the_standard_ones():
    assert contrast_ratio((0, 0, 0), (255, 255, 255)) == pytest.approx(21.0)
    assert contrast_ratio((118, 118, 118), (255, 255, 255)) == pytest.approx(4.54, abs=0.02)  # WCAG's grey on white
    assert simulate_cvd((255, 255, 255), "deuteranopia") == (255, 255, 255)
    assert delta_e((255, 0, 0), (0, 255, 0)) > 100


@pytest.mark.parametrize("kind", ["protanopia", "deuteranopia", "tritanopia", None])
def test_the_first_eight_robot_colours_stay_distinct_for_colour_blind_readers(kind):
    colours = [c if kind is None else simulate_cvd(c, kind) for c in ROBOT_COLOURS[:8]]
    worst = min(delta_e(a, b) for a, b in itertools.combinations(colours, 2))
    assert worst >= 10.0, kind


def test_robots_beyond_the_palette_stay_distinguishable_by_their_number():
    """Twelve colours, then the numbers: the sprites of 0..23 are all different images."""
    theme = THEMES["light"]
    images = {raster(sprite(theme, i, 0, "idle", True, 64.0).ops(32, 32), 64, 64, theme.floor).tobytes() for i in range(24)}
    assert len(images) == 24


def test_each_pose_and_heading_draws_a_different_robot():
    theme = THEMES["light"]
    images = set()
    for pose in POSES:
        for heading in range(5):
            images.add(raster(robot(32, 32, 64, theme, ROBOT_COLOURS[0], heading, pose), 64, 64, theme.floor).tobytes())
    assert len(images) == len(POSES) * 5 - 0


def test_the_robot_is_anti_aliased_not_jagged():
    theme = THEMES["light"]
    img = raster(robot(32, 32, 64, theme, ROBOT_COLOURS[0]), 64, 64, (255, 255, 255))
    colours = {tuple(p) for p in img.reshape(-1, 3)}
    assert len(colours) > 60  # edge pixels blend ink and background


# ---------------------------------------------------------------------- the font
def test_the_font_has_every_printable_character_at_every_size_with_real_proportions():
    for size in glyphs.sizes():
        assert glyphs.text_width("W", size) > glyphs.text_width("i", size) > 0
        assert glyphs.cap_height(size)[1] >= size * 0.6
    assert glyphs.sizes()[0] <= 7 and glyphs.sizes()[-1] >= 48


def test_text_is_drawn_with_grey_levels_and_fills_its_measured_width():
    op = Text(2, 10, "Baby Robot 0.5", 16, (0, 0, 0), align="left")
    img = raster([op], 200, 24, (255, 255, 255))
    ink = img[:, :, 0] < 250
    cols = np.nonzero(ink.any(axis=0))[0]
    assert abs((cols.max() - cols.min()) - glyphs.text_width(op.text, 16)) <= 3
    assert len(np.unique(img[:, :, 0])) > 20  # anti-aliased
    assert glyphs.ink_box(op) == (
        cols.min(),
        np.nonzero(ink.any(axis=1))[0].min(),
        cols.max() + 1,
        np.nonzero(ink.any(axis=1))[0].max() + 1,
    )


def test_characters_outside_the_font_are_drawn_as_question_marks_not_dropped():
    a = raster([Text(2, 10, "a\u00e9b", 16, (0, 0, 0), align="left")], 60, 24, (255, 255, 255))
    b = raster([Text(2, 10, "a?b", 16, (0, 0, 0), align="left")], 60, 24, (255, 255, 255))
    assert (a == b).all()


# ---------------------------------------------------------------------- PNG snapshot, caches
def test_png_snapshots_decode_to_the_exact_frame():
    from PIL import Image

    img = np.random.default_rng(0).integers(0, 256, size=(37, 53, 3), dtype=np.uint8)
    assert (np.array(Image.open(io.BytesIO(png_bytes(img)))) == img).all()


def test_text_measures_and_sprites_are_cached_in_bounded_caches():
    for i in range(5000):
        glyphs.text_width(f"panel line {i}", 12)
    assert glyphs.text_width.cache_info().currsize <= glyphs.text_width.cache_info().maxsize == 4096
    assert sprites._robot_sprite.cache.max_bytes > 0


@pytest.mark.parametrize("cs", SIZES)
def test_start_and_exit_labels_cover_no_value_box(cs):
    from babyrobot_marl.render.paint import Fill
    from babyrobot_marl.render.rgb import RgbRenderer

    level = levels.get("mixed-8x8")
    ov = update_overlay(Overlay(), level, values=np.full((8, 8), -12.5), arrows=np.ones((8, 8, 5), dtype=bool))
    r = RgbRenderer(level, cs)
    pills = [op for op in r.labels if isinstance(op, Fill)]
    boxes = [op for op in annotate.ink_ops(ov, cs, THEMES["light"], r.labelled) if isinstance(op, Fill) and len(op.points) != 7]
    assert pills and r.labelled == {level.starts[0], *level.exits} or cs == 32
    def cell_of_fill(f):
        return tuple((f.points.mean(axis=0) // cs).astype(int))

    for pill in pills:
        for box in (b for b in boxes if cell_of_fill(b) == cell_of_fill(pill)):
            apart = (
                pill.points[:, 1].max() <= box.points[:, 1].min() + 0.5
                or pill.points[:, 0].max() <= box.points[:, 0].min()
                or box.points[:, 0].max() <= pill.points[:, 0].min()
            )
            assert apart, (cs, pill.points.mean(axis=0), box.points.mean(axis=0))


@pytest.mark.parametrize("cs", SIZES)
def test_start_and_exit_labels_cover_no_action_value(cs):
    from babyrobot_marl.render.paint import Fill
    from babyrobot_marl.render.rgb import RgbRenderer

    level = levels.get("walls")
    r = RgbRenderer(level, cs)
    ov = full_overlay(level)
    pills = {tuple((op.points.mean(axis=0) // cs).astype(int)): op for op in r.labels if isinstance(op, Fill)}
    for op in q_number_ops(ov.q_values, cs, r.labelled):
        if isinstance(op, Text) and cell_of(op, cs) in pills:
            assert glyphs.ink_box(op)[1] >= pills[cell_of(op, cs)].points[:, 1].max(), (cs, op.text)


@pytest.mark.parametrize("theme", ["light", "dark"])
@pytest.mark.parametrize("cs", (32, 48, 64, 96, 128))
def test_the_robot_on_its_start_hides_the_whole_flag_which_shows_once_it_leaves(theme, cs):
    """At reset nothing of the start's flag peeks beside the robot (its head under the START label);
    one step later the flag is there."""
    from babyrobot_marl import BabyRobotEnv

    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=cs, theme=theme)
    env.reset(seed=0)
    ink = np.array(THEMES[theme].start_ink, dtype=np.uint8)

    def flag_pixels() -> int:  # in the flag's box: the tile's outline round it is drawn in the same ink
        box = env.render()[int(0.3 * cs) : int(0.9 * cs), int(0.3 * cs) : int(0.72 * cs)]
        return int((box == ink).all(axis=2).sum())

    assert env.robot_cell == (0, 0) and flag_pixels() == 0
    env.step(Action.EAST)
    assert env.robot_cell == (1, 0) and flag_pixels() > cs  # the pole alone is taller than that
