"""Time per rgb_array frame: Baby Robot beside Minigrid, both 8x8 cells drawn at 256x256 pixels.

    python benchmarks/bench_render.py            # a few seconds
    python benchmarks/bench_render.py --quick    # CI: well under a second

Both render through their env's ``render()`` after a random step, in the same process,
interleaved round by round; medians over rounds. Minigrid (pip package ``minigrid``, the
``bench`` extra) draws MiniGrid-Empty-8x8-v0 with its default 32-pixel tiles: 256x256.
Rows for 8x8 and 32x32 mazes with 1 and 8 robots, and with an overlay (values and arrows).

Then the live canvas: the Python-side time to issue one frame (robots redrawn in one
``hold_canvas`` batch, serialised as ipycanvas sends it; no browser attached) beside the
plain way (the whole ``rgb_array`` frame put on a canvas each step, PNG-encoded), one
animated step, and overlay changes (needs the ``notebook`` extra).
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time

import numpy as np

from babyrobot_marl import BabyRobotEnv, race_v0


def frame_time(env, step, frames: int, rng: np.random.Generator) -> float:
    """Seconds per (step + render) minus seconds per step: the render alone."""
    env.reset(seed=0)
    actions = rng.integers(0, 3, frames).tolist()
    t0 = time.perf_counter()
    for a in actions:
        step(env, a)
        env.render()
    t1 = time.perf_counter()
    for a in actions:
        step(env, a)
    t2 = time.perf_counter()
    return max(((t1 - t0) - (t2 - t1)) / frames, 0.0)


def gym_step(env, a: int) -> None:
    _, _, terminated, truncated, _ = env.step(a)
    if terminated or truncated:
        env.reset()


def race_step(env, a: int) -> None:
    if not env.agents:
        env.reset()
    env.step({agent: a for agent in env.agents})


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--frames", type=int, default=2000)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args(argv)
    frames, rounds = (200, 1) if args.quick else (args.frames, args.rounds)
    def race(level: str, n: int, **kw):
        return race_v0.parallel_env(level=level, n_robots=n, start="random", render_mode="rgb_array", cell_size=32, **kw)

    overlaid = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array", cell_size=32)
    overlaid.set_overlay(values=np.arange(64.0).reshape(8, 8), arrows=np.full((8, 8), 2))
    envs = {
        "babyrobot mixed-8x8, 1 robot": (BabyRobotEnv(level="mixed-8x8", render_mode="rgb_array", cell_size=32), gym_step),
        "babyrobot maze-8x8, 8 robots": (race("maze-8x8", 8), race_step),
        "babyrobot maze-8x8 + overlay": (overlaid, gym_step),
        "babyrobot maze-32x32, 1 robot": (BabyRobotEnv(level="maze-32x32", render_mode="rgb_array", cell_size=32), gym_step),
        "babyrobot maze-32x32, 8 robots": (race("maze-32x32", 8), race_step),
        "babyrobot race-4 (7x7), 4 robots": (
            race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=32),
            race_step,
        ),
    }
    peer = "minigrid Empty-8x8 (peer)"
    if importlib.util.find_spec("minigrid") is not None:
        import gymnasium
        import minigrid  # noqa: F401  (registers MiniGrid envs)

        envs[peer] = (gymnasium.make("MiniGrid-Empty-8x8-v0", render_mode="rgb_array").unwrapped, gym_step)
    rng = np.random.default_rng(0)
    times: dict[str, list[float]] = {name: [] for name in envs}
    for _ in range(rounds):
        for name, (env, step) in envs.items():
            times[name].append(frame_time(env, step, frames, rng))
    peer_t = statistics.median(times[peer]) if peer in times else None
    print(f"{'rgb_array frame (256x256 for 8x8)':36s} {'ms/frame':>9s} {'shape':>15s} {'vs minigrid':>12s}")
    for name, ts in times.items():
        t = statistics.median(ts)
        shape = envs[name][0].render().shape
        ratio = f"{peer_t / t:11.1f}x" if peer_t and t > 0 else "          -"
        print(f"{name:36s} {t * 1e3:9.4f} {str(shape):>15s} {ratio}")
    if peer_t is None:
        print("minigrid is not installed (pip install -e '.[bench]'): no peer figure")
    canvas_times(frames // 4, rounds)


def canvas_times(frames: int, rounds: int) -> None:
    """Python-side cost of live-canvas frames (ipycanvas serialises and sends; no browser here)."""
    if importlib.util.find_spec("ipycanvas") is None:
        print("\nipycanvas is not installed (pip install -e '.[notebook]'): no canvas figures")
        return
    from ipycanvas import Canvas, hold_canvas

    from babyrobot_marl import levels
    from babyrobot_marl.render.canvas import LiveCanvas
    from babyrobot_marl.render.overlay import Overlay, update_overlay
    from babyrobot_marl.render.rgb import RgbRenderer

    print(f"\n{'live canvas, Python side (fps=0: unpaced)':52s} {'ms/frame':>9s} {'vs whole image':>15s}")
    for level, n in (("maze-8x8", 1), ("maze-8x8", 8), ("maze-32x32", 8)):
        lv = levels.get(level)
        renderer = RgbRenderer(lv, 32)
        canvas = LiveCanvas(renderer, animation_frames=0, fps=0)
        plain = Canvas(width=renderer.shape[1], height=renderer.shape[0])
        cells = [[(k % lv.width, (k + i) % lv.height) for i in range(n)] for k in range(frames)]
        ts, peer = [], []
        for _ in range(rounds):
            t0 = time.perf_counter()
            for robots in cells:
                canvas.draw(robots)
            t1 = time.perf_counter()
            for robots in cells[: max(1, frames // 10)]:  # the peer: the whole rgb_array frame sent each step
                rgba = np.dstack([renderer.frame(robots), np.full(renderer.shape[:2], 255, np.uint8)])
                with hold_canvas():
                    plain.put_image_data(rgba, 0, 0)
            ts.append((t1 - t0) / frames)
            peer.append((time.perf_counter() - t1) / max(1, frames // 10))
        t, p = statistics.median(ts), statistics.median(peer)
        print(f"{f'robots frame, {level}, {n} robots':52s} {t * 1e3:9.4f} {p / t:14.1f}x")
        print(f"{f'  peer: whole frame as PNG, {level}':52s} {p * 1e3:9.4f}")
    lv = levels.get("maze-8x8")
    canvas = LiveCanvas(RgbRenderer(lv, 32), animation_frames=4, fps=0)
    cells = [[(k % lv.width, 1)] for k in range(frames)]
    t0 = time.perf_counter()
    for robots in cells:
        canvas.draw(robots)
    print(f"{'one step, 4 animation frames, 1 robot':52s} {(time.perf_counter() - t0) / frames * 1e3:9.4f}  (per step)")
    k = max(4, frames // 10)
    arrows = [update_overlay(Overlay(), lv, arrows=np.full((8, 8), 1 + i % 4)) for i in range(k)]
    values = [update_overlay(Overlay(), lv, values=np.full((8, 8), float(i)) + np.eye(8)) for i in range(k)]
    for what, overlays in (("arrows (ink layer only)", arrows), ("values (level PNG + numbers)", values)):
        canvas = LiveCanvas(RgbRenderer(lv, 32), animation_frames=0, fps=0)
        t0 = time.perf_counter()
        for ov in overlays:
            canvas.set_overlay(ov)
        print(f"{'overlay change, 8x8: ' + what:52s} {(time.perf_counter() - t0) / len(overlays) * 1e3:9.4f}")
    print("(a browser then decodes and paints these; that side is not measured here)")


if __name__ == "__main__":
    main()
