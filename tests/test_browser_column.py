"""Real-browser test: in a narrow window (760 pixels) no canvas runs past its notebook column; a
canvas with a fixed cell size scales down whole (its height with its width), its backing store
keeping every pixel. Harness: tests/browser."""

from __future__ import annotations

from tests.test_browser import MARKER, shot

CELLS = [
    """
    from babyrobot_marl import BabyRobotEnv
    from babyrobot_marl.play import notebook
    env = BabyRobotEnv(level="mixed-8x8", render_mode="human", animation_frames=0, cell_size=64)
    env.reset(seed=0)
    env.step(2)
    """,
    """
    wide = BabyRobotEnv(level="mixed-8x8", render_mode="human", animation_frames=0, cell_size=72)
    wide.reset(seed=0)
    """,
    """
    editor = notebook.edit("walls", cell_size=64)
    editor
    """,
]

# every visible canvas of the outputs: its box, its backing store, its output column's right edge
_CANVASES = """() => Array.from(document.querySelectorAll('.jp-OutputArea-output canvas'))
  .filter(c => c.width > 0 && c.offsetParent !== null).map(c => {
    const r = c.getBoundingClientRect(), col = c.closest('.jp-OutputArea-output').getBoundingClientRect();
    return {width: c.width, height: c.height, css_width: r.width, css_height: r.height, right: r.right,
            column_right: col.right};
  })"""


def test_in_a_narrow_window_every_canvas_fits_its_column_scaled_down_whole(page, screenshots):
    from tests.browser.notebook_files import write_notebook

    name = "narrow_column"
    page.page.set_viewport_size({"width": 760, "height": 1400})
    try:
        write_notebook(page.lab.root_dir / f"{name}.ipynb", [*CELLS, f"print({MARKER!r})"])
        page.run_all(f"{name}.ipynb", MARKER)
        page.canvas_pixels(0)
        page.page.wait_for_function(f"() => ({_CANVASES})().length >= 3", timeout=300_000)
        canvases = page.page.evaluate(_CANVASES)
    finally:
        shot(page, screenshots, name)
        page.page.set_viewport_size({"width": page.viewport[0], "height": page.viewport[1]})
    page.log(f"canvases in a 760-pixel window: {canvases}")
    widths = {c["width"] for c in canvases}
    assert {2 * 8 * 64, 2 * 8 * 72} <= widths, canvases  # both envs' canvases, at their full resolution
    for c in canvases:
        assert c["right"] <= c["column_right"] + 1, c  # nothing cut off at the right
        # scaled down whole: the CSS box keeps the backing store's shape
        assert abs(c["css_height"] / c["css_width"] - c["height"] / c["width"]) < 0.02, c
    assert any(c["css_width"] < c["width"] / 2 - 1 for c in canvases), canvases  # the window did make one scale down
