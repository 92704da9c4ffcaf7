"""Real-browser tests of the live canvas's first frame and its replay (issue 26 items 3 and 6).

- No blank first frame: from the moment the canvas output appears on the page, every animation
  frame of the page shows it drawn (read in the page at each animation frame, ``record_canvas``).
- Replay: after an episode the replay bar (slider and play button) shows under the canvas; dragging
  the slider to its start draws the first scene on the same canvas, and the kernel's env has not
  stepped (its step counter and the canvas's scenes unchanged). For one robot and for a race.

Every wait is for an event, with the harness's limit (``chrome.WAIT``). The intervals between the
frames drawn in the first steps are printed (a figure, not a test).
"""

from __future__ import annotations

import numpy as np

from babyrobot_marl.render.palette import THEMES
from tests.browser.chrome import WAIT
from tests.test_browser import CELL, MARKER, cell_box, count, shot

THEME = THEMES["light"]
# mixed-8x8 from (0, 0) to its exit (7, 7) along a shortest path (14 steps)
PATH = [2, 2, 3, 3, 2, 2, 2, 3, 2, 2, 3, 3, 3, 3]
REPLAY_BAR = ".babyrobot-replay"


def _open(page, screenshots, name: str, cells: list[str], before=None) -> None:
    from tests.browser.notebook_files import write_notebook

    write_notebook(page.lab.root_dir / f"{name}.ipynb", [*cells, f"print({MARKER!r})"])
    try:
        page.run_all(f"{name}.ipynb", MARKER, before=before)
    finally:
        shot(page, screenshots, name)


def _replay_bar_shown(page) -> None:
    # shown, and its slider at the episode's last step (the kernel sets its range and value just
    # before showing it; a drag before the browser has them would move a slider already at 0)
    page.page.wait_for_function(
        f"() => {{ const b = document.querySelector('{REPLAY_BAR}'); const r = b && b.querySelector('.widget-readout');"
        f" return !!b && b.getBoundingClientRect().height > 0 && !!r && r.innerText.trim() !== '0'; }}",
        timeout=WAIT * 1000,
        polling=200,
    )


def _drag_slider_to_start(page) -> None:
    """Drag the replay slider's handle past the left end of its track, as a learner would."""
    p = page.page
    handle = p.locator(f"{REPLAY_BAR} .noUi-handle").first
    track = p.locator(f"{REPLAY_BAR} .noUi-target").first
    h, t = handle.bounding_box(), track.bounding_box()
    p.mouse.move(h["x"] + h["width"] / 2, h["y"] + h["height"] / 2)
    p.mouse.down()
    p.mouse.move(t["x"] - 40, h["y"] + h["height"] / 2, steps=8)
    p.mouse.up()


def _kernel_state(page, env: str) -> str:
    return page.kernel_output(f"print({env}.unwrapped.elapsed_steps, len({env}.unwrapped.canvas.history), "
                              f"{env}.unwrapped.canvas.frames_sent)").strip()  # fmt: skip


def test_single_robot_replay_redraws_an_earlier_frame_without_stepping(page, screenshots):
    name = "replay_single"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL}, animation_frames=0, render_fps=0)
        env.reset(seed=0)
        for a in {PATH}:
            env.step(a)
        """,
    ])  # fmt: skip
    start, exit_ = (0, 0), (7, 7)
    body = THEME.robots[0]
    end = page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], exit_), body) > 50)[..., :3]
    _replay_bar_shown(page)
    before = _kernel_state(page, "env")
    steps, scenes, sent = map(int, before.split())
    assert steps == len(PATH) and scenes == len(PATH) + 1, before
    assert count(cell_box(end, start), body) == 0  # at the end the robot is in the exit, not at the start
    _drag_slider_to_start(page)
    first = page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], start), body) > 50)[..., :3]
    shot(page, screenshots, f"{name}_at_start")
    assert count(cell_box(first, start), body) > 50, "the replay did not draw the robot at its start"
    assert count(cell_box(first, exit_), body) == 0, "the robot is still drawn in the exit"
    after = _kernel_state(page, "env")
    steps2, scenes2, sent2 = map(int, after.split())
    assert (steps2, scenes2) == (steps, scenes), f"the env stepped: {before} -> {after}"
    assert sent2 > sent  # the canvas drew the replayed scene (the kernel sent it, stepping nothing)


def test_race_replay_redraws_the_start_without_stepping(page, screenshots):
    name = "replay_race"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import race_v0
        from babyrobot_marl.policies import ShortestPathPolicy
        race = race_v0.parallel_env(level="race-4", n_robots=2, render_mode="human", cell_size={CELL},
                                    animation_frames=0, render_fps=0)
        obs, _ = race.reset(seed=0)
        starts = race.unwrapped.robot_cells
        policy = ShortestPathPolicy(race.unwrapped.table)
        while race.agents:
            obs, *_ = race.step({{a: policy(obs[a]) for a in race.agents}})
        print("STARTS", starts)
        """,
    ])  # fmt: skip
    import ast

    text = page.outputs_text()
    starts = ast.literal_eval(text.split("STARTS ", 1)[1].splitlines()[0])
    _replay_bar_shown(page)
    before = _kernel_state(page, "race")
    steps, scenes, sent = map(int, before.split())
    end = page.canvas_pixels(0)[..., :3]
    _drag_slider_to_start(page)

    def at_starts(rgba: np.ndarray) -> bool:
        return all(count(cell_box(rgba[..., :3], c), THEME.robots[i]) > 50 for i, c in enumerate(starts))

    # at the starts and no longer the last frame (the start flags wear the robots' colours too)
    first = page.canvas_pixels(0, ready=lambda rgba: at_starts(rgba) and not (rgba[..., :3] == end).all())[..., :3]
    shot(page, screenshots, f"{name}_at_start")
    assert at_starts(first), "the replay did not draw the robots at their starts"
    assert not (first == end).all()
    after = _kernel_state(page, "race")
    steps2, scenes2, sent2 = map(int, after.split())
    assert (steps2, scenes2) == (steps, scenes), f"the race stepped: {before} -> {after}"
    assert sent2 > sent


