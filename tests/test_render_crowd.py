"""Crowded rgb_array frames: each cell's robots from a block by their look, and only the cells
whose drawings reach into another's (or under a burst) drawn the general way, with the same pixels."""

from __future__ import annotations

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.render.cellgroups import overlap
from babyrobot_marl.render.rgb import RgbRenderer


def crowd_scenes(level: str, n: int, cs: int, steps: int, seed: int):
    """Scenes of a random race: robots sharing cells, bumping, finishing, bursts."""
    env = race_v0.parallel_env(level=level, n_robots=n, start="random", render_mode="rgb_array", cell_size=cs)
    env.reset(seed=seed)
    u = env.unwrapped
    rng = np.random.default_rng(seed)
    for _ in range(steps):
        if not env.agents:
            env.reset()
        env.step({a: int(rng.integers(5)) for a in env.agents})
        yield u, u._scene()


def clashing(units: list[tuple], marks: list[tuple]) -> list[int]:
    """The cells' units whose cells overlap another unit's or a burst's (pair by pair)."""
    rects = [u[0] for u in units] + [m[5] for m in marks]
    return [k for k in range(len(units)) if any(overlap(rects[k], r) for j, r in enumerate(rects) if j != k)]


@pytest.mark.parametrize(("level", "n", "cs", "seed", "clashes"),
                         [("maze-16x16", 90, 8, 90, True), ("maze-16x16", 60, 12, 0, True), ("mixed-8x8", 12, 32, 12, False)])
def test_the_fast_path_gives_the_general_paths_pixels_on_random_crowds(level, n, cs, seed, clashes):
    """``clashes``: some frames have cells whose drawings overlap (at 32 pixels a bumped robot's
    stars stay in its cell: none do)."""
    kept, mixed = None, 0
    for u, scene in crowd_scenes(level, n, cs, 25, seed=seed):
        kept = kept or RgbRenderer(u.level, cs, u.theme)
        static = kept.static(None)
        fast = kept.frame(scene)[: static.shape[0]]
        general = RgbRenderer(u.level, cs, u.theme)._general(static, scene)
        assert (fast == general).all()
        mixed += not kept._apart(kept._cell_units(static, scene)[0], kept._marks(scene))
    assert (mixed > 0) == clashes  # frames whose cells clash were drawn


def test_only_a_frames_clashing_cells_are_drawn_the_general_way():
    seen = 0
    for u, scene in crowd_scenes("maze-16x16", 90, 8, 25, seed=5):
        r = RgbRenderer(u.level, 8, u.theme)
        static = r.static(None)
        units, marks = r._cell_units(static, scene)[0], r._marks(scene)
        if r._apart(units, marks):
            continue
        r.frame(scene)  # every block cached: now each block drawn the general way is one call
        calls: list[tuple] = []
        block = r._block

        def counted(st, rect, items, calls=calls, block=block):
            calls.append((rect, items))
            return block(st, rect, items)

        r._block = counted
        r.frame(scene)
        clash = clashing(units, marks)
        assert clash and len(calls) < len(units) // 2
        for k in clash:  # each clashing cell is inside a block drawn the general way
            assert any(units[k][0] == tuple(np.clip(units[k][0], rect[:2] * 2, rect[2:] * 2)) for rect, _ in calls)
        for rect, items in calls:  # and each such block holds a clash: two drawings or a burst
            assert len(items) > 1 or items[0] in marks
            inside = [k for k in clash if overlap(units[k][0], rect)]
            assert inside or any(overlap(m[5], rect) for m in marks)
        lone_items = {id(e[1]) for k, u in enumerate(units) if k not in clash and not any(
            overlap(u[0], rect) for rect, _ in calls) for e in u[2] or ()}  # fmt: skip (a tile's: none kept)
        assert not lone_items & {id(it) for _, items in calls for it in items}
        seen += 1
    assert seen > 0


def test_a_robot_on_a_floor_cell_it_never_stood_on_is_drawn_by_a_copy():
    """A lone robot's block is the same in every cell of the same pixels (a floor cell with the
    same walls round it): a robot that looks the same blends once per kind of cell, not once per
    cell, with the general way's pixels (also beside START / EXIT labels, with an overlay's
    corner, and for a bumped robot whose stars reach the next cell)."""
    import babyrobot_marl.render.crowd as crowd
    import babyrobot_marl.render.rgb as rgbmod
    from babyrobot_marl import levels
    from babyrobot_marl.render import paint
    from babyrobot_marl.render.overlay import Overlay
    from babyrobot_marl.render.scene import RobotView, Scene

    level = levels.get("maze-16x16")
    real = paint.blend
    for cs, pose, corner in ((31, "idle", False), (12, "moving", False), (48, "bumped", False), (40, "idle", True)):
        r, ref = RgbRenderer(level, cs), RgbRenderer(level, cs)
        overlay = Overlay(values=np.zeros((level.height, level.width))) if corner else None
        blends: list[int] = []

        def counting(*args, blends=blends):
            blends.append(1)
            return real(*args)

        crowd.blend = rgbmod.blend = counting
        try:
            frames = [(cell, r.frame(Scene((RobotView(3, cell, 2, pose),), corner=corner), overlay))
                      for cell in level.free_cells()]  # fmt: skip
        finally:
            crowd.blend = rgbmod.blend = real
        static = r.static(overlay)
        for cell, got in frames:
            want = ref._general(static, Scene((RobotView(3, cell, 2, pose),), corner=corner))
            assert (got[: static.shape[0]] == want).all(), (cs, pose, cell)
        if not corner:  # (an overlay's corner at these sizes is off the quarter pixel: keyed by cell)
            share = 2 / 3 if pose == "bumped" else 1 / 3  # a bump's stars: a block of the cells round it
            assert len(blends) <= len(frames) * share, (cs, pose, len(blends), len(frames))


def test_a_crowd_s_views_stay_the_same_objects_from_frame_to_frame():
    """The scene's views and legend rows are shared by content, bounded by two generations: a
    value used in the last frame is the same object in this one however the generations turn
    (renderers compare them by identity), and at most two generations are kept."""
    from babyrobot_marl.envs import scenes
    from babyrobot_marl.render.scene import RobotView

    n = scenes.GENERATION // 4  # robots that stand still, and as many that move, each frame
    still = [scenes._value(RobotView, i, (i % 50, i // 50)) for i in range(n)]
    for step in range(8):
        again = [scenes._value(RobotView, i, (i % 50, i // 50)) for i in range(n)]
        assert all(a is b for a, b in zip(still, again)), step
        for i in range(n):  # the moving ones: new views every frame
            scenes._value(RobotView, n + i, (step, i))
    assert sum(map(len, scenes._VALUES)) <= 2 * scenes.GENERATION
