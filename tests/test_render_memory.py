"""The renderers' caches: bounded by the bytes they hold, and large enough for a crowd's frame."""

from __future__ import annotations

import gc
import tracemalloc

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv, race_v0
from babyrobot_marl.render import glyphs, paint, rgb, sprites
from babyrobot_marl.render.memo import ENTRY_BYTES, MB, ByteCache

SOAK_PANELS = 40  # each 2,000 characters at 128-pixel cells: about 1.5 MB of panel and text each, unbounded


def test_a_byte_cache_keeps_the_most_recently_used_values_within_its_bytes():
    cache: ByteCache[np.ndarray] = ByteCache(10_000 + 3 * ENTRY_BYTES)
    for k in range(4):
        cache.put(k, np.zeros(5_000, dtype=np.uint8))
    assert list(cache._data) == [2, 3] and cache.bytes == 2 * (5_000 + ENTRY_BYTES)
    assert cache.get(2) is not None  # used: now the newest
    cache.put(4, np.zeros(5_000, dtype=np.uint8))
    assert list(cache._data) == [2, 4] and cache.get(3) is None
    big = np.zeros(20_000, dtype=np.uint8)
    assert cache.put("big", big) is big and "big" not in cache  # larger than the bound: returned, not kept
    assert cache.bytes <= cache.max_bytes


def test_the_stated_bounds_are_tens_of_megabytes():
    shared = paint.PATCH_BYTES + sprites.SPRITE_BYTES + glyphs.TEXT_BYTES
    assert (shared, rgb.RENDERER_BYTES) == (32 * MB, 66 * MB)  # as the rendering guide states them


@pytest.mark.slow
def test_a_soak_of_long_different_panels_at_large_cells_retains_only_the_bounded_caches():
    """Panels of 2,000 characters at 128-pixel cells, each different: the panel strips and the
    lines of text drawn are kept by bytes (the old caches, by count, kept hundreds of MB)."""
    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=128)
    env.reset(seed=0)
    env.render()
    rng = np.random.default_rng(0)
    words = ["abcdefghij", "klmnop", "qrstu", "vwxyz", "0123456789"]
    gc.collect()
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        for k in range(SOAK_PANELS):
            env.unwrapped.set_overlay(panel=[(f"{k} " + " ".join(rng.choice(words, 400)))[:2000]])
            frame = env.render()
        del frame
        gc.collect()
        retained = tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()
    renderer = env.unwrapped.rgb_renderer
    assert renderer._panels.bytes <= rgb.PANEL_BYTES and glyphs._run.cache.bytes <= glyphs.TEXT_BYTES
    frames = 3 * renderer._base_img.nbytes  # the frame kept to draw on, and a panel's strip or two
    assert retained <= glyphs.TEXT_BYTES + rgb.PANEL_BYTES + frames, f"{retained / MB:.0f} MB retained"


def test_a_crowd_s_frame_is_drawn_again_from_the_caches_without_rasterising():
    """1,200 robots at 12-pixel cells: robots that look the same (below the size their number is
    drawn at, a robot is its colour) share a sprite, so one frame's sprites fit the caches: the
    same state drawn again rasterises nothing (a cache of 1,024 sprites rasterised them all again)."""
    env = race_v0.parallel_env(level="maze-64x64", n_robots=1200, start="random", render_mode="rgb_array")
    env.reset(seed=0)
    env.step({a: k % 5 for k, a in enumerate(env.agents)})
    first = env.render()
    renderer = env.unwrapped.rgb_renderer
    renderer._lone[0].clear()  # the cells drawn with their robots: drawn again from the sprites
    renderer._lone[1].clear()
    renderer._blocks.clear()
    renderer._placed.clear()
    painted = []
    real = paint.paint

    def counting(*args, **kwargs):
        painted.append(1)
        return real(*args, **kwargs)

    paint.paint = counting
    try:
        again = env.render()
    finally:
        paint.paint = real
    assert painted == [] and (again == first).all()
    assert len(sprites._robot_sprite.cache) < 1200


def reference_groups(rects):
    """The groups of overlapping cell rectangles, found pair by pair (the way before cells were looked up)."""
    groups = []
    for k, rect in enumerate(rects):
        members = [k]
        hit = [g for g in groups if rgb._overlap(rect, g[0])]
        while hit:
            for g in hit:
                groups.remove(g)
                r = g[0]
                rect = (min(rect[0], r[0]), min(rect[1], r[1]), max(rect[2], r[2]), max(rect[3], r[3]))
                members += g[1]
            hit = [g for g in groups if rgb._overlap(rect, g[0])]
        groups.append((rect, sorted(members)))
    return sorted(groups)


@pytest.mark.parametrize("seed", range(20))
def test_sprites_are_grouped_by_shared_cells_as_pair_by_pair(seed):
    rng = np.random.default_rng(seed)
    rects = []
    for _ in range(int(rng.integers(2, 60))):
        x, y = (int(v) for v in rng.integers(0, 12, 2))
        w, h = (int(v) for v in rng.integers(1, 3, 2))
        rects.append((x, y, x + w, y + h))
    drawn = [(None,) * 5 + (r, k) for k, r in enumerate(rects)]
    got = sorted((rect, sorted(item[6] for item in items)) for rect, items in rgb._groups(drawn))
    assert got == reference_groups(rects)
    assert rgb._any_overlap(rects) == (len(got) < len(rects))


@pytest.mark.parametrize("seed", range(12))
def test_a_crowd_s_rectangles_are_grouped_as_pair_by_pair(seed):
    """Hundreds of cells, most of one cell and a few wider (a bump's stars, a burst): the cells no
    other rectangle reaches are set aside first, and a merged group still takes in a lone cell its
    bounding rectangle reaches."""
    rng = np.random.default_rng(100 + seed)
    rects = set()
    while len(rects) < int(rng.integers(60, 300)):
        x, y = (int(v) for v in rng.integers(0, 24, 2))
        w, h = (int(v) for v in rng.integers(1, 4, 2)) if rng.random() < 0.15 else (1, 1)
        rects.add((x, y, x + w, y + h))
    rects = sorted(rects, key=lambda r: rng.random())
    drawn = [(None,) * 5 + (r, k) for k, r in enumerate(rects)]
    got = sorted((rect, sorted(item[6] for item in items)) for rect, items in rgb._groups(drawn))
    assert got == reference_groups(rects)
