"""Real-browser test: JupyterLab + headless Chromium (Playwright) run notebooks and we read the canvas pixels.

Needs the system Chromium (``apt-get install chromium fonts-liberation``, done by ``.ci/browser.sh``)
and the ``test`` extra (jupyterlab, playwright, ipycanvas). Locally the tests skip when Chromium is
absent; with ``CI=true`` a missing browser fails them. Screenshots go to ``$BABYROBOT_SCREENSHOTS``
(default: ``<tmp>/babyrobot_marl_screenshots``) and their paths are printed.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import pytest

from tests.browser.chrome import chromium_path
from tests.browser.lab import LabServer, processes_mentioning
from tests.browser.notebook_files import write_notebook

ROOT = Path(__file__).resolve().parents[1]
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")
MARKER = "BROWSER-TEST-DONE"
SCREENSHOTS = Path(os.environ.get("BABYROBOT_SCREENSHOTS", Path(tempfile.gettempdir()) / "babyrobot_marl_screenshots"))


def _unavailable() -> str | None:
    if chromium_path() is None:
        return "Chromium not installed (apt-get install chromium fonts-liberation; .ci/browser.sh does it in CI)"
    for module in ("playwright", "jupyterlab", "ipycanvas"):
        try:
            __import__(module)
        except ImportError:
            return f"{module} not installed (pip install -e '.[test]')"
    return None


@pytest.fixture(scope="module")
def browser_ready():
    reason = _unavailable()
    if reason is not None:
        if IN_CI:
            pytest.fail(f"CI=true and the browser test cannot run: {reason}")
        pytest.skip(reason)


@pytest.fixture(scope="module")
def lab(browser_ready, tmp_path_factory):

    root, work = tmp_path_factory.mktemp("lab_root"), tmp_path_factory.mktemp("lab_work")
    with LabServer(root, work, pythonpath=ROOT) as server:
        yield server
    left = processes_mentioning(str(root)) + processes_mentioning(str(work))  # the server and its kernels
    assert not left, f"processes left behind by JupyterLab: {left}"


@pytest.fixture(scope="module")
def page(lab, tmp_path_factory):
    from tests.browser.chrome import NotebookPage

    profile = tmp_path_factory.mktemp("chromium_profile")
    with NotebookPage(lab, profile, chromium_path()) as nb:
        yield nb
    left = processes_mentioning(str(profile))
    assert not left, f"Chromium processes left behind: {left}"


def run_in_browser(lab, page, name: str, cells: list[str], capsys) -> np.ndarray:
    """Write ``name``.ipynb into the server root, run it in the browser, screenshot it, return canvas 0 (RGB)."""
    write_notebook(lab.root_dir / f"{name}.ipynb", [*cells, f"print({MARKER!r})"])
    try:
        page.run_all(f"{name}.ipynb", MARKER)
        pixels = page.canvas_pixels(0)
    finally:
        shot = page.screenshot(SCREENSHOTS / f"{name}.png")
        with capsys.disabled():
            print(f"\nscreenshot: {shot}")
    assert (pixels[..., 3] == 255).all(), "the canvas has transparent pixels: something was not drawn"
    return pixels[..., :3]


def test_plain_ipycanvas_pixels(lab, page, capsys):
    """The harness itself: a canvas drawn with plain ipycanvas reads back with the colours drawn."""
    img = run_in_browser(lab, page, "plain_ipycanvas", [
        """
        from ipycanvas import Canvas, hold_canvas
        canvas = Canvas(width=120, height=60)
        with hold_canvas(canvas):
            canvas.fill_style = "#dc3c32"
            canvas.fill_rect(0, 0, 60, 60)
            canvas.fill_style = "#325ad2"
            canvas.fill_rect(60, 0, 60, 60)
        canvas
        """,
    ], capsys)  # fmt: skip
    assert img.shape == (60, 120, 3)
    assert tuple(img[30, 30]) == (0xDC, 0x3C, 0x32)
    assert tuple(img[30, 90]) == (0x32, 0x5A, 0xD2)


# ------------------------------------------------------------------ the env's live canvas
CELL = 32  # cell_size of the test envs: cell (x, y) covers pixels [x*CELL, (x+1)*CELL) of the grid


def _centre(cell) -> tuple[int, int]:
    return cell[0] * CELL + CELL // 2, cell[1] * CELL + CELL // 2


def expected_pixels(level, robots, theme, avoid=()) -> list[tuple[str, tuple[int, int], tuple[int, int, int]]]:
    """(what, (px, py), colour) at known places: each robot's centre, an empty floor cell's centre,
    the middle of an inner wall, the middle of the top border. The empty cell is none of ``avoid``."""
    samples = [(f"robot {i} at {cell}", _centre(cell), theme.robots[i % len(theme.robots)]) for i, cell in enumerate(robots)]
    marked = {*level.starts, *level.exits, *level.small_puddles, *level.large_puddles, *level.blocked, *robots, *avoid}
    empty = next((x, y) for y in range(level.height) for x in range(level.width) if (x, y) not in marked)
    samples.append((f"empty floor cell {empty}", _centre(empty), theme.floor))
    a, b = sorted(level.walls)[len(level.walls) // 2]
    on_wall = (b[0] * CELL, a[1] * CELL + CELL // 2) if a[1] == b[1] else (a[0] * CELL + CELL // 2, b[1] * CELL)
    samples.append((f"wall between {a} and {b}", on_wall, theme.wall))
    samples.append(("top border", (CELL // 2 + CELL, 1), theme.wall))
    return samples


def assert_pixels(img: np.ndarray, samples) -> None:
    wrong = [
        f"{what} at pixel {p}: expected {colour}, got {tuple(int(v) for v in img[p[1], p[0]])}"
        for what, p, colour in samples
        if tuple(int(v) for v in img[p[1], p[0]]) != tuple(colour)
    ]
    assert not wrong, "\n".join(wrong)


SINGLE_ACTIONS = [2, 2, 3, 3]  # EAST, EAST, SOUTH, SOUTH on "walls" from its start (0, 0)
ARROW_CELL = (3, 2)  # an empty cell of "walls" given an EAST arrow overlay


def test_single_robot_live_canvas(lab, page, capsys):
    from babyrobot_marl import BabyRobotEnv
    from babyrobot_marl.render.rgb import THEMES

    img = run_in_browser(lab, page, "single_robot_canvas", [
        f"""
        import numpy as np
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="walls", render_mode="human", cell_size={CELL})
        env.reset(seed=0)
        for a in {SINGLE_ACTIONS}:
            env.step(a)
        arrows = np.full((env.level.height, env.level.width), -1)
        arrows[{ARROW_CELL[1]}, {ARROW_CELL[0]}] = 2
        env.set_overlay(arrows=arrows, panel="a panel line")
        print("robot at", env.robot_cell)
        """,
    ], capsys)  # fmt: skip
    env = BabyRobotEnv(level="walls")  # the same episode, played here
    env.reset(seed=0)
    for a in SINGLE_ACTIONS:
        env.step(a)
    lv, theme = env.level, THEMES["light"]
    assert env.robot_cell != lv.starts[0] and env.robot_cell != ARROW_CELL
    assert f"robot at {env.robot_cell}" in page.outputs_text()
    samples = expected_pixels(lv, [env.robot_cell], theme, avoid=[ARROW_CELL])
    # the overlay layer: an arrow's shaft east of the cell centre, and the panel below the grid
    samples.append(("EAST arrow shaft", (ARROW_CELL[0] * CELL + CELL * 5 // 8, ARROW_CELL[1] * CELL + CELL // 2), theme.arrow))
    grid_h = lv.height * CELL
    assert img.shape[0] > grid_h + 8, f"no panel below the {grid_h}-pixel grid: canvas is {img.shape[0]} pixels high"
    samples.append(("panel background", (img.shape[1] - 3, grid_h + 3), theme.panel))
    assert_pixels(img, samples)


RACE_STEPS = 3


def test_race_live_canvas(lab, page, capsys):
    from babyrobot_marl import race_v0
    from babyrobot_marl.policies import ShortestPathPolicy
    from babyrobot_marl.render.rgb import THEMES

    img = run_in_browser(lab, page, "race_canvas", [
        f"""
        from babyrobot_marl import race_v0
        from babyrobot_marl.policies import ShortestPathPolicy
        env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="human", cell_size={CELL})
        obs, infos = env.reset(seed=0)
        policy = ShortestPathPolicy(env.unwrapped.table)
        for _ in range({RACE_STEPS}):
            obs, *_ = env.step({{a: policy(obs[a]) for a in env.agents}})
        print("robots at", env.unwrapped.robot_cells)
        """,
    ], capsys)  # fmt: skip
    env = race_v0.parallel_env(level="race-4", n_robots=4)  # the same race, played here
    obs, _ = env.reset(seed=0)
    policy = ShortestPathPolicy(env.unwrapped.table)
    for _ in range(RACE_STEPS):
        obs, *_ = env.step({a: policy(obs[a]) for a in env.agents})
    cells = env.unwrapped.robot_cells
    assert len(env.agents) == 4 and len(set(cells)) == 4  # all four still on the board, apart
    assert f"robots at {cells}" in page.outputs_text()
    assert_pixels(img, expected_pixels(env.unwrapped.level, cells, THEMES["light"]))


def test_canvas_redrawn_when_a_browser_reconnects(lab, page, capsys):
    """Reload the page: the kernel still holds the env, and the canvas (empty in a new page) must be
    drawn again (``on_client_ready``), robot included."""
    from babyrobot_marl import BabyRobotEnv
    from babyrobot_marl.render.rgb import THEMES

    name = "reconnect_canvas"
    run_in_browser(lab, page, name, [
        f"""
        from babyrobot_marl import BabyRobotEnv
        env = BabyRobotEnv(level="walls", render_mode="human", cell_size={CELL})
        env.reset(seed=0)
        for a in {SINGLE_ACTIONS}:
            env.step(a)
        """,
    ], capsys)  # fmt: skip
    page.save_and_reopen(f"{name}.ipynb", MARKER)
    img = page.canvas_pixels(0)
    shot = page.screenshot(SCREENSHOTS / f"{name}_reopened.png")
    with capsys.disabled():
        print(f"\nscreenshot: {shot}")
    env = BabyRobotEnv(level="walls")
    env.reset(seed=0)
    for a in SINGLE_ACTIONS:
        env.step(a)
    assert (img[..., 3] == 255).all(), "the canvas was not drawn again after the page was reloaded"
    assert_pixels(img[..., :3], expected_pixels(env.level, [env.robot_cell], THEMES["light"]))
