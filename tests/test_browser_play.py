"""Real-browser tests of the notebook player and level editor: JupyterLab + headless Chromium (Playwright).

Reuses the harness of ``tests/test_browser.py`` (the session's JupyterLab and Chromium, from
``tests/browser/fixtures.py``; they skip without Chromium locally and fail with ``CI=true``).
The tests click the widgets' buttons, focus the canvas and press keys as a learner would, then check
the robots where the same game, replayed here, puts them: in the panel the notebook shows and in the
canvas pixels (drawn by the same renderer).
"""

from __future__ import annotations

import numpy as np

from babyrobot_marl.core.actions import Action
from babyrobot_marl.play.notebook import make_game
from babyrobot_marl.render.palette import THEMES
from babyrobot_marl.render.rgb import RgbRenderer
from tests.browser.chrome import WAIT
from tests.test_browser import CELL, MARKER, PX, assert_robot_at, cell_box, has, shot

WAIT_MS = WAIT * 1000  # a guard against a dead kernel, not a speed target


def open_notebook(page, name: str, cells: list[str]) -> None:
    from tests.browser.notebook_files import write_notebook

    write_notebook(page.lab.root_dir / f"{name}.ipynb", [*cells, f"print({MARKER!r})"])
    page.run_all(f"{name}.ipynb", MARKER)


def panel_text(page) -> str:
    return page.page.locator(".babyrobot-panel").first.inner_text()


def wait_panel(page, text: str) -> str:
    """Wait until the panel (the kernel's answer to the last click or key) shows ``text``."""
    try:
        page.page.wait_for_function(
            "(t) => { const p = document.querySelector('.babyrobot-panel'); return !!p && p.innerText.includes(t); }",
            arg=text, timeout=WAIT_MS, polling=100,
        )  # fmt: skip
    except Exception as e:
        raise AssertionError(f"the panel never showed {text!r}; it shows:\n{panel_text(page)}") from e
    return panel_text(page)


def where_text(game) -> str:
    """The panel's lines saying where the robots are, for ``game`` (the same game replayed here)."""
    from babyrobot_marl.play.notebook import where

    return "\n".join(where(game))


def assert_robot_pixels(img: np.ndarray, level, robots) -> None:
    """Baby Robot (body, eye, visor) in each robot's cell; in every other cell no robot, and an empty
    floor cell exactly as ``rgb_array`` draws it (the canvas holds two device pixels per CSS pixel)."""
    theme = THEMES["light"]
    for i, cell in enumerate(robots):
        if cell is not None:
            assert_robot_at(img, cell, theme.robots[i], theme)
    others = [(x, y) for y in range(level.height) for x in range(level.width) if (x, y) not in robots]
    for cell in others:
        assert not has(cell_box(img, cell), theme.eye), f"a robot drawn in {cell}"
    marked = {*level.starts, *level.exits, *level.small_puddles, *level.large_puddles, *level.blocked}
    empty = next(c for c in others if c not in marked)
    assert (cell_box(img, empty) == cell_box(RgbRenderer(level, PX).background, empty)).all(), f"cell {empty} differs"


def test_player_buttons_and_keys_move_the_robot_where_the_game_predicts(page, screenshots):
    open_notebook(page, "play_single", [
        f"""
        from babyrobot_marl.play import notebook
        player = notebook.play("walls", seed=0, cell_size={CELL})
        player
        """,
    ])  # fmt: skip
    p = page.page
    assert "step 0/" in wait_panel(page, "Baby Robot is at column 0, row 0")
    p.locator(".babyrobot-east").first.click()
    wait_panel(page, "step 1/")
    p.locator(".babyrobot-east").first.click()
    wait_panel(page, "step 2/")
    canvas = p.locator(".jp-OutputArea-output canvas").first
    canvas.click(position={"x": 5, "y": 5})  # the focus: keys now go to the game
    outline = p.evaluate("""() => { const k = document.querySelector('.babyrobot-player .babyrobot-keys');
      return [k, k.querySelector('canvas')].filter(e => e).map(e => getComputedStyle(e).outlineStyle); }""")
    assert "solid" in outline, f"no focus frame on the canvas with the keys: {outline}"  # issue 26: a visible focus
    assert_framed_on_four_sides(p, canvas)
    for k, key in enumerate(["ArrowDown", "s", "x", " "]):
        p.keyboard.press(key)
        wait_panel(page, "that key does nothing" if key == "x" else f"step {3 + k - (key == ' ')}/")
    game = make_game("walls", seed=0)
    for a in (Action.EAST, Action.EAST, Action.SOUTH, Action.SOUTH, Action.STAY):
        game.act(a)
    text = wait_panel(page, where_text(game))
    assert f"step 5/{game.env.max_steps}  return {game.ret:g}  last: STAY -> stayed" in text
    img = page.canvas_pixels(0)[..., :3]
    shot(page, screenshots, "play_single")
    assert_robot_pixels(img, game.env.level, game.robots)
    p.keyboard.press("r")  # restart: back at the start
    wait_panel(page, "Baby Robot is at column 0, row 0")
    assert "step 0/" in panel_text(page)


