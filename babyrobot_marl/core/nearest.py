"""The "nearest" observations: each robot's ``k`` nearest other racing robots (``observe.py`` holds the
modes and their ``Observer``).

Rows hold ``[dx + W - 1, dy + H - 1]`` of the nearest first (Manhattan distance, ties to the lower
robot number); missing ones (fewer than ``k`` others racing) are ``[2W - 1, 2H - 1]``. Nearest robots
are found by brute force for a few robots, else by searching rings of cells around each robot.
"""

from __future__ import annotations

import math

import numpy as np


def nearest_nvec(width: int, height: int, k: int) -> np.ndarray:
    return np.array([width, height] + [2 * width, 2 * height] * k, dtype=np.int64)


_BRUTE_UP_TO = 128  # robots per race up to which all pairs are compared
_CHUNK = 1 << 20  # pairs compared at once (memory bound)


def nearest_observations(xy: np.ndarray, racing: np.ndarray, k: int, width: int, height: int, extra: int = 0) -> np.ndarray:
    """``(..., n, 2 + 2k)`` int64 rows from ``[x, y]`` of shape ``(..., n, 2)`` and racing flags ``(..., n)``
    (``extra``: more columns at the end, as ``local_observations``)."""
    xy, racing = np.asarray(xy, dtype=np.int64), np.asarray(racing, dtype=bool)
    *lead, n, _ = xy.shape
    n_races = math.prod(lead)
    xy2, racing2 = xy.reshape(n_races, n, 2), racing.reshape(n_races, n)
    size = 2 + 2 * k + extra
    out = np.empty((n_races, n, size), dtype=np.int64)
    out[:, :, :2] = xy2
    rel = out[:, :, 2 : 2 + 2 * k].reshape(n_races, n, k, 2)
    if k == 0:
        return out.reshape(*lead, n, size)
    if n <= _BRUTE_UP_TO:
        step = max(1, _CHUNK // (n * n))
        for s in range(0, n_races, step):
            _nearest_brute(xy2[s : s + step], racing2[s : s + step], rel[s : s + step])
    else:
        for s in range(n_races):
            _nearest_rings(xy2[s], racing2[s], rel[s], width, height)
    # [dx, dy] -> [dx + W - 1, dy + H - 1]; a missing robot: [2W - 1, 2H - 1]
    missing = rel[..., 0] == _MISSING
    rel += (width - 1, height - 1)
    rel[missing] = (2 * width - 1, 2 * height - 1)
    return out.reshape(*lead, n, size)


_MISSING = np.iinfo(np.int64).min // 4


def _nearest_brute(xy: np.ndarray, racing: np.ndarray, rel: np.ndarray) -> None:
    """All pairs: ``rel`` (R, n, k, 2) gets the k nearest's ``[dx, dy]`` (``_MISSING`` if none)."""
    r, n, k = rel.shape[0], rel.shape[1], rel.shape[2]
    d = xy[:, None, :, :] - xy[:, :, None, :]  # (R, i, j, 2): j relative to i
    dist = np.abs(d).sum(axis=3)
    big = 4 * (np.abs(xy).max() + 1) if xy.size else 1
    dist = np.where(racing[:, None, :] & ~np.eye(n, dtype=bool), dist, big)  # others on the board only
    key = dist * n + np.arange(n)  # ties to the lower robot number
    kk = min(k, n)
    near = np.argpartition(key, kk - 1, axis=2)[:, :, :kk] if kk < n else np.broadcast_to(np.arange(n), (r, n, n))
    near = np.take_along_axis(near, np.argsort(np.take_along_axis(key, near, axis=2), axis=2), axis=2)
    found = np.take_along_axis(dist, near, axis=2) < big
    rel[:, :, :kk] = np.where(found[..., None], np.take_along_axis(d, near[..., None], axis=2), _MISSING)
    rel[:, :, kk:] = _MISSING


def _nearest_rings(xy: np.ndarray, racing: np.ndarray, rel: np.ndarray, width: int, height: int) -> None:
    """One race of many robots: look at the cells at distance 0, 1, 2, ... around each robot until
    ``k`` others are found; robots still looking once a ring would cost more than comparing with
    everyone are done by brute force."""
    n, k = rel.shape[0], rel.shape[1]
    rel[...] = _MISSING
    others = np.flatnonzero(racing)
    if others.size == 0:
        return
    # the racing robots by cell (several may share one under "pass"), robot numbers ascending
    cell = xy[others, 1] * width + xy[others, 0]
    order = np.lexsort((others, cell))
    robots = others[order]
    # robots[first_on[c] : first_on[c] + count[c]] are the racing robots on cell c; the last slot: outside
    count = np.bincount(cell, minlength=width * height + 1)
    first_on = np.cumsum(count) - count
    found = np.zeros(n, dtype=np.int64)
    todo = np.arange(n)
    d = 0
    while todo.size and 2 * d * d <= n:
        if d == 0:
            dx = dy = np.zeros(1, dtype=np.int64)
        else:
            t = np.arange(d)
            dx = np.concatenate([d - t, -t, t - d, t])
            dy = np.concatenate([t, d - t, -t, t - d])
        x = xy[todo, 0][:, None] + dx
        y = xy[todo, 1][:, None] + dy
        inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
        c = np.where(inside, y * width + x, width * height)
        lo = first_on.take(c)
        hi = lo + count.take(c)
        per_row = (hi - lo).sum(axis=1)
        rows = np.flatnonzero(per_row)
        if rows.size:
            # every robot of the ring, row by row, then sorted by robot number within a row
            lo_r, hi_r = lo[rows].ravel(), hi[rows].ravel()
            length = hi_r - lo_r
            row_of = np.repeat(np.repeat(rows, dx.size), length)
            start = np.repeat(lo_r - np.cumsum(length) + length, length)
            hits = robots[start + np.arange(length.sum())]
            keep = hits != todo[row_of]  # not the observer itself
            row_of, hits = row_of[keep], hits[keep]
            o = np.lexsort((hits, row_of))
            row_of, hits = row_of[o], hits[o]
            first = np.searchsorted(row_of, row_of)  # rank of each hit within its row
            slot = found[todo[row_of]] + np.arange(row_of.size) - first
            use = slot < k
            who = todo[row_of[use]]
            rel[who, slot[use]] = xy[hits[use]] - xy[who]
            np.add.at(found, who, 1)
        todo = todo[found[todo] < k]
        d += 1
    if todo.size:  # far from the rest: compare with everyone
        step = max(1, _CHUNK // max(n, 1))
        for s in range(0, todo.size, step):
            _nearest_subset(xy, racing, rel, todo[s : s + step])


def _nearest_subset(xy: np.ndarray, racing: np.ndarray, rel: np.ndarray, who: np.ndarray) -> None:
    n, k = rel.shape[0], rel.shape[1]
    d = xy[None, :, :] - xy[who, None, :]  # (m, n, 2)
    dist = np.abs(d).sum(axis=2)
    big = 4 * (np.abs(xy).max() + 1)
    ok = racing[None, :] & (np.arange(n)[None, :] != who[:, None])
    key = np.where(ok, dist, big) * n + np.arange(n)
    kk = min(k, n)
    near = np.argpartition(key, kk - 1, axis=1)[:, :kk] if kk < n else np.broadcast_to(np.arange(n), (who.size, n))
    near = np.take_along_axis(near, np.argsort(np.take_along_axis(key, near, axis=1), axis=1), axis=1)
    found = np.take_along_axis(ok, near, axis=1)
    vals = np.where(found[..., None], np.take_along_axis(d, near[..., None], axis=1), _MISSING)
    rel[who, :kk] = vals
    rel[who, kk:] = _MISSING
