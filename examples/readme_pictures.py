"""Make the README's pictures from the package itself (nothing is drawn by hand).

    python examples/readme_pictures.py            # writes docs/images/*.{gif,png}

- ``race.gif``: a four-robot race on ``race-4`` (three shortest-path robots and a clumsy one),
  the robots gliding between cells, with the legend;
- ``planning.png``: value iteration on ``mixed-8x8``: values in boxes, the best actions as
  arrows, the colour bar;
- ``action_values.png``: the action values of ``default`` in their triangles;
- ``themes.png``: the four built-in themes side by side;
- ``poses.png``: Baby Robot's poses (rows) and headings (columns).

Needs the ``video`` extra (imageio) for the GIF; the rest is numpy and imageio's PNG writer.
``--out DIR`` writes the pictures elsewhere. The output is the same on every run and machine
(``tests/test_readme_pictures.py`` checks it against the committed files): the pictures hold no
randomness but the seeded policies', and the GIF's colours are chosen here, not by the encoder.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from babyrobot_marl import BabyRobotEnv, planning, race_v0
from babyrobot_marl.policies import make as make_policy
from babyrobot_marl.render.paint import Text, raster
from babyrobot_marl.render.palette import ROBOT_COLOURS, THEMES
from babyrobot_marl.render.robot import POSES, robot
from babyrobot_marl.render.video import episode_frames, save_gif

OUT = Path(__file__).resolve().parents[1] / "docs" / "images"


def race_gif(out: Path) -> Path:
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=56)
    u = env.unwrapped
    u.set_overlay(names=["shortest", "shortest", "shortest", "clumsy"])
    shortest, rnd = make_policy("shortest", u.table), make_policy("random", u.table, seed=0)
    policies = {a: shortest for a in env.possible_agents}
    policies["robot_3"] = lambda obs: rnd(obs) if rnd.rng.random() < 0.3 else shortest(obs)
    frames = episode_frames(env, policies, seed=3, animation_frames=4)
    frames += [frames[-1]] * 12  # hold the final ranks
    return save_gif(gif_colours(frames), out / "race.gif", fps=12)


def gif_colours(frames: list[np.ndarray], n: int = 256) -> list[np.ndarray]:
    """``frames`` in at most ``n`` colours: the ``n`` most common ones, every other colour replaced
    by its nearest. A GIF holds 256 colours per frame; left to the encoder, Pillow's quantizer picks
    them, and its choice may change between Pillow versions; given 256 it keeps them exactly."""
    stack = np.stack(frames).astype(np.uint32)
    codes = (stack[..., 0] << 16) | (stack[..., 1] << 8) | stack[..., 2]
    colours, inverse, counts = np.unique(codes, return_inverse=True, return_counts=True)
    rgb = np.stack([colours >> 16, (colours >> 8) & 255, colours & 255], axis=1).astype(np.int64)
    keep = rgb[np.argsort(-counts, kind="stable")[:n]]  # ties in the order of the codes
    nearest = ((rgb[:, None, :] - keep[None, :, :]) ** 2).sum(axis=2).argmin(axis=1)
    out = keep[nearest][inverse.reshape(codes.shape)].astype(np.uint8)
    return list(out)


def planning_png(out: Path) -> list[Path]:
    import imageio.v3 as iio

    env = BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array")
    sol = planning.value_iteration(planning.model(env.level), gamma=1.0)
    env.set_overlay(values=sol.value_grid, arrows=sol.best_actions, panel="value iteration, gamma = 1")
    env.reset(seed=0)
    for a in (2, 3, 3):
        env.step(a)
    iio.imwrite(out / "planning.png", env.render())
    small = BabyRobotEnv(level="walls", render_mode="rgb_array", cell_size=96)
    sol = planning.value_iteration(planning.model(small.level), gamma=0.9)
    h, w = sol.value_grid.shape
    q = sol.q.reshape(h, w, 5).copy()
    q[np.isnan(sol.value_grid)] = np.nan
    small.set_overlay(q_values=q, panel="action values q(s, a), gamma = 0.9")
    small.reset(seed=0)
    iio.imwrite(out / "action_values.png", small.render())
    return [out / "planning.png", out / "action_values.png"]


def themes_png(out: Path) -> Path:
    import imageio.v3 as iio

    tiles = []
    for name in THEMES:
        env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=40, theme=name)
        env.reset(seed=1)
        for _ in range(2):
            env.step({a: 2 if i % 2 else 3 for i, a in enumerate(env.agents)})
        frame = env.render()[: 7 * 40]
        label = raster([Text(6, 14, name, 16, THEMES[name].text, align="left")], frame.shape[1], 28, THEMES[name].panel)
        tiles.append(np.concatenate([frame, label], axis=0))
    gap = np.full((tiles[0].shape[0], 12, 3), 255, dtype=np.uint8)
    row = np.concatenate([t for tile in tiles for t in (tile, gap)][:-1], axis=1)
    iio.imwrite(out / "themes.png", row)
    return out / "themes.png"


def poses_png(out: Path) -> Path:
    import imageio.v3 as iio

    cs, theme = 72, THEMES["light"]
    ops = []
    for row, pose in enumerate(POSES):
        ops.append(Text(8, (row + 0.5) * cs, pose, 14, theme.text, align="left"))
        for heading in range(5):
            colour = ROBOT_COLOURS[(row + heading) % 8]
            ops += robot(110 + (heading + 0.5) * cs, (row + 0.5) * cs, cs, theme, colour, heading, pose, row * 5 + heading)
    for heading, name in enumerate(("STAY", "NORTH", "EAST", "SOUTH", "WEST")):
        ops.append(Text(110 + (heading + 0.5) * cs, len(POSES) * cs + 12, name, 12, theme.text))
    iio.imwrite(out / "poses.png", raster(ops, 110 + 5 * cs, len(POSES) * cs + 26, theme.floor))
    return out / "poses.png"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for path in [race_gif(args.out), *planning_png(args.out), themes_png(args.out), poses_png(args.out)]:
        print(f"wrote {path} ({path.stat().st_size:,} bytes)")


if __name__ == "__main__":
    main()
