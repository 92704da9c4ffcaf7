"""The site's pictures, drawn by the package itself at build time (``rgb_array`` frames).

mkdocs-gen-files runs ``gen_pages.py``, which calls :func:`write_all`; nothing drawn here is
stored in git except the README's picture, which ``python docs/_scripts/figures.py --readme``
writes to ``docs/assets/readme/baby-robot.png``.

Every animation is one seeded episode of the env named on its page, recorded with
``babyrobot_marl.render.video.episode_frames`` and written with ``save_gif``. The collision
pictures place two robots with ``RaceEnv.set_cells``, draw the frame before the step (arrows: the
actions) and the frame after it, side by side.
"""

from __future__ import annotations

import io
import sys
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))  # architecture.py, beside this file
import architecture  # noqa: E402

import babyrobot_marl  # noqa: E402, F401  (registers the envs)
from babyrobot_marl import Action, race_v0  # noqa: E402
from babyrobot_marl.policies import make as make_policy  # noqa: E402
from babyrobot_marl.render.video import episode_frames, save_gif  # noqa: E402

# One open corridor of 5 x 3 cells, the exit far from the robots: the collision set-ups.
COLLISION_LEVEL = """
+-+-+-+-+-+
|. . . . E|
+ + + + + +
|. . . . .|
+ + + + + +
|0 . . . 1|
+-+-+-+-+-+
"""

# name -> (collisions mode, the two robots' cells, their actions); docs/guides/rules.md says what each shows
COLLISIONS: dict[str, tuple[str, list[tuple[int, int]], list[Action]]] = {
    "block": ("block", [(1, 1), (3, 1)], [Action.EAST, Action.WEST]),
    "bounce": ("bounce", [(1, 1), (3, 1)], [Action.EAST, Action.WEST]),
    "pass": ("pass", [(1, 1), (3, 1)], [Action.EAST, Action.WEST]),
    "swap": ("block", [(1, 1), (2, 1)], [Action.EAST, Action.WEST]),
    "swap-pass": ("pass", [(1, 1), (2, 1)], [Action.EAST, Action.WEST]),
    "follow": ("block", [(1, 1), (2, 1)], [Action.EAST, Action.EAST]),
    "follow-blocked": ("block", [(1, 1), (2, 1)], [Action.EAST, Action.STAY]),
}
COLLISION_SEED = 3
ANIMATION, FPS = 3, 9  # the animations: 3 frames per step (the robots glide), 3 steps a second
GAP = 12  # pixels between the frames before and after


def png_bytes(image: np.ndarray) -> bytes:
    import imageio.v3 as iio

    buf = io.BytesIO()
    iio.imwrite(buf, image, extension=".png")
    return buf.getvalue()


def gif_bytes(frames: list[np.ndarray], fps: float) -> bytes:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = save_gif(frames, Path(tmp) / "episode.gif", fps=fps)
        return path.read_bytes()


def single_robot_gif() -> bytes:
    """BabyRobot-v0 on mixed-8x8: the shortest-path robot, its arrows drawn, seed 2."""
    env = gym.make("babyrobot_marl/BabyRobot-v0", level="mixed-8x8", render_mode="rgb_array", cell_size=48)
    u = env.unwrapped
    policy = make_policy("shortest", u.table)
    u.set_overlay(arrows=policy.actions.reshape(u.level.height, u.level.width))
    return gif_bytes(episode_frames(env, policy, seed=2, animation_frames=ANIMATION), fps=FPS)


def race_gym_gif() -> bytes:
    """BabyRobotRace-v0 on race-4: robot 0 takes the shortest path against shortest, random, random."""
    env = gym.make(
        "babyrobot_marl/BabyRobotRace-v0", level="race-4", opponents=["shortest", "random", "random"], render_mode="rgb_array"
    )
    policy = make_policy("shortest", env.unwrapped.race.table)  # the PettingZoo race under the Gymnasium adapter
    return gif_bytes(episode_frames(env, policy, seed=0, animation_frames=ANIMATION), fps=FPS)


