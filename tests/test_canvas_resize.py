"""A canvas that grows (its panel gains a line mid-episode) is cleared by the browser: the resize
is followed by one message that draws every layer again, the level's picture included, so no
frame shows the canvas without the level. Recorded on the Python side (see test_canvas.py)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("ipycanvas")

import ipycanvas.canvas as ipc  # noqa: E402

from babyrobot_marl import levels  # noqa: E402
from babyrobot_marl.render import canvas as live  # noqa: E402
from babyrobot_marl.render.overlay import Overlay, update_overlay  # noqa: E402
from babyrobot_marl.render.rgb import RgbRenderer  # noqa: E402
from tests.test_canvas import NAMES  # noqa: E402


def test_a_resize_is_followed_by_one_message_drawing_every_layer(monkeypatch):
    level = levels.get("mixed-8x8")
    c = live.LiveCanvas(RgbRenderer(level, 32), animation_frames=2, fps=0)
    layers = {f"IPY_MODEL_{layer.model_id}": i for i, layer in enumerate(c.widget._canvases)}
    events: list = []

    def record(command, buffers=()):
        current, touched = None, set()
        for cmd in command if command and isinstance(command[0], list) else [command]:
            if NAMES[cmd[0]] == "switchCanvas":
                current = layers.get(cmd[1][0])
            elif NAMES[cmd[0]] in ("fillStyledRects", "putImageData"):
                touched.add((current, "picture"))
            else:
                touched.add((current, "draw"))
        events.append(("message", touched))

    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", record)
    c.widget._canvases[0].observe(lambda change: events.append(("resize", change["new"])), names="height")
    c.draw([(0, 0)])
    c.draw([(1, 0)], update_overlay(Overlay(), level, panel=["step 1  return -1"]))
    before = c.widget.height
    c.draw([(2, 0)], update_overlay(Overlay(), level, panel=["step 2  return -2", "moved"] + ["a line"] * 20))  # past the spare
    assert c.widget.height > before  # the panel grew: the canvas did
    at = [k for k, e in enumerate(events) if e[0] == "resize"]
    assert len(at) == 1
    after = events[at[0] + 1 :]
    first = after[0]
    assert first[0] == "message"
    assert (0, "picture") in first[1] and any(layer == 1 for layer, _ in first[1]) and any(layer == 2 for layer, _ in first[1])
    assert not any(e[0] == "resize" for e in after)


def test_the_shown_canvas_is_resized_after_its_layers_are_drawn_at_the_new_height_and_composed_again(monkeypatch):
    """The page shows the ``MultiCanvas``'s own canvas: it is resized (and cleared by the browser)
    only once every layer has its picture at the new height, and a batch of commands follows at
    once (the browser composes the layers into it after each batch)."""
    level = levels.get("mixed-8x8")
    c = live.LiveCanvas(RgbRenderer(level, 32), animation_frames=0, fps=0)
    events: list = []
    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", lambda command, buffers=(): events.append("message"))
    c.widget.observe(lambda change: events.append("shown resized"), names="height")
    for k, layer in enumerate(c.widget._canvases):
        layer.observe(lambda change, k=k: events.append(f"layer {k} resized"), names="height")
    c.draw([(0, 0)])
    c.draw([(1, 0)], update_overlay(Overlay(), level, panel=["one", "two", "three", "four", "five"] * 4))
    assert events.count("shown resized") == 1
    at = events.index("shown resized")
    assert {"layer 0 resized", "layer 1 resized", "layer 2 resized"} <= set(events[:at])
    assert events[at - 1] == "message"  # the layers drawn at the new height before
    assert events[at + 1 : at + 2] == ["message"]  # and composed again right after


def test_an_episode_whose_panel_shows_two_lines_after_its_first_step_keeps_its_height():
    """Quickstart's loop: a step's line and its outcome from the first step on. The panel has room
    for them from the start: the canvas does not grow mid-episode."""
    level = levels.get("mixed-8x8")
    c = live.LiveCanvas(RgbRenderer(level, 32), animation_frames=0, fps=0)
    c.draw([(0, 0)])
    h = c.shown
    for t, cell in enumerate([(1, 0), (2, 0), (2, 1)], start=1):
        c.draw([cell], update_overlay(c.overlay, level, panel=[f"step {t}  return {-t}", "moved"]))
        assert c.shown == h


def test_an_episode_that_starts_with_panel_lines_has_room_for_values_under_them_too():
    level = levels.get("mixed-8x8")
    c = live.LiveCanvas(RgbRenderer(level, 32), animation_frames=0, fps=0)
    c.draw([(0, 0)])
    c.draw([(1, 0)], update_overlay(c.overlay, level, panel=["a", "b", "c", "d"]))
    c.new_episode()  # the overlay's four lines stay: the episode starts with them
    c.draw([(0, 0)], animate=False)
    h = c.shown
    c.draw([(1, 0)], update_overlay(c.overlay, level, values=np.arange(64.0).reshape(8, 8)))
    assert c.shown == h


def test_a_panel_growing_into_the_spare_rows_resizes_nothing_and_is_drawn_before_it_shows(monkeypatch):
    """The backing store keeps rows below the picture (``crop``): a panel that grows into them is
    drawn there, then shown by a change of CSS; no canvas is resized (the browser clears those)."""
    level = levels.get("mixed-8x8")
    c = live.LiveCanvas(RgbRenderer(level, 32), animation_frames=0, fps=0)
    events: list = []
    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", lambda command, buffers=(): events.append("message"))
    for w in (c.widget, *c.widget._canvases):
        w.observe(lambda change: events.append("resized"), names="height")
    c.widget.layout.observe(lambda change: events.append("cropped"), names="margin")
    c.draw([(0, 0)])
    start = c.shown
    for t in range(1, 9):  # a line more at every step
        events.clear()
        shown = c.shown
        c.draw([(t % 8, 0)], update_overlay(c.overlay, level, panel=[f"step {t}"] + ["moved"] * t))
        assert "resized" not in events
        if c.shown > shown:
            at = events.index("cropped")
            assert "message" in events[:at]  # the panel drawn before its rows show
    assert c.shown > start
    assert c.picture().shape[0] == c.shown  # the still: the picture shown
