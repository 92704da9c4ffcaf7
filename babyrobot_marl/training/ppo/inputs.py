"""What a robot's network sees: its cell and, in a race, the racing robots near it, as one integer key per robot-step."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...core.level import Level


def near_offsets(radius: int) -> tuple[tuple[int, int], ...]:
    """The cells a race robot watches for other robots: every ``(dx, dy)`` at 1 to ``radius`` steps
    (Manhattan distance), row by row. Radius 2 (12 cells) holds every robot that can contest the
    robot's next cell or stand in its way; robots further off cannot touch its next step."""
    return tuple((dx, dy) for dy in range(-radius, radius + 1) for dx in range(-radius, radius + 1)
                 if 0 < abs(dx) + abs(dy) <= radius)


@dataclass(frozen=True)
class Inputs:
    """What a robot's network sees, as one integer key per robot-step.

    The input is the one-hot of the robot's own cell (``n_cells`` wide) and, in a race, one bit per
    cell of ``near`` (offsets from ``near_offsets``): set when a racing robot stands there. Its key
    is ``cell << m | bits`` (``m = len(near)``). Far robots are left out on purpose: inputs repeat
    (about 350 distinct ones in a rollout of 65,536 robot-steps on race-4 at radius 1, 2,100 at
    radius 2), and the net runs
    once per distinct input, in rollouts and in updates. Such a policy races with any number of
    robots. One robot: ``near = ()``, the key is the cell.
    """

    width: int
    height: int
    near: tuple[tuple[int, int], ...] = ()

    @property
    def n_cells(self) -> int:
        return self.width * self.height

    @property
    def n_in(self) -> int:
        """Width of the one-hot input: the cells, then the near bits."""
        return self.n_cells + len(self.near)

    @property
    def n_keys(self) -> int:
        return self.n_cells << len(self.near)

    @functools.cached_property
    def neighbours(self) -> np.ndarray:
        """``(n_cells + 1, m)``: the cell at each near offset of each cell, ``n_cells`` off the grid
        (and for the padding cell ``n_cells``)."""
        xs, ys = np.arange(self.n_cells) % self.width, np.arange(self.n_cells) // self.width
        out = np.full((self.n_cells + 1, len(self.near)), self.n_cells, dtype=np.int64)
        for b, (dx, dy) in enumerate(self.near):
            x, y = xs + dx, ys + dy
            inside = (x >= 0) & (x < self.width) & (y >= 0) & (y < self.height)
            out[:-1, b] = np.where(inside, y * self.width + x, self.n_cells)
        return out

    def keys(self, cells: np.ndarray, racing: np.ndarray) -> np.ndarray:
        """Every robot's key from a batch's ``(n_envs, n_robots)`` cells and racing flags."""
        m = len(self.near)
        if not m:
            return cells.copy()
        e, stride = cells.shape[0], self.n_cells + 1  # per env: its cells, then one never occupied
        base = np.arange(e)[:, None] * stride
        occupied = np.zeros(e * stride, dtype=np.uint8)
        occupied[base + np.where(racing, cells, self.n_cells)] = 1
        occupied[self.n_cells :: stride] = 0
        bits = occupied.take(self.neighbours[cells] + base[:, :, None])  # (E, R, m)
        return (cells << m) | (bits.astype(np.int64) @ (1 << np.arange(m)))

    def key_of_observation(self, obs: Any) -> int:
        """One env's ``MultiDiscrete`` observation (``[x, y]``, then ``[x, y, finished]`` per other
        robot in a race) as its key: what ``keys`` gives for that robot in a batch."""
        o = np.asarray(obs, dtype=np.int64).reshape(-1)
        cell = int(o[1]) * self.width + int(o[0])
        if not self.near:
            return cell
        rest = o[2:].reshape(-1, 3)
        occupied = {int(y) * self.width + int(x) for x, y, finished in rest if not finished}
        bits = sum(1 << b for b, c in enumerate(self.neighbours[cell]) if int(c) in occupied)
        return (cell << len(self.near)) | bits

    def rows(self, keys: np.ndarray) -> np.ndarray:
        """The net's rows of input indices for ``keys``: ``(U, 1 + m)``, the cell, then ``n_cells + b``
        for each set bit ``b`` (the padding index ``n_in`` for the others)."""
        keys = np.asarray(keys, dtype=np.int64).reshape(-1)
        m = len(self.near)
        if not m:
            return keys[:, None]
        bits = (keys[:, None] >> np.arange(m)) & 1
        return np.concatenate([(keys >> m)[:, None], np.where(bits == 1, self.n_cells + np.arange(m), self.n_in)], axis=1)

    def one_hot(self, keys: np.ndarray) -> np.ndarray:
        """The dense float32 input that keys stand for, ``(..., n_in)``."""
        rows = self.rows(keys)
        dense = np.zeros((rows.shape[0], self.n_in + 1), dtype=np.float32)
        dense[np.arange(rows.shape[0])[:, None], rows] = 1.0
        return dense[:, : self.n_in].reshape(*np.shape(keys), self.n_in)


def make_inputs(level: Level, n_robots: int, near_radius: int) -> Inputs:
    """A race's ``Inputs`` (robots within ``near_radius`` steps), or one robot's (its cell only)."""
    return Inputs(level.width, level.height, near_offsets(near_radius) if n_robots > 1 else ())