def test_race_tab_hands_the_keys_to_the_next_robot(page, screenshots):
    open_notebook(page, "play_race", [
        f"""
        from babyrobot_marl.play import notebook
        race = notebook.play("race-4", policies="shortest", seed=0, cell_size={CELL})
        race
        """,
    ])  # fmt: skip
    p = page.page
    wait_panel(page, "you drive #0 (robot_0)")
    p.locator(".jp-OutputArea-output canvas").first.click(position={"x": 5, "y": 5})
    game = make_game("race-4", policies="shortest", seed=0)
    game.labels = lambda i: f"#{i}"  # as the player numbers them
    for key in ["ArrowRight", "Tab", " ", "ArrowDown"]:
        p.keyboard.press(key)
        game.command({"ArrowRight": Action.EAST, "Tab": "switch", " ": Action.STAY, "ArrowDown": Action.SOUTH}[key])
        wait_panel(page, where_text(game))
    text = wait_panel(page, "you drive #1 (robot_1)")
    assert f"step {game.steps}/" in text
    img = page.canvas_pixels(0)[..., :3]
    shot(page, screenshots, "play_race")
    assert_robot_pixels(img, game.env.level, game.robots)


def test_editor_builds_a_level_by_clicks_and_plays_it(page, screenshots):
    cs = 40
    open_notebook(page, "edit_level", [
        f"""
        from babyrobot_marl.play import notebook
        editor = notebook.edit((3, 2), cell_size={cs})
        editor
        """,
    ])  # fmt: skip
    p = page.page
    canvas = p.locator(".jp-OutputArea-output canvas").first
    box = canvas.bounding_box()
    scale = box["width"] / (3 * cs)  # CSS pixels per canvas pixel

    def click(x: float, y: float, then: str) -> None:
        canvas.click(position={"x": x * scale, "y": y * scale})
        p.wait_for_function(
            "(t) => document.querySelector('.babyrobot-level-text').innerText.includes(t)", arg=then, timeout=WAIT_MS
        )

    def row(i: int) -> str:
        return p.locator(".babyrobot-level-text").inner_text().splitlines()[i]

    click(100, 20, "|S   p|")  # cell (2, 0): floor -> small puddle
    click(60, 60, "|  p E|")  # cell (1, 1): floor -> small puddle
    click(78, 60, "|  p|E|")  # the line between (1, 1) and (2, 1): a wall
    click(100, 38, "+ + +-+")  # the line under (2, 0): a wall, the exit is walled in
    assert row(3) == "|  p|E|"
    verdict = p.locator(".babyrobot-verdict").inner_text()
    assert "the start (column 0, row 0) cannot reach an exit" in verdict and "line 2" not in verdict
    assert p.locator(".babyrobot-play-it button, button.babyrobot-play-it").first.is_disabled()
    click(100, 38, "+ + +*+")  # wall -> glass: the exit can be reached again
    p.wait_for_function("() => document.querySelector('.babyrobot-verdict').innerText.includes('ok: a 3x2 level')",
                        timeout=WAIT_MS)  # fmt: skip
    text = p.locator(".babyrobot-level-text").inner_text().strip()
    assert text == "+-+-+-+\n|S   p|\n+ + +*+\n|  p|E|\n+-+-+-+"
    p.locator(".babyrobot-play-it").first.click()
    wait_panel(page, "Baby Robot is at column 0, row 0")
    shot(page, screenshots, "edit_level")


def assert_framed_on_four_sides(p, element) -> None:
    """The focus frame is seen on all four sides of ``element`` (on the page, as painted: an outline
    outside the element is cut off where a parent clips its content)."""
    import io

    from PIL import Image

    from babyrobot_marl.play.notebook import FOCUS

    box = element.bounding_box()
    pad = 8
    clip = {"x": max(0, box["x"] - pad), "y": max(0, box["y"] - pad), "width": box["width"] + 2 * pad,
            "height": box["height"] + 2 * pad}  # fmt: skip
    img = np.asarray(Image.open(io.BytesIO(p.screenshot(clip=clip))).convert("RGB")).astype(int)
    rgb = np.array([int(FOCUS[k : k + 2], 16) for k in (1, 3, 5)])
    blue = (np.abs(img - rgb).sum(axis=2) < 30)
    h, w = blue.shape
    rows, cols = blue.any(axis=1), blue.any(axis=0)
    sides = {"top": blue[: h // 4].any(axis=0).mean(), "bottom": blue[3 * h // 4 :].any(axis=0).mean(),
             "left": blue[:, : w // 4].any(axis=1).mean(), "right": blue[:, 3 * w // 4 :].any(axis=1).mean()}  # fmt: skip
    assert rows.any() and cols.any(), "no focus frame seen"
    assert all(share > 0.8 for share in sides.values()), f"the focus frame's sides (share of their length seen): {sides}"
