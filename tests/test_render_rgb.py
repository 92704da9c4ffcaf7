"""rgb_array frames: size, the robot character, the level as a picture, race scenes, themes, bad options."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import babyrobot_marl  # noqa: F401  (registers the envs)
from babyrobot_marl import BabyRobotEnv, Level, levels, race_v0
from babyrobot_marl.render.palette import THEMES, Theme, variant
from babyrobot_marl.render.rgb import MAX_FRAME_PIXELS, RgbRenderer, auto_cell_size

CS = 48


def cell(frame: np.ndarray, xy: tuple[int, int], cs: int = CS) -> np.ndarray:
    x, y = xy
    return frame[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs]


def has(pixels: np.ndarray, colour) -> bool:
    return bool((pixels.reshape(-1, 3) == colour).all(axis=1).any())


def count(pixels: np.ndarray, colour) -> int:
    return int((pixels.reshape(-1, 3) == colour).all(axis=1).sum())


def edge_strip(frame: np.ndarray, a, b, cs: int = CS, half: int = 1) -> np.ndarray:
    """The pixels on the shared edge of two neighbour cells, away from the corners."""
    if a[1] == b[1]:
        x = max(a[0], b[0]) * cs
        return frame[a[1] * cs + cs // 4 : (a[1] + 1) * cs - cs // 4, x - half : x + half]
    y = max(a[1], b[1]) * cs
    return frame[y - half : y + half, a[0] * cs + cs // 4 : (a[0] + 1) * cs - cs // 4]


@pytest.mark.parametrize("name", levels.names())
def test_a_single_robot_frame_is_uint8_of_the_level_size_in_cells_times_cell_size(name):
    level = levels.get(name)
    env = BabyRobotEnv(level=level, render_mode="rgb_array", cell_size=CS)
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.shape == (level.height * CS, level.width * CS, 3)


def test_the_default_cell_size_fills_a_notebook_column_and_stays_64_for_small_levels():
    assert auto_cell_size(levels.get("default")) == 64
    assert auto_cell_size(levels.get("maze-8x8")) == 64
    big = levels.get("maze-16x16")
    assert auto_cell_size(big) * big.width <= 896 and auto_cell_size(big) >= 40
    env = BabyRobotEnv(level="default", render_mode="rgb_array")
    env.reset(seed=0)
    assert env.render().shape == (192, 192, 3)  # the 3x3 level: 64-pixel cells, nothing clipped
    assert BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=20).cell_size == 20


def test_the_robot_is_drawn_in_its_colour_with_its_eyes_at_its_cell_and_moves_with_it():
    theme = THEMES["light"]
    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=CS)
    env.reset(seed=0)
    before = env.render()
    assert has(cell(before, (0, 0)), theme.robots[0]) and has(cell(before, (0, 0)), theme.eye)
    assert has(cell(before, (0, 0)), theme.visor)
    env.step(2)  # EAST: (0, 0) -> (1, 0) on the open default level
    after = env.render()
    assert has(cell(after, (1, 0)), theme.robots[0]) and has(cell(after, (1, 0)), theme.eye)
    assert not has(cell(after, (0, 0)), theme.robots[0])  # the start cell shows again


def test_the_robot_faces_the_way_it_moves():
    """Its eyes (and head) turn: the eye pixels of a robot that moved east lie right of one that moved west."""
    theme = THEMES["light"]
    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=64)
    env.reset(seed=0)
    env.step(2)  # east, to (1, 0)
    east = cell(env.render(), (1, 0), 64)
    env.step(4)  # west, back to (0, 0)
    west = cell(env.render(), (0, 0), 64)
    cx = [np.nonzero((img == theme.eye).all(axis=2))[1].mean() for img in (east, west)]
    assert cx[0] > cx[1] + 2


def test_poses_show_what_the_step_did():
    """A bump into the border draws stars (bumped pose), which an ordinary step does not."""
    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=64)
    env.reset(seed=0)
    env.step(2)
    moved = cell(env.render(), (1, 0), 64)
    env.step(1)  # NORTH into the border: bumped, stays at (1, 0)
    bumped = cell(env.render(), (1, 0), 64)
    star = (255, 200, 40)
    assert has(bumped, star) and not has(moved, star)


def test_a_finished_robot_celebrates_in_the_exit_cell():
    from dataclasses import replace

    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=64)
    env.reset(seed=0)
    for a in (2, 2, 3, 3):
        env.step(a)
    assert env.robot_cell == (2, 2)
    scene = env.unwrapped._scene()
    assert [v.pose for v in scene.robots] == ["finished"] and scene.done
    frame = env.render()
    assert has(cell(frame, (2, 2), 64), THEMES["light"].robots[0])
    idle = env.unwrapped.rgb_renderer.frame(replace(scene, robots=(replace(scene.robots[0], pose="idle"),)))
    assert (cell(frame, (2, 2), 64) != cell(idle, (2, 2), 64)).any()  # arms up, happy eyes


LEVEL = """
+-+-+-+-+-+-+
|S p P # E  |
+ + + + + + +
|           |
+-+-+-+-+-+-+
"""


def test_cells_show_their_kind_puddles_blocks_start_and_exit():
    theme = THEMES["light"]
    frame = RgbRenderer(Level.from_ascii(LEVEL), CS, "light").frame()
    small, large = cell(frame, (1, 0)), cell(frame, (2, 0))
    assert count(large, theme.large_puddle) > 2 * count(small, theme.small_puddle) > 0  # a large puddle is larger
    assert has(cell(frame, (3, 0)), theme.blocked)
    assert has(cell(frame, (4, 0)), theme.exit) and has(cell(frame, (4, 0)), theme.label_bg)  # the EXIT pill
    assert has(cell(frame, (0, 0)), theme.start) and has(cell(frame, (0, 0)), theme.label_bg)  # the START pill
    assert not has(cell(frame, (5, 1)), theme.small_puddle) and not has(cell(frame, (5, 1)), theme.blocked)


def test_walls_are_solid_glass_walls_are_framed_panes_and_open_edges_are_not_drawn():
    theme = THEMES["light"]
    level = Level.from_ascii(
        """
        +-+-+-+-+
        |S| *   |
        + + +-+ +
        |      E|
        +-+-+-+-+
        """
    )
    for cs in (32, 48, 64):
        frame = RgbRenderer(level, cs, "light").frame()
        wall = edge_strip(frame, (0, 0), (1, 0), cs)
        assert (wall == theme.wall).all(axis=-1).all()
        pane = edge_strip(frame, (1, 0), (2, 0), cs, half=6)
        assert has(pane, theme.glass) and has(pane, theme.glass_frame) and not has(pane, theme.wall)
        open_edge = edge_strip(frame, (0, 1), (1, 1), cs)
        assert not has(open_edge, theme.wall) and not has(open_edge, theme.glass)


@pytest.mark.parametrize("theme", sorted(THEMES))
def test_the_outer_border_is_a_wall_all_round(theme):
    frame = RgbRenderer(levels.get("default"), CS, theme).frame()
    wall = THEMES[theme].wall
    for strip in (frame[0], frame[-1], frame[:, 0], frame[:, -1]):
        assert (strip == wall).all()


LANE = """
+-+-+-+-+
|0   E 1|
+-+-+-+-+
"""


def test_race_robots_each_carry_their_colour_and_finishers_are_drawn_in_the_exit_with_their_rank():
    theme = THEMES["light"]
    env = race_v0.parallel_env(level=LANE, n_robots=2, render_mode="rgb_array", cell_size=64)
    env.reset(seed=0)
    frame = env.render()
    grid = frame[:64]
    assert has(cell(grid, (0, 0), 64), theme.robots[0]) and has(cell(grid, (3, 0), 64), theme.robots[1])
    env.step({"robot_0": 2, "robot_1": 0})
    env.step({"robot_0": 2, "robot_1": 0})  # robot 0 enters the exit (2, 0) and finishes first
    assert env.unwrapped.ranks[0] == 1
    exit_cell = cell(env.render()[:64], (2, 0), 64)
    assert has(exit_cell, theme.robots[0]) and has(exit_cell, (240, 190, 40))  # in the exit, with a gold badge
    env.step({"robot_1": 4})
    assert has(cell(env.render()[:64], (2, 0), 64), theme.robots[0])  # still there, later


def test_the_race_frame_has_a_legend_with_a_swatch_per_robot():
    theme = THEMES["light"]
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=48)
    env.reset(seed=0)
    frame = env.render()
    grid_h = env.unwrapped.level.height * 48
    assert frame.shape[0] > grid_h
    legend = frame[grid_h:]
    for i in range(4):
        assert has(legend, theme.robots[i])


CORRIDOR = """
+-+-+-+-+-+
|0 1      |
+-+-+-+-+-+
|        E|
+-+-+-+-+-+
"""


def test_a_robot_stopped_by_another_gets_a_burst_at_that_cell_in_the_same_step_only():
    theme = THEMES["light"]
    level = Level.from_ascii(CORRIDOR.replace("+-+-+-+-+-+\n|        E|", "+ + + + +-+\n|        E|"))
    env = race_v0.parallel_env(level=level, n_robots=2, render_mode="rgb_array", cell_size=64, collisions="block")
    env.reset(seed=0)
    env.step({"robot_0": 2, "robot_1": 0})  # robot 0 walks into robot 1, who stays: blocked
    frame = env.render()[: 2 * 64]
    assert has(cell(frame, (1, 0), 64), theme.mark)  # at the cell it could not enter
    env.step({"robot_0": 0, "robot_1": 0})
    assert not has(env.render()[: 2 * 64], theme.mark)


def test_robots_sharing_a_cell_under_pass_are_drawn_side_by_side():
    theme = THEMES["light"]
    level = Level.from_ascii(CORRIDOR.replace("+-+-+-+-+-+\n|        E|", "+ + + + +-+\n|        E|"))
    env = race_v0.parallel_env(level=level, n_robots=2, render_mode="rgb_array", cell_size=64, collisions="pass")
    env.reset(seed=0)
    env.step({"robot_0": 2, "robot_1": 0})  # both in (1, 0)
    shared = cell(env.render()[:128], (1, 0), 64)
    left, right = shared[:, :32], shared[:, 32:]
    assert count(left, theme.robots[0]) > 20 > count(right, theme.robots[0])  # robot 0 on the left
    assert count(right, theme.robots[1]) > 20 and count(right, theme.robots[1]) > count(left, theme.robots[1])


def test_the_same_state_gives_the_same_bytes_and_frames_are_fresh_arrays():
    a = BabyRobotEnv(level="puddles", render_mode="rgb_array")
    b = BabyRobotEnv(level="puddles", render_mode="rgb_array")
    a.reset(seed=3)
    b.reset(seed=3)
    for action in [2, 3, 3, 2, 2, 3]:
        a.step(action)
        b.step(action)
        fa, fb = a.render(), b.render()
        assert fa.tobytes() == fb.tobytes()
    fa[:] = 0  # a caller scribbling on a frame does not touch the next one
    assert a.render().tobytes() == fb.tobytes()


def test_themes_change_colours_and_a_custom_theme_is_data():
    level = levels.get("mixed-8x8")
    frames = {name: RgbRenderer(level, CS, name).frame([(0, 0)]).tobytes() for name in THEMES}
    assert len(set(frames.values())) == len(THEMES) == 4
    custom = variant(THEMES["light"], floor=(1, 2, 3))
    assert isinstance(custom, Theme) and has(RgbRenderer(level, CS, custom).frame(), (1, 2, 3))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"cell_size": 4}, "cell_size"),
        ({"cell_size": 257}, "cell_size"),
        ({"cell_size": 32.0}, "cell_size"),
        ({"cell_size": True}, "cell_size"),
        ({"cell_size": "32"}, "cell_size"),
        ({"theme": "neon"}, "theme: unknown theme 'neon'"),
    ],
)
def test_bad_render_options_name_the_argument(kwargs, message):
    with pytest.raises(ValueError, match=message):
        BabyRobotEnv(level="default", render_mode="rgb_array", **kwargs)
    with pytest.raises(ValueError, match=message):
        race_v0.parallel_env(render_mode="rgb_array", **kwargs)


def test_numpy_integers_are_cell_sizes_too():
    assert BabyRobotEnv(level="default", cell_size=np.int64(40)).cell_size == 40


def test_a_frame_over_the_pixel_limit_is_refused_before_drawing_naming_cell_size_and_what_fits():
    level = levels.get("maze-64x64")
    with pytest.raises(ValueError, match=r"cell_size: .*limit.*cell_size <= 64"):
        BabyRobotEnv(level=level, render_mode="rgb_array", cell_size=65)
    assert MAX_FRAME_PIXELS >= 64 * 64 * 64 * 64


def test_gymnasium_make_renders_rgb_array_for_both_registered_envs():
    for env_id, kwargs in [("babyrobot_marl/BabyRobot-v0", {}), ("babyrobot_marl/BabyRobotRace-v0", {"level": "race-4"})]:
        env = gymnasium.make(env_id, render_mode="rgb_array", cell_size=16, **kwargs)
        env.reset(seed=0)
        frame = env.render()
        level = env.unwrapped.level
        assert frame.shape[1:] == (level.width * 16, 3) and frame.shape[0] >= level.height * 16


def test_text_frames_give_84_robots_their_own_character_and_say_which_share_one_past_that():
    from babyrobot_marl.render.ansi import GLYPHS, frame, robot_glyph

    glyphs = [robot_glyph(i, 200) for i in range(len(GLYPHS))]
    assert len(set(glyphs)) == len(GLYPHS) >= 84 and all(len(g) == 1 for g in glyphs)
    level = levels.get("maze-16x16")
    cells = [(i % 16, i // 16) for i in range(100)]
    text = frame(level, cells, status="step 0")
    assert "robots 84..99 drawn as @" in text and text.split("\nstep 0")[0].count("@") == 100 - 84
    assert "drawn as @" not in frame(level, cells[:84])


def test_the_race_gym_env_names_the_learner_and_its_opponents_and_forwards_the_animation_settings():
    env = gymnasium.make(
        "babyrobot_marl/BabyRobotRace-v0",
        level="race-4",
        opponents=["shortest", "random"],
        render_mode="rgb_array",
        animation_frames=0,
        render_fps=10,
    )
    env.reset(seed=0)
    race = env.unwrapped.race
    assert [row.name for row in race._scene().legend] == ["learner", "shortest", "random"]
    assert race.animation_frames == 0 and env.unwrapped.metadata["render_fps"] == 10
    assert env.render().shape[0] > race.level.height * race.cell_size  # the legend


def test_a_race_legend_stops_growing_past_eight_robots_and_the_frame_limit_counts_it():
    def height(n: int) -> int:
        env = race_v0.parallel_env(level="maze-16x16", n_robots=n, start="random", render_mode="rgb_array")
        env.reset(seed=0)
        return env.render().shape[0]

    assert height(2) < height(8) and height(9) < height(8) and height(30) == height(100)  # compact past eight
    with pytest.raises(ValueError, match=r"^cell_size: .*legend of 4 robots.* 4096x4262 frame"):
        race_v0.parallel_env(level="maze-16x16", n_robots=4, start="random", cell_size=256, render_mode="rgb_array")
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"^panel: 3,000 lines"):
        env.unwrapped.set_overlay(panel=[f"line {i}" for i in range(3000)])


def test_a_collision_burst_is_beside_both_faces_and_podium_robots_show_only_their_rank():
    """The burst sits on the shared edge below the faces (both visors untouched); a finished
    robot carries no id on its chest (its rank badge only) and is at least 24 px at 64 px cells."""
    from babyrobot_marl.render.robot import icon_scale
    from babyrobot_marl.render.scene import BURST, burst_centre

    cx, cy = burst_centre((1, 0), (2, 0), 64)
    assert cx == 2 * 64 and cy - 0.5 * 64 >= BURST[1] * 64 - 1  # on the edge, below the eyes' row
    face_bottom = 0.5 * 64 + (-0.11 * 0.86) * 64  # a full-size robot's visor ends here
    assert cy - BURST[0] * 64 * 1.12 > face_bottom
    s, _ = icon_scale(4, 0.3)
    assert s * 64 >= 24
    env = race_v0.parallel_env(level=LANE, n_robots=2, render_mode="rgb_array", cell_size=64)
    env.reset(seed=0)
    env.step({"robot_0": 2, "robot_1": 0})
    env.step({"robot_0": 2, "robot_1": 0})
    from babyrobot_marl.render.scene import robot_sprites

    u = env.unwrapped
    sprites = robot_sprites(u._scene(), 64, THEMES["light"], labelled=u.drawing.renderer.labelled)
    texts = [t.text for s, _, _ in sprites for t in s.texts]
    assert "1" in texts and "0" not in texts  # the rank badge's 1, not robot 0's id


def test_the_kept_frame_redraws_changed_legend_rows_and_a_new_overlay():
    """Frames from one renderer, its panel and placed robots kept, equal frames from a fresh one."""
    env = race_v0.parallel_env(level="mixed-8x8", n_robots=4, start="random", render_mode="rgb_array", cell_size=48)
    env.reset(seed=1)
    fresh = race_v0.parallel_env(level="mixed-8x8", n_robots=4, start="random", render_mode="rgb_array", cell_size=48)
    fresh.reset(seed=1)
    rng = np.random.default_rng(0)
    for k in range(12):
        if not env.agents:
            break
        acts = {a: int(rng.integers(5)) for a in env.agents}
        env.step(acts)
        fresh.step(acts)
        if k == 6:
            env.unwrapped.set_overlay(values=np.arange(64.0).reshape(8, 8))
            fresh.unwrapped.set_overlay(values=np.arange(64.0).reshape(8, 8))
        kept = env.render()
        from babyrobot_marl.render.rgb import RgbRenderer

        u = fresh.unwrapped
        new = RgbRenderer(u.level, 48, u.drawing.renderer.theme).frame(u._scene(), u.overlay)
        assert (kept == new).all(), k


@pytest.mark.parametrize("n", [4, 12])
def test_kept_blocks_and_legend_pieces_equal_a_fresh_renderers_frames(n):
    """The caches (cells with robots by exact content, legend pieces, the kept frame) across
    steps, bursts, shared cells, in-between frames, overlay and name changes, and a compact
    legend: every frame equals a fresh renderer's."""
    from babyrobot_marl.render.rgb import RgbRenderer

    env = race_v0.parallel_env(level="mixed-8x8", n_robots=n, start="random", render_mode="rgb_array", cell_size=32)
    env.reset(seed=2)
    u = env.unwrapped
    rng = np.random.default_rng(3)
    seen = {"burst": 0, "shared": 0}
    for k in range(70):
        if not env.agents:
            env.reset()
        env.step({a: int(rng.integers(5)) for a in env.agents})
        if k == 20:
            u.set_overlay(values=np.arange(64.0).reshape(8, 8), arrows=np.full((8, 8), 2), panel="step 20")
        if k == 40:
            u.set_overlay(names=[f"p{i}" for i in range(n)], panel=None)
        if k == 55:
            u.set_overlay(values=None, arrows=None)
        scene = u._scene()
        seen["burst"] += bool(scene.marks)
        seen["shared"] += len({v.cell for v in scene.robots}) < len(scene.robots)
        kept = [u.rgb_renderer.frame(scene, u.overlay, 0.5), env.render()]  # every step: the caches in use
        if k % 3 == 0 or k in (21, 41, 56):
            fresh = RgbRenderer(u.level, 32, u.theme)
            assert (kept[0] == fresh.frame(scene, u.overlay, 0.5)).all(), k
            assert (kept[1] == fresh.frame(scene, u.overlay)).all(), k
    assert n == 4 or (seen["burst"] and seen["shared"])  # the blocks of several sprites were exercised


