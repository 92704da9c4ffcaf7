"""Real-browser test: JupyterLab + headless Chromium (Playwright) run notebooks and we read the canvas pixels.

Needs the system Chromium (``apt-get install chromium fonts-liberation``, done by ``.ci/browser.sh``)
and the ``test`` extra (jupyterlab, playwright, ipycanvas). Locally the tests skip when Chromium is
absent; with ``CI=true`` a missing browser fails them. The fixtures (``tests/browser/fixtures.py``)
print each step on the terminal as it happens. Screenshots go to ``$BABYROBOT_SCREENSHOTS``
(default: a folder in pytest's temporary directory) and their paths are printed.

Every wait is for an event (the kernel idle, a marker printed, the canvas drawn, the robot in it),
with a limit (``chrome.WAIT``) that only a dead kernel or browser reaches.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tests.browser.chrome import WAIT

ROOT = Path(__file__).resolve().parents[1]
MARKER = "BROWSER-TEST-DONE"


def shot(page, screenshots: Path, name: str) -> Path:
    """Screenshot the page into ``screenshots`` and say where."""
    path = page.screenshot(screenshots / f"{name}.png")
    page.log(f"screenshot: {path}")
    return path


def run_in_browser(page, screenshots: Path, name: str, cells: list[str], ready=None) -> np.ndarray:
    """Write ``name``.ipynb into the server root, run it in the browser, screenshot it, return canvas 0
    (RGB, at its backing store's resolution) once drawn and, with ``ready(rgb)``, once that holds:
    the canvas's layers arrive one after another."""
    from tests.browser.notebook_files import write_notebook

    write_notebook(page.lab.root_dir / f"{name}.ipynb", [*cells, f"print({MARKER!r})"])
    try:
        page.run_all(f"{name}.ipynb", MARKER)
        pixels = page.canvas_pixels(0, ready=None if ready is None else lambda rgba: ready(rgba[..., :3]))
        page.log(f"{name}.ipynb: canvas drawn")
    finally:
        shot(page, screenshots, name)
    assert (pixels[..., 3] == 255).all(), "the canvas has transparent pixels: something was not drawn"
    return pixels[..., :3]


def test_plain_ipycanvas_pixels(page, screenshots):
    """The harness itself: a canvas drawn with plain ipycanvas reads back with the colours drawn."""
    img = run_in_browser(page, screenshots, "plain_ipycanvas", [
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
    ])  # fmt: skip
    assert img.shape == (60, 120, 3)
    assert tuple(img[30, 30]) == (0xDC, 0x3C, 0x32)
    assert tuple(img[30, 90]) == (0x32, 0x5A, 0xD2)


# ------------------------------------------------------------------ the env's live canvas
CELL = 32  # cell_size of the test envs, in CSS pixels
PX = 2 * CELL  # the canvas's backing store: two device pixels per CSS pixel (pixel_ratio 2)


def cell_box(img: np.ndarray, cell) -> np.ndarray:
    x, y = cell
    return img[y * PX : (y + 1) * PX, x * PX : (x + 1) * PX]


def has(pixels: np.ndarray, colour) -> bool:
    return bool((pixels.reshape(-1, 3) == tuple(colour)).all(axis=1).any())


def count(pixels: np.ndarray, colour) -> int:
    return int((pixels.reshape(-1, 3) == tuple(colour)).all(axis=1).sum())


def assert_robot_at(img: np.ndarray, cell, colour, theme) -> None:
    """Baby Robot in ``cell``: more than one colour of it, its body's and its eye's (and its visor's)."""
    box = cell_box(img, cell)
    missing = [what for what, c in (("body", colour), ("eye", theme.eye), ("visor", theme.visor)) if not has(box, c)]
    assert not missing, f"robot at {cell}: no {', '.join(missing)} pixels"


def assert_backing_store_is_twice_the_css_size(page) -> None:
    size = page.canvas_size(0)
    assert size["dpr"] == 2
    assert size["width"] == 2 * round(size["css_width"]) and size["height"] == 2 * round(size["css_height"]), size


SINGLE_ACTIONS = [2, 3, 3, 2]  # EAST, SOUTH, SOUTH, EAST on mixed-8x8 from its start (0, 0)
GLASS = ((1, 6), (2, 6))  # mixed-8x8's glass wall
# a notebook cell: one robot on mixed-8x8 takes SINGLE_ACTIONS on its live canvas
WALK_CELL = f"""
from babyrobot_marl import BabyRobotEnv
env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL})
env.reset(seed=0)
for a in {SINGLE_ACTIONS}:
    env.step(a)
"""


def test_single_robot_live_canvas(page, screenshots):
    from babyrobot_marl import BabyRobotEnv, planning
    from babyrobot_marl.render.palette import THEMES
    from babyrobot_marl.render.rgb import RgbRenderer

    env = BabyRobotEnv(level="mixed-8x8", cell_size=CELL)  # the episode the browser will show, played here
    sol = planning.value_iteration(planning.model(env.level), gamma=1.0)
    env.set_overlay(values=sol.value_grid, arrows=sol.best_actions, panel="a panel line")
    env.reset(seed=0)
    for a in SINGLE_ACTIONS:
        env.step(a)
    lv, theme = env.level, THEMES["light"]
    img = run_in_browser(page, screenshots, "single_robot_canvas", [
        f"""
        from babyrobot_marl import BabyRobotEnv, planning
        env = BabyRobotEnv(level="mixed-8x8", render_mode="human", cell_size={CELL})
        sol = planning.value_iteration(planning.model(env.level), gamma=1.0)
        env.set_overlay(values=sol.value_grid, arrows=sol.best_actions, panel="a panel line")
        env.reset(seed=0)
        for a in {SINGLE_ACTIONS}:
            env.step(a)
        print("robot at", env.robot_cell)
        """,
    ], ready=lambda rgb: has(cell_box(rgb, env.robot_cell), theme.eye))  # fmt: skip
    assert f"robot at {env.robot_cell}" in page.outputs_text()
    assert env.robot_cell not in (lv.starts[0], *lv.exits)
    assert_backing_store_is_twice_the_css_size(page)
    assert_robot_at(img, env.robot_cell, theme.robots[0], theme)
    # away from the robot the canvas shows exactly the rgb_array picture at twice the cell size
    static = RgbRenderer(lv, PX).static(env.overlay)
    for cell in [(5, 5), (6, 6), (3, 1)]:
        assert (cell_box(img, cell) == cell_box(static, cell)).all(), f"cell {cell} differs from rgb_array's picture"
    # value text inside its cell: the light text in the dark box, within the cell's walls
    box = cell_box(img, (5, 5))
    text = np.argwhere((box == theme.value_text).all(axis=2))
    assert len(text) > 10 and text.min() >= 4 and text.max() < PX - 4
    # the glass pane on the glass edge: pane and frame colours there, no wall colour
    (ax, ay), _ = GLASS
    edge = img[ay * PX + PX // 4 : (ay + 1) * PX - PX // 4, (ax + 1) * PX - 6 : (ax + 1) * PX + 6]
    assert has(edge, theme.glass) and has(edge, theme.glass_frame) and not has(edge, theme.wall)
    # the START and EXIT words, and the panel with the colour bar below the grid
    assert has(cell_box(img, lv.starts[0])[: PX // 3], theme.label_bg)
    grid_h = lv.height * PX
    assert img.shape[0] > grid_h + 40, f"no panel below the {grid_h}-pixel grid: canvas is {img.shape[0]} pixels high"
    assert has(img[grid_h:], theme.panel) and has(img[grid_h:], (253, 231, 37))  # viridis' top colour in the bar


RACE_LEVEL = "race-4"


def first_finish(seed: int = 0) -> int:
    """Steps of race-4 with four shortest-path robots until the first robot finishes."""
    from babyrobot_marl import race_v0
    from babyrobot_marl.policies import ShortestPathPolicy

    env = race_v0.parallel_env(level=RACE_LEVEL, n_robots=4)
    obs, _ = env.reset(seed=seed)
    policy = ShortestPathPolicy(env.unwrapped.table)
    for t in range(1, 100):
        obs, *_ = env.step({a: policy(obs[a]) for a in env.agents})
        if any(env.unwrapped.ranks):
            return t
    raise AssertionError("nobody finished")


def test_race_live_canvas_legend_and_the_finisher_in_the_exit(page, screenshots):
    from babyrobot_marl import race_v0
    from babyrobot_marl.policies import ShortestPathPolicy
    from babyrobot_marl.render.palette import THEMES

    steps = first_finish()
    env = race_v0.parallel_env(level=RACE_LEVEL, n_robots=4)  # the race the browser will show, played here
    obs, _ = env.reset(seed=0)
    policy = ShortestPathPolicy(env.unwrapped.table)
    for _ in range(steps):
        obs, *_ = env.step({a: policy(obs[a]) for a in env.agents})
    u, theme = env.unwrapped, THEMES["light"]
    cells, ranks = u.robot_cells, u.ranks
    (exit_cell,) = u.level.exits
    img = run_in_browser(page, screenshots, "race_canvas", [
        f"""
        from babyrobot_marl import race_v0
        from babyrobot_marl.policies import ShortestPathPolicy
        env = race_v0.parallel_env(level="{RACE_LEVEL}", n_robots=4, render_mode="human", cell_size={CELL})
        env.unwrapped.set_overlay(names=["shortest"] * 4)
        obs, infos = env.reset(seed=0)
        policy = ShortestPathPolicy(env.unwrapped.table)
        for _ in range({steps}):
            obs, *_ = env.step({{a: policy(obs[a]) for a in env.agents}})
        print("robots at", env.unwrapped.robot_cells, "ranks", env.unwrapped.ranks)
        """,
    ], ready=lambda rgb: has(cell_box(rgb, exit_cell), (240, 190, 40)))  # fmt: skip
    assert f"robots at {cells} ranks {ranks}" in page.outputs_text()
    assert_backing_store_is_twice_the_css_size(page)
    winner = ranks.index(1)
    assert cells[winner] == exit_cell
    # the finisher is drawn inside the exit cell in its finishing step, with its gold rank badge
    exit_box = cell_box(img, exit_cell)
    assert count(exit_box, theme.robots[winner]) > 50 and has(exit_box, (240, 190, 40))
    for i, cell in enumerate(cells):
        if not ranks[i] and cell != exit_cell:
            assert_robot_at(img, cell, theme.robots[i], theme)
    # the legend under the grid: a swatch (the robot icon) of every robot's colour
    legend = img[u.level.height * PX :]
    assert legend.shape[0] > 4 * 40
    for i in range(4):
        assert count(legend, theme.robots[i]) > 20, f"no legend swatch for robot {i}"


def test_canvas_redrawn_when_a_browser_reconnects(page, screenshots):
    """Reload the page: the kernel still holds the env, and the canvas (empty in a new page) must be
    drawn again (``on_client_ready``), robot included."""
    from babyrobot_marl import BabyRobotEnv
    from babyrobot_marl.render.palette import THEMES

    name = "reconnect_canvas"
    run_in_browser(page, screenshots, name, [WALK_CELL])
    page.save_and_reopen(f"{name}.ipynb", MARKER)
    env = BabyRobotEnv(level="mixed-8x8")
    env.reset(seed=0)
    for a in SINGLE_ACTIONS:
        env.step(a)
    theme = THEMES["light"]
    # the layers arrive one after the other: wait for the robot's (a drawn canvas without it fails below)
    img = page.canvas_pixels(0, ready=lambda rgba: has(cell_box(rgba[..., :3], env.robot_cell), theme.eye))
    shot(page, screenshots, f"{name}_reopened")
    assert (img[..., 3] == 255).all(), "the canvas was not drawn again after the page was reloaded"
    assert_robot_at(img[..., :3], env.robot_cell, theme.robots[0], theme)


def test_a_saved_notebook_opened_elsewhere_shows_the_picture_of_the_last_frame(lab, page, screenshots):
    """Save, shut the kernel down, and open the file as someone else would (a copy, not signed
    by this server: JupyterLab renders only safe outputs then, as for a notebook from GitHub):
    the output shows the PNG of the canvas's last frame, not the widget's text."""
    import nbformat

    name = "saved_canvas"
    run_in_browser(page, screenshots, name, [WALK_CELL])
    p = page.page
    page.save()
    lab.shutdown_kernels()
    nb = nbformat.read(lab.root_dir / f"{name}.ipynb", as_version=4)
    nb.metadata["copied_from"] = "elsewhere"  # changed outside the server: no longer signed
    nbformat.write(nb, lab.root_dir / f"{name}_copy.ipynb")
    page.log(f"{name}_copy.ipynb: opening the copy, kernel shut down")
    p.goto(lab.url(f"lab/tree/{name}_copy.ipynb"), timeout=WAIT * 1000)
    try:
        p.wait_for_function(
            "() => Array.from(document.querySelectorAll('.jp-OutputArea-output img')).some(i => i.naturalWidth > 0)",
            timeout=WAIT * 1000,
            polling=300,
        )
    finally:
        shot(page, screenshots, f"{name}_elsewhere")
    images = p.evaluate(
        "() => Array.from(document.querySelectorAll('.jp-OutputArea-output img')).map(i => [i.naturalWidth, i.naturalHeight])"
    )
    # the still of the 8x8 level's canvas, at two device pixels per CSS pixel (and the panel's strip under the grid)
    assert any(w == 2 * 8 * CELL and h > 2 * 8 * CELL for w, h in images), images
    assert "MultiCanvas(" not in page.outputs_text()