def signature(rgba: np.ndarray) -> int:
    """The page's checksum of a canvas's pixels (``_RECORD_CANVAS`` in tests/browser/chrome.py)."""
    sig = 0
    flat = rgba.reshape(-1)
    for i in range(0, flat.size, 28):
        sig = (sig * 31 + int(flat[i]) + 3 * int(flat[i + 1]) + 7 * int(flat[i + 2])) % 2**32
    return sig


def test_no_blank_first_frame(page, screenshots):
    """From the first animation frame the canvas is on the page, it shows the level with the robot:
    the picture it keeps (no blank canvas, no level without its robot, before any step)."""
    name = "first_frame"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL})
        env.reset(seed=0)
        """,
    ], before=page.record_canvas)  # fmt: skip
    final = page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], (0, 0)), THEME.robots[0]) > 50)
    frames = page.recorded_frames()
    assert frames, "the canvas was never seen on the page"
    assert frames[0]["drawn"], f"the canvas appeared blank (not drawn) at first: {frames[:3]}"
    assert [f["sig"] for f in frames] == [signature(final)], f"the canvas changed after it appeared: {frames}"


def test_the_first_steps_are_paced_as_the_others(page, screenshots):
    """Eight steps at 4 a second right after the canvas is shown: each step's frame seen, none
    blank; the times between them are printed (the first step's stall of issue 26, if any)."""
    name = "first_steps"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL}, animation_frames=1, render_fps=4)
        env.reset(seed=0)
        for a in {PATH[:8]}:
            env.step(a)
        """,
    ], before=page.record_canvas)  # fmt: skip
    # the last step's frame (the robot where the eight steps take it), then the record
    page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], (5, 3)), THEME.robots[0]) > 50)
    frames = page.recorded_frames()
    assert frames and all(f["drawn"] for f in frames), f"a blank canvas was seen: {frames}"
    times = [round(f["t"] - frames[0]["t"]) for f in frames]
    page.log(f"{name}: canvas changes at {times} ms after it appeared (4 steps a second intended: 250 ms apart)")
    assert len(frames) >= 8, f"fewer changes than steps: {times}"


def test_the_player_replays_its_episode_without_stepping(page, screenshots):
    name = "replay_player"
    _open(page, screenshots, name, [
        f"""
        from babyrobot_marl.play import notebook
        player = notebook.play("default", seed=0, cell_size={CELL})
        player
        """,
        """
        for key in ["ArrowRight", "ArrowRight", "s", "s"]:
            player.press(key)
        print("over:", player.game.terminated)
        """,
    ])  # fmt: skip
    assert "over: True" in page.outputs_text()
    start, exit_ = (0, 0), (2, 2)
    body = THEME.robots[0]
    page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], exit_), body) > 50)
    _replay_bar_shown(page)
    before = page.kernel_output("print(player.game.steps, len(player.canvas.history), player.canvas.frames_sent)").strip()
    steps, scenes, sent = map(int, before.split())
    assert (steps, scenes) == (4, 5), before
    _drag_slider_to_start(page)
    first = page.canvas_pixels(0, ready=lambda rgba: count(cell_box(rgba[..., :3], start), body) > 50)[..., :3]
    shot(page, screenshots, f"{name}_at_start")
    assert count(cell_box(first, start), body) > 50 and count(cell_box(first, exit_), body) == 0
    after = page.kernel_output("print(player.game.steps, len(player.canvas.history), player.canvas.frames_sent)").strip()
    assert after.split()[:2] == before.split()[:2] and int(after.split()[2]) > sent, f"{before} -> {after}"