def race_frames(seed: int = 4, animation_frames: int = 0) -> list[np.ndarray]:
    """race_v0 on race-4, 4 robots, collisions block: three shortest-path robots and a clumsy
    one (robot 3: a random action one step in three, else the shortest path)."""
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array")
    env.set_overlay(names=["shortest", "shortest", "shortest", "clumsy"])
    shortest = make_policy("shortest", env.table)
    rand = make_policy("random", env.table, seed=seed)
    policies = {a: shortest for a in env.possible_agents}
    policies["robot_3"] = lambda obs: rand(obs) if rand.rng.random() < 1 / 3 else shortest(obs)
    return episode_frames(env, policies, seed=seed, animation_frames=animation_frames)


def race_gif() -> bytes:
    return gif_bytes(race_frames(animation_frames=ANIMATION), fps=FPS)


def collision_picture(name: str, cell_size: int = 48) -> np.ndarray:
    """The frame before the step (the robots' actions as arrows) and the frame after it, side by side."""
    mode, cells, actions = COLLISIONS[name]
    env = race_v0.parallel_env(level=COLLISION_LEVEL, n_robots=2, collisions=mode, render_mode="rgb_array", cell_size=cell_size)
    env.reset(seed=COLLISION_SEED)
    env.set_cells(cells)
    arrows = np.zeros((env.level.height, env.level.width), dtype=np.int64)
    for (x, y), a in zip(cells, actions):
        arrows[y, x] = int(a)
    names = ("robot 0", "robot 1")
    env.set_overlay(arrows=arrows, panel=[f"{mode}: before"] + [f"{n}: {a.name.lower()}" for n, a in zip(names, actions)])
    before = env.render()
    _, _, _, _, infos = env.step({agent: int(a) for agent, a in zip(env.possible_agents, actions)})
    moved = [tuple(int(v) for v in infos[a]["cell"]) != cell for a, cell in zip(env.possible_agents, cells)]
    after_lines = [f"{n}: {'moved' if m else 'stayed'}" for n, m in zip(names, moved)]
    env.set_overlay(arrows=None, panel=["after one step", *after_lines])
    after = env.render()
    gap = np.full((before.shape[0], GAP, 3), 255, dtype=np.uint8)
    return np.concatenate([before, gap, after], axis=1)


def readme_picture() -> np.ndarray:
    """The README's picture: the race of the race_v0 page after 5 steps, beside one robot on
    mixed-8x8 with value iteration's values and greedy arrows overlaid (BabyRobot-v0)."""
    from babyrobot_marl.planning import model, value_iteration

    race = race_frames()[5]
    env = gym.make("babyrobot_marl/BabyRobot-v0", level="mixed-8x8", render_mode="rgb_array", cell_size=48)
    env.reset(seed=0)
    sol = value_iteration(model(env.unwrapped), gamma=1.0)
    env.unwrapped.set_overlay(values=sol.value_grid, arrows=sol.policy_grid)
    single = env.render()
    height = max(race.shape[0], single.shape[0])
    pad = [np.pad(img, ((0, height - img.shape[0]), (0, 0), (0, 0)), constant_values=255) for img in (race, single)]
    gap = np.full((height, 2 * GAP, 3), 255, dtype=np.uint8)
    return np.concatenate([pad[0], gap, pad[1]], axis=1)


FIGURES: dict[str, Callable[[], bytes]] = {
    "assets/envs/babyrobot-v0.gif": single_robot_gif,
    "assets/envs/babyrobotrace-v0.gif": race_gym_gif,
    "assets/envs/race_v0.gif": race_gif,
    "assets/architecture.svg": lambda: architecture.svg(architecture.import_graph()).encode(),
    **{f"assets/collisions/{name}.png": (lambda name=name: png_bytes(collision_picture(name))) for name in COLLISIONS},
}


def write_all(open_file: Callable[[str, str], io.IOBase]) -> list[str]:
    """Draw every figure and write it with ``open_file(path, "wb")``; returns the paths."""
    for path, draw in FIGURES.items():
        with open_file(path, "wb") as f:
            f.write(draw())
    return list(FIGURES)


if __name__ == "__main__":
    if sys.argv[1:] != ["--readme"]:
        sys.exit("usage: python docs/_scripts/figures.py --readme   (the site's figures are drawn by mkdocs build)")
    out = Path(__file__).resolve().parents[1] / "assets" / "readme" / "baby-robot.png"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_bytes(png_bytes(readme_picture()))
    print(out)