def test_a_cell_block_is_keyed_by_all_its_robots_and_the_burst_by_its_cells():
    """The same view of robot 0 alone, then sharing its cell, then alone again; a burst on and off."""
    from babyrobot_marl.render.rgb import RgbRenderer
    from babyrobot_marl.render.scene import RobotView, Scene

    level = levels.get("mixed-8x8")
    zero, one = RobotView(0, (2, 2), 2, "moved"), RobotView(1, (2, 2), 4, "moved")
    podium = (RobotView(2, (5, 5), 0, "finished", rank=1), RobotView(3, (5, 5), 0, "finished", rank=2))
    scenes = [Scene((zero,)), Scene((zero, one)), Scene((zero,)), Scene((zero, RobotView(1, (3, 2), 4, "bumped")),
              (((3, 2), (2, 2)),)), Scene((zero, RobotView(1, (3, 2), 4, "bumped"))), Scene((zero, *podium)),
              Scene((zero, podium[0]))]  # fmt: skip
    kept = RgbRenderer(level, 48)
    for k, scene in enumerate(scenes * 2):
        assert (kept.frame(scene) == RgbRenderer(level, 48).frame(scene)).all(), k


@pytest.mark.parametrize("theme", ["light", "dark"])
@pytest.mark.parametrize("cs", [32, 48, 64])
def test_at_reset_the_robots_head_shows_below_the_start_pill(cs, theme):
    """Issue 26: the START pill hid the robot's head at reset. Its eyes and visor show in the
    start cell, the whole head below the pill's band (its top a few pixels clear of it), and
    the pill is still there."""
    from babyrobot_marl.render.picture import label_band

    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=cs, theme=theme)
    env.reset(seed=0)
    th = THEMES[theme]
    x, y = env.unwrapped.robot_cell
    start = env.render()[y * cs : (y + 1) * cs, x * cs : (x + 1) * cs].astype(int)
    band = int(np.ceil(label_band(cs)[1]))
    eye = (np.abs(start - th.eye).sum(axis=2) <= 6)
    visor = (np.abs(start - th.visor).sum(axis=2) <= 6)
    pill = (x, y) in env.unwrapped.rgb_renderer.labelled  # at 32 px the word does not fit: no pill
    assert pill == (cs >= 48)
    assert eye.sum() >= 2 and visor[band if pill else 0 :].sum() >= cs // 8, (eye.sum(), visor.sum())
    if pill:
        assert not eye[:band].any()  # no eye under the pill (the pill's ink may match the visor's)
        body = np.nonzero((np.abs(start - th.robots[0]).sum(axis=2) <= 6).any(axis=1))[0]
        assert body.min() >= band + max(3, cs // 16)  # the head's top clear of the pill (it ran on under it)
        assert (np.abs(start[:band] - th.label_bg).sum(axis=2) <= 6).sum() >= cs // 2  # the pill itself


@pytest.mark.parametrize("cs", [48, 56, 64])
def test_podium_robots_are_24_px_and_wear_a_readable_rank_clear_of_the_exit_label(cs):
    """Issue 26: podium robots were about 23 px in race.gif (56 px cells), their rank badges
    too small for a digit at 48-56 px and the gold one under the EXIT pill."""
    from babyrobot_marl.render.picture import label_band
    from babyrobot_marl.render.scene import RobotView, Scene, placement_sprites, placements

    level = levels.get("race-4")
    exit_cell = sorted(level.exits)[0]
    scene = Scene(tuple(RobotView(i, exit_cell, 0, "finished", rank=i + 1) for i in range(4)))
    r = RgbRenderer(level, cs)
    band = exit_cell[1] * cs + label_band(cs)[1]
    for pl in placements(scene, r.labelled, r.label_top):
        assert pl.scale * cs >= (24 if cs >= 56 else 21)
        _, (medal, mx, my) = placement_sprites(pl, cs, r.theme, "finished", pl.cx, pl.cy)
        assert [t.text for t in medal.texts] == [str(pl.view.rank)]  # its digit fits
        assert my + medal.points[:, 1].min() > band  # its top below the pill
