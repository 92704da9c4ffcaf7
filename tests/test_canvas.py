"""The live canvas without a browser: the ipycanvas commands it sends, recorded on the Python side.

ipycanvas batches the commands of one ``hold_canvas()`` block into one message
(``_CANVAS_MANAGER._send_custom``); these tests record those messages. What the browser
shows for them is tests/test_browser.py's job.
"""

from __future__ import annotations

import base64
import io
import numbers

import numpy as np
import pytest

pytest.importorskip("ipycanvas", reason="the notebook extra (ipycanvas) is part of the test extra; CI installs it")
import ipycanvas.canvas as ipc  # noqa: E402

from babyrobot_marl import levels, race_v0  # noqa: E402
from babyrobot_marl.envs.single import BabyRobotEnv  # noqa: E402
from babyrobot_marl.render import canvas as live  # noqa: E402
from babyrobot_marl.render.overlay import Overlay, update_overlay  # noqa: E402
from babyrobot_marl.render.rgb import RgbRenderer  # noqa: E402
from babyrobot_marl.render.scene import RobotView, Scene  # noqa: E402

NAMES = {i: name for name, i in ipc.COMMANDS.items()}


@pytest.fixture
def sent(monkeypatch):
    """Every message the canvas manager sends (a list of raw commands)."""
    messages: list[list] = []

    def record(command, buffers=()):
        messages.append(command)

    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", record)
    return messages


def names(message) -> list[str]:
    """The command names of one message (a held batch is a list of commands)."""
    cmds = message if message and isinstance(message[0], list) else [message]
    return [NAMES.get(c[0], str(c[0])) for c in cmds]


def level_sent(message) -> bool:
    """The message carries a picture of the level (as rectangles on a new canvas, else as PNG)."""
    return bool({"putImageData", "fillStyledRects"} & set(names(message)))


def python_numbers_only(obj) -> bool:
    """No numpy scalars anywhere (without orjson they are not JSON serialisable)."""
    if isinstance(obj, (list, tuple)):
        return all(python_numbers_only(o) for o in obj)
    if isinstance(obj, dict):
        return all(python_numbers_only(v) for v in obj.values())
    return not isinstance(obj, np.generic) and (obj is None or isinstance(obj, (str, bool, numbers.Number)))


def make(animation_frames=3, level="maze-8x8", cs=32, ratio=2) -> live.LiveCanvas:
    return live.LiveCanvas(RgbRenderer(levels.get(level), cs), animation_frames=animation_frames, fps=0, pixel_ratio=ratio)


def test_the_backing_store_is_twice_the_css_size_for_hidpi_screens():
    c = make(cs=40)
    assert c.widget.width == 8 * 40 * 2 and c.shown == 8 * 40 * 2 + c._reserved(Scene())
    assert c.widget.height > c.shown  # spare rows below the picture, cropped (``crop``)
    # the box: the picture's 320 CSS pixels and its 1-pixel frame on each side; the height follows the width
    assert (c.box.layout.width, c.widget.layout.height) == ("322px", "auto")
    one = make(cs=40, ratio=1)
    assert one.widget.width == 320
    with pytest.raises(ValueError, match="^pixel_ratio"):
        make(ratio=3)


def test_the_static_layer_is_drawn_once_in_one_batch(sent):
    c = make()
    assert sum(level_sent(m) for m in sent) == 1
    sent.clear()
    c.draw([(1, 1)], animate=False)
    c.draw([(1, 2)])
    assert not any(level_sent(m) for m in sent)


def test_each_animation_frame_is_one_batch_that_clears_and_redraws_every_robot_in_one_call(sent):
    c = make(animation_frames=3)
    c.draw([(1, 1), (2, 2)], animate=False)
    sent.clear()
    c.draw(Scene((RobotView(0, (2, 1), 2, "moving", (1, 1)), RobotView(1, (2, 3), 3, "moving", (2, 2)))))
    robot_batches = [m for m in sent if "fillStyledPolygons" in names(m)]
    assert len(robot_batches) == 3  # three interpolated frames
    for message in robot_batches:
        n = names(message)
        assert n.count("clear") == 1 and n.count("fillStyledPolygons") == 1
        assert n.count("fillText") == 2  # the two robots' numbers


def test_animation_frames_zero_sends_one_frame_per_step(sent):
    c = make(animation_frames=0)
    sent.clear()
    for cell in [(1, 1), (2, 1), (3, 1)]:
        c.draw([cell])
    assert sum("fillStyledPolygons" in names(m) for m in sent) == 3


def test_robots_glide_through_the_points_between_cells(monkeypatch):
    c = make(animation_frames=4)
    seen = []
    real = live.robot_sprites

    def spy(scene, cs, theme, poses=None, at=None, labelled=frozenset()):
        seen.append((dict(at or {}), dict(poses or {})))
        return real(scene, cs, theme, poses, at, labelled)

    monkeypatch.setattr(live, "robot_sprites", spy)
    c.draw(Scene((RobotView(0, (3, 1), 2, "finished", (1, 1)),)))
    xs = [at.get(0, (3.5, 1.5))[0] for at, _ in seen]  # the last frame: the robot's own placement
    assert xs == pytest.approx([(1.5 + 0.5 * k) for k in range(1, 5)])
    assert [p for _, p in seen[:-1]] == [{0: "moving"}] * 3 and seen[-1][1] == {}  # it celebrates on arrival


def test_every_argument_sent_is_a_python_number_or_string(sent):
    c = make()
    lv = levels.get("maze-8x8")
    ov = update_overlay(
        Overlay(), lv, values=np.random.default_rng(0).normal(size=(8, 8)), arrows=np.ones((8, 8), dtype=np.int64), panel="x"
    )
    c.draw([(np.int64(1), np.int64(2))], ov)
    c.draw([(2, 2)], ov)
    assert sent and all(python_numbers_only(m) for m in sent)


def test_an_overlay_is_sent_when_it_changes_and_not_again(sent):
    c = make(animation_frames=0)
    lv = levels.get("maze-8x8")
    ov = update_overlay(Overlay(), lv, arrows=np.full((8, 8), 2))
    sent.clear()
    c.draw([(1, 1)], ov)
    assert sum("putImageData" in names(m) for m in sent) == 1
    sent.clear()
    c.draw([(1, 2)], ov)
    assert all("putImageData" not in names(m) for m in sent)


def test_a_client_connecting_gets_everything_redrawn(sent):
    c = make(animation_frames=0)
    c.draw([(4, 4)], update_overlay(Overlay(), levels.get("maze-8x8"), text={(0, 0): "A"}, panel="p"))
    sent.clear()
    for layer in c.widget._canvases:  # what a browser sends, for each layer once its view is ready
        layer._handle_frontend_event(None, {"event": "client_ready"}, [])
    all_names = [n for m in sent for n in names(m)]
    assert "fillStyledRects" in all_names and "fillText" in all_names and "fillStyledPolygons" in all_names
    sent.clear()
    c.widget[1]._handle_frontend_event(None, {"event": "client_ready"}, [])  # the robots' layer alone
    assert not any(level_sent(m) for m in sent)
    assert "fillStyledPolygons" in [n for m in sent for n in names(m)]


def test_a_panel_taller_than_the_reserved_one_makes_the_canvas_taller_in_whole_css_pixels():
    c = make()
    h = c.shown
    c.draw([(1, 1)], update_overlay(Overlay(), levels.get("maze-8x8"), panel=["a", "b"]))
    assert c.shown > h and c.shown % 2 == 0
    taller = c.shown
    c.draw([(1, 1)], Overlay())  # the panel gone: the canvas keeps its height (nothing below it jumps)
    assert c.shown == taller


def test_the_canvas_keeps_a_colour_bar_height_from_the_start_so_values_do_not_make_it_grow(sent):
    c = make()
    h = c.shown
    assert h > 8 * 64  # the reserved strip under the grid
    c.draw([(1, 1)], update_overlay(Overlay(), levels.get("maze-8x8"), values=np.arange(64.0).reshape(8, 8)))
    assert c.shown == h
    assert c.picture().shape[0] == h  # the still is as tall as the canvas


def test_a_canvas_without_a_cell_size_fills_90_percent_of_the_column_with_the_pixels_for_it():
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8")), fps=0, fit=True)
    assert (c.box.layout.width, c.widget.layout.height) == ("90%", "auto")
    # no wider than its backing store's pixels (90% of a 1,032-pixel column is 929), nor than 80% of the window's height
    assert c.box.layout.max_width.startswith(f"min({c.width}px, calc(80vh * 0.") and c.width >= 929
    assert c.widget.width == 2 * c.width
    tall = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8").__class__(width=4, height=40, exits=[(0, 0)])), fps=0, fit=True)
    assert tall.grid_height <= live.FIT_HEIGHT  # capped for tall levels
    assert f"calc(80vh * {tall.hi.width / tall.shown:.4f})" in tall.css  # of the picture shown
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array")
    assert env.drawing.fit and not BabyRobotEnv(level="maze-8x8", cell_size=32).drawing.fit


def test_human_mode_outside_jupyter_prints_the_text_frame(capsys):
    env = BabyRobotEnv(level="maze-8x8", render_mode="human")
    env.reset(seed=0)
    env.step(2)
    assert env.canvas is None
    assert "step 1" in capsys.readouterr().out


class FakeHandle:
    def __init__(self):
        self.updates = []

    def update(self, data, raw=False, metadata=None):
        self.updates.append(data)


@pytest.fixture
def jupyter(monkeypatch, sent):
    """``notebook_available`` true and ``display`` recorded: the bundles shown and their updates."""
    import IPython.display

    monkeypatch.setattr(live, "notebook_available", lambda: True)
    handles: list[FakeHandle] = []
    bundles: list[dict] = []

    def display(obj, raw=False, display_id=None, metadata=None):
        bundles.append(obj)
        handles.append(FakeHandle())
        return handles[-1]

    monkeypatch.setattr(IPython.display, "display", display)
    return bundles, handles


def decode(bundle) -> np.ndarray:
    from PIL import Image

    return np.array(Image.open(io.BytesIO(base64.b64decode(bundle["image/png"]))))


def test_human_mode_in_jupyter_shows_a_canvas_and_a_still_of_its_frame_at_twice_its_css_size(jupyter):
    bundles, handles = jupyter
    env = BabyRobotEnv(level="maze-8x8", render_mode="human", animation_frames=0, render_fps=0)
    env.reset(seed=0)
    assert env.canvas is not None and len(bundles) == 2
    view, still = bundles
    assert set(view) == {"application/vnd.jupyter.widget-view+json", "text/plain"} and view["text/plain"] == ""
    assert view["application/vnd.jupyter.widget-view+json"]["model_id"] == env.canvas.view.model_id
    png = decode(still)
    assert (png == env.canvas.picture()).all() and png.shape[1] == 2 * env.canvas.width
    c = env.canvas
    assert (png[: c.hi.grid_height] == c.hi.frame(c.scene)[: c.hi.grid_height]).all()  # rgb_array's picture, at 2x
    # the HTML of the still: the same PNG, and the style that shows either it or the live canvas
    uid = c._still.uid
    assert f'class="babyrobot-still-{uid}"' in still["text/html"] and still["image/png"] in still["text/html"]
    assert f".jp-OutputArea:has(.babyrobot-live-{uid})" in still["text/html"]
    assert f"babyrobot-live-{uid}" in c.view._dom_classes
    env.step(3)
    assert [v.cell for v in env.canvas.scene.robots] == [env.robot_cell]
    env.set_overlay(values=np.zeros((8, 8)))
    assert env.canvas.overlay is env.overlay


def test_the_png_is_refreshed_when_an_episode_ends_and_when_the_env_closes(jupyter):
    _, handles = jupyter
    env = BabyRobotEnv(level="default", render_mode="human", animation_frames=0, render_fps=0)
    env.reset(seed=0)
    for a in (2, 2, 3):
        env.step(a)
    assert handles[1].updates == []
    env.step(3)  # reaches the exit
    assert len(handles[1].updates) == 1
    rgb = BabyRobotEnv(level="default", render_mode="rgb_array")
    rgb.reset(seed=0)
    for a in (2, 2, 3, 3):
        rgb.step(a)
    c = env.canvas
    hi = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=c.hi.cell_size)
    hi.reset(seed=0)
    for a in (2, 2, 3, 3):
        hi.step(a)
    shown = decode(handles[1].updates[-1])
    assert (shown[: c.hi.grid_height] == hi.render()[: c.hi.grid_height]).all()  # what rgb_array shows for the same state
    assert (c.frame() == rgb.render()).all()
    env.close()
    assert len(handles[1].updates) == 2


def test_race_human_mode_draws_every_robot_with_the_legend_and_snapshots_the_final_ranks(jupyter):
    _, handles = jupyter
    env = race_v0.parallel_env(level="race-corridor", n_robots=2, render_mode="human", animation_frames=2, render_fps=0)
    env.reset(seed=0)
    c = env.unwrapped.canvas
    assert [v.number for v in c.scene.robots] == [0, 1] and len(c.scene.legend) == 2
    rng = np.random.default_rng(0)
    while env.agents:
        env.step({a: int(rng.integers(5)) for a in env.agents})
    assert handles[1].updates  # the race's end
    final = decode(handles[1].updates[-1])
    assert final.shape[0] > c.hi.grid_height  # the legend, with the ranks


def test_an_env_with_a_canvas_still_pickles_and_the_copy_has_none(jupyter):
    import pickle

    env = BabyRobotEnv(level="maze-8x8", render_mode="human")
    env.reset(seed=0)
    copy = pickle.loads(pickle.dumps(env))
    assert env.canvas is not None and copy.canvas is None and copy.robot_cell == env.robot_cell


def test_bad_animation_frames_is_a_value_error_naming_it():
    for bad in (-1, 61, 1.5, True, "4"):
        with pytest.raises(ValueError, match="^animation_frames"):
            BabyRobotEnv(animation_frames=bad)


# ------------------------------------------------------------------ layers, shared pixels, pacing
def pictures(command, buffers) -> list[tuple[str, np.ndarray]]:
    """The pictures one message puts on a canvas, as the browser draws them: ``(how, uint8[H, W, 3 or 4])``
    for each PNG (``putImageData``) and each set of one-colour rectangles (``fillStyledRects``,
    painted here; a pixel covered twice or not at all is an error)."""
    from PIL import Image

    out, k = [], 0
    for cmd in command if command and isinstance(command[0], list) else [command]:
        n = cmd[2] if len(cmd) > 2 else 0
        bufs, k = buffers[k : k + n], k + n
        name = NAMES[cmd[0]]
        if name == "putImageData":
            out.append((name, np.array(Image.open(io.BytesIO(bytes(bufs[0]))))))
        elif name == "fillStyledRects":
            x, y, w, h, colours = (np.frombuffer(bytes(bufs[a["idx"]]), dtype=a["dtype"]).reshape(a["shape"]) for a in cmd[1][:5])
            assert cmd[1][5] == 1, "rectangles drawn opaque"
            img = np.zeros((int((y + h).max()), int((x + w).max()), 3), dtype=np.uint8)
            times = np.zeros(img.shape[:2], dtype=int)
            for a, b, ww, hh, c in zip(x, y, w, h, colours):
                img[b : b + hh, a : a + ww] = c
                times[b : b + hh, a : a + ww] += 1
            assert (times == 1).all(), "each pixel drawn by exactly one rectangle"
            out.append((name, img))
    return out


@pytest.fixture
def sent_images(monkeypatch):
    """The pictures put on the canvas, as drawn (``pictures``): a list of ``(how, image)``, in order."""
    images: list[tuple[str, np.ndarray]] = []

    def record(command, buffers=()):
        images.extend(pictures(command, buffers))

    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", record)
    return images


def layer_commands(messages, canvas: live.LiveCanvas) -> list[tuple[int, str]]:
    """(layer index, command name) of every drawing command, following ipycanvas's switchCanvas."""
    layers = {f"IPY_MODEL_{layer.model_id}": i for i, layer in enumerate(canvas.widget._canvases)}
    current, out = None, []
    for message in messages:
        for cmd in message if message and isinstance(message[0], list) else [message]:
            if NAMES[cmd[0]] == "switchCanvas":
                current = layers.get(cmd[1][0])
            else:
                out.append((current, NAMES[cmd[0]]))
    return out


def test_the_level_and_overlay_go_under_the_robots_and_labels_and_panel_over_them(sent):
    c = make(animation_frames=0)  # its first message switches to layer 0: layer_commands follows from there
    lv = levels.get("maze-8x8")
    values, arrows = np.arange(64.0).reshape(8, 8), np.full((8, 8), 3)
    ov = update_overlay(Overlay(), lv, values=values, arrows=arrows, text={(1, 1): "A"}, panel="p")
    c.draw([(1, 1)], ov)
    where: dict[str, set[int]] = {}
    for layer, name in layer_commands(sent, c):
        where.setdefault(name, set()).add(layer)
    assert where["putImageData"] == {0}  # the level with the overlay's tints, arrows and numbers
    assert where["fillStyledRects"] == {0}  # the first picture of the level: rectangles, drawn on arrival
    assert 1 in where["fillStyledPolygons"] and 2 in where["fillStyledPolygons"]  # robots; labels and panel
    assert where["fillText"] == {2}  # the labels and the panel (a lone robot shows no number)
    assert 0 not in where["fillStyledPolygons"]


def test_the_bottom_layer_shows_exactly_the_rgb_array_pixels_at_twice_the_cell_size(sent_images):
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array", cell_size=32)
    env.reset(seed=0)
    values = np.random.default_rng(1).normal(size=(8, 8))
    values[3, 3] = np.nan
    env.set_overlay(values=values)
    c = live.LiveCanvas(env.rgb_renderer, animation_frames=0, fps=0)
    hi = RgbRenderer(env.level, 64)
    # a new canvas: rectangles the browser draws as they come (a PNG decodes later: a blank first frame)
    assert sent_images[0][0] == "fillStyledRects" and (sent_images[0][1] == hi.background).all()
    c.draw([], env.overlay)
    how, img = sent_images[-1]
    assert how == "putImageData"  # on a canvas that shows the level: the browser keeps it until this is decoded
    assert img.shape[2] == 4 and (img[:, :, 3] == 255).all()  # RGBA: sent as lossless PNG, opaque
    assert (img[:, :, :3] == hi.static(env.overlay)).all()
    nan_cell = (slice(3 * 64 + 8, 4 * 64 - 8), slice(3 * 64 + 8, 4 * 64 - 8))  # values[3, 3] is NaN: the plain level there
    assert (img[nan_cell][:, :, :3] == hi.background[nan_cell]).all()


def test_a_layer_the_browser_may_show_empty_gets_its_level_as_rectangles(sent_images):
    """A new canvas, a browser's new layer (client_ready) and a resized canvas (resizing clears it)
    get the level as rectangles, exactly its pixels with the overlay; a shown one a PNG."""
    lv = levels.get("maze-8x8")
    c = make(animation_frames=0)
    hi = c.hi
    ov = update_overlay(Overlay(), lv, values=np.arange(64.0).reshape(8, 8), arrows=np.full((8, 8), 3))
    c.draw([(1, 1)], ov)
    assert [how for how, _ in sent_images] == ["fillStyledRects", "putImageData"]
    sent_images.clear()
    c.widget[0]._handle_frontend_event(None, {"event": "client_ready"}, [])
    assert [how for how, _ in sent_images] == ["fillStyledRects"]
    assert (sent_images[0][1] == hi.static(ov)).all()
    sent_images.clear()
    c.set_overlay(update_overlay(ov, lv, panel=["a line"] * 30))  # a panel taller than the spare rows
    assert [how for how, _ in sent_images] == ["fillStyledRects"] and (sent_images[0][1] == hi.static(ov)).all()


def test_a_picture_past_the_rectangle_cap_goes_as_png_over_a_coarse_copy_drawn_first(sent_images, monkeypatch):
    """Rectangles stop paying past ``MAX_RECTS``: a new or reconnected canvas then gets a coarse
    copy (at most ``COARSE_RECTS`` rectangles, covering every pixel: never a blank canvas) and the
    exact picture as PNG over it; under the cap, rectangles alone."""
    from babyrobot_marl.render import transfer

    lv = levels.get("maze-8x8")
    ov = update_overlay(Overlay(), lv, values=np.arange(64.0).reshape(8, 8), arrows=np.full((8, 8), 3))
    c = make(animation_frames=0)
    c.draw([(1, 1)], ov)
    exact = c.hi.static(ov)
    full = len(transfer.rectangles(exact)[0])
    monkeypatch.setattr(transfer, "MAX_RECTS", full - 1)
    monkeypatch.setattr(transfer, "COARSE_RECTS", 100)
    sent_images.clear()
    c.widget[0]._handle_frontend_event(None, {"event": "client_ready"}, [])  # a browser reconnects
    assert [how for how, _ in sent_images] == ["fillStyledRects", "putImageData"]
    coarse, png = sent_images[0][1], sent_images[1][1]
    assert coarse.shape == exact.shape  # every pixel covered once (``pictures`` checks), none blank
    assert (png[:, :, :3] == exact).all() and (png[:, :, 3] == 255).all()
    rects = transfer.coarse_rectangles(exact, 100)
    assert 0 < len(rects[0]) <= 100
    monkeypatch.setattr(transfer, "MAX_RECTS", full)
    sent_images.clear()
    c.redraw()
    assert [how for how, _ in sent_images][:1] == ["fillStyledRects"] and "putImageData" not in [h for h, _ in sent_images]


def test_the_rectangle_cap_is_a_few_megabytes_of_rectangles():
    from babyrobot_marl.render import transfer

    assert transfer.MAX_RECTS * 19 <= 6 << 20 and transfer.COARSE_RECTS < transfer.MAX_RECTS


def test_changing_only_the_panel_does_not_resend_the_level(sent):
    c = make(animation_frames=0)
    lv = levels.get("maze-8x8")
    ov = update_overlay(Overlay(), lv, values=np.ones((8, 8)))
    c.draw([(1, 1)], ov)
    sent.clear()
    c.set_overlay(update_overlay(ov, lv, panel="new line"))
    all_names = [n for m in sent for n in names(m)]
    assert "putImageData" not in all_names  # a taller canvas has the level again, as rectangles (it was cleared)
    sent.clear()
    c.set_overlay(update_overlay(c.overlay, lv, panel="another line"))
    assert "putImageData" not in [n for m in sent for n in names(m)]
    sent.clear()
    c.set_overlay(update_overlay(c.overlay, lv, values=np.zeros((8, 8))))
    assert "putImageData" in [n for m in sent for n in names(m)]


class FakeClock:
    """time.monotonic and time.sleep for the canvas module: sleeping advances the clock."""

    def __init__(self):
        self.now, self.sleeps, self.sent_at = 100.0, [], []

    def monotonic(self) -> float:
        return self.now

    def sleep(self, s: float) -> None:
        self.sleeps.append(s)
        self.now += s


@pytest.fixture
def clock(monkeypatch):
    fake = FakeClock()
    monkeypatch.setattr(live.time, "monotonic", fake.monotonic)
    monkeypatch.setattr(live.time, "sleep", fake.sleep)
    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", lambda command, buffers=(): fake.sent_at.append(fake.now))
    return fake


def walk(x0: int, x1: int) -> Scene:
    return Scene((RobotView(0, (x1, 1), 2, "moving", (x0, 1)),))


@pytest.mark.parametrize("frames", [0, 1, 2, 4])
def test_robot_frames_are_paced_at_fps_steps_per_second(clock, frames):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=frames, fps=4)
    c.draw([(1, 1)], animate=False)
    clock.sent_at.clear()
    for x in range(2, 6):
        c.draw(walk(x - 1, x))
    per_step = max(1, frames)
    assert len(clock.sent_at) == 4 * per_step
    gaps = np.diff(clock.sent_at)
    assert gaps == pytest.approx(np.full(len(gaps), 0.25 / per_step))  # 4 steps a second, frames evenly spaced


@pytest.mark.parametrize("frames", [0, 1, 4])
def test_the_start_of_an_episode_stays_one_frame_like_every_other(clock, frames):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=frames, fps=4)
    c.draw([(1, 1)], animate=False)  # a reset's frame
    start = clock.sent_at[-1]
    c.draw(walk(1, 2))
    assert clock.sent_at[-max(1, frames)] - start == pytest.approx(0.25 / max(1, frames))


def test_time_spent_between_steps_is_not_added_to_the_pace(clock):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=2, fps=4)
    c.draw([(1, 1)], animate=False)
    c.draw(walk(1, 2))
    clock.now += 1.0  # the program thinks for a second
    clock.sleeps.clear()
    c.draw(walk(2, 3))
    assert clock.sleeps == [pytest.approx(0.125)]  # only between this step's two frames


def test_fps_zero_never_sleeps(clock):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=3, fps=0)
    clock.sent_at.clear()
    for x in range(1, 6):
        c.draw(walk(x, x + 1))
    assert clock.sleeps == [] and len(clock.sent_at) == 5 * 3


def test_render_fps_is_the_env_own_and_reaches_the_canvas(jupyter):
    env = BabyRobotEnv(level="maze-8x8", render_mode="human", render_fps=0)
    env.reset(seed=0)
    assert env.metadata["render_fps"] == 0 and BabyRobotEnv.metadata["render_fps"] == 4
    assert env.canvas.fps == 0
    race = race_v0.parallel_env(level="race-4", n_robots=2, render_mode="human", render_fps=12.5)
    race.reset(seed=0)
    assert race.unwrapped.canvas.fps == 12.5 and type(race.unwrapped).metadata["render_fps"] == 4


@pytest.mark.parametrize("bad", [-1, float("inf"), float("nan"), "fast", True])
def test_bad_render_fps_is_a_value_error_naming_it(bad):
    with pytest.raises(ValueError, match="^render_fps"):
        BabyRobotEnv(render_fps=bad)
    with pytest.raises(ValueError, match="^render_fps"):
        race_v0.parallel_env(render_fps=bad)


def test_jupyter_is_an_ipython_shell_with_a_kernel(monkeypatch):
    import IPython

    class Shell:
        kernel = None

    monkeypatch.setattr(IPython, "get_ipython", lambda: None)
    assert not live.notebook_available()  # plain Python
    monkeypatch.setattr(IPython, "get_ipython", lambda: Shell())
    assert not live.notebook_available()  # terminal IPython: no kernel
    Shell.kernel = object()
    assert live.notebook_available()  # a Jupyter kernel, ipycanvas installed


def test_the_canvas_legend_stops_growing_past_eight_robots_and_an_oversized_panel_is_refused_before_drawing():
    from babyrobot_marl.render.panel import LegendRow

    c = make(cs=32)

    def legend(n: int) -> Scene:
        return Scene(tuple(RobotView(i, (i % 8, i // 8 % 8)) for i in range(n)),
                     legend=tuple(LegendRow(i, "", -1.0, 0, True) for i in range(n)))  # fmt: skip

    c.draw(legend(8), animate=False)
    eight = c.widget.height
    c.draw(legend(30), animate=False)
    c.draw(legend(300), animate=False)
    assert c.widget.height == eight  # the canvas never shrinks: the notebook below does not jump
    # past eight robots the legend is compact: shorter than eight rows, and it stops growing
    rows = [c.renderer.frame(legend(n)).shape[0] for n in (8, 30, 300)]
    assert rows[2] == rows[1] < rows[0] and c.frame().shape[0] == rows[2]
    sent_before, overlay = c.frames_sent, c.overlay
    huge = update_overlay(Overlay(), levels.get("maze-8x8"), panel=["l"] * 20_000)
    with pytest.raises(ValueError, match=r"^panel: 20,000 lines"):
        c.draw(legend(3), huge)
    assert c.frames_sent == sent_before and c.overlay is overlay  # nothing drawn, nothing changed


def test_the_race_legend_changes_with_the_frame_that_shows_the_robots_where_they_end(jupyter):
    """The legend (a rank, a return) is of the step the robots finish moving in: drawn after
    the step's last in-between frame, never before its first."""
    env = race_v0.parallel_env(level="race-corridor", n_robots=2, render_mode="human", animation_frames=3, render_fps=0)
    env.reset(seed=0)
    c = env.unwrapped.canvas
    calls: list[tuple] = []
    draw_robots, draw_top = c._draw_robots, c._draw_top
    c._draw_robots = lambda scene, at=None, poses=None: (calls.append(("robots", at)), draw_robots(scene, at, poses))[1]
    c._draw_top = lambda scene=None, force=False: (calls.append(("legend", (scene or c.scene).legend)), draw_top(scene, force))[1]
    env.step({a: 2 for a in env.agents})  # both robots move east: three in-between frames
    kinds = [k for k, _ in calls]
    assert kinds.count("robots") == 3 and kinds[-1] == "legend", kinds
    assert calls[-1][1] == c.scene.legend


def test_after_an_episode_the_replay_bar_shows_its_scenes_on_the_same_canvas_without_stepping(jupyter, sent):
    env = race_v0.parallel_env(level="race-corridor", n_robots=2, render_mode="human", animation_frames=0, render_fps=0)
    env.reset(seed=0)
    c = env.unwrapped.canvas
    bar = c._replay
    assert bar.widget.layout.display == "none"  # nothing to replay during the race
    rng = np.random.default_rng(0)
    scenes = [c.scene]
    while env.agents:
        env.step({a: int(rng.integers(5)) for a in env.agents})
        scenes.append(c.scene)
    assert bar.widget.layout.display == "flex" and bar.slider.max == len(c.history) - 1 == bar.play.max
    assert [s for s, _ in c.history] == [s for k, s in enumerate(scenes) if k == 0 or s != scenes[k - 1]]
    final, t = c.scene, env.unwrapped._t
    sent.clear()
    bar.slider.value = 0  # the slider (the play button moves it in the browser) draws the start again
    assert sent and any("fillStyledPolygons" in names(m) for m in sent)
    assert env.unwrapped._t == t and c.scene is final  # the env was not stepped; the live scene is kept
    drawn = []
    c._draw_robots = lambda scene, at=None, poses=None: drawn.append(scene)
    bar.slider.value = 1
    assert drawn == [c.history[1][0]]
    env.reset(seed=1)  # a new episode: the bar goes until it ends
    assert bar.widget.layout.display == "none" and len(c.history) == 1


def test_a_browser_redraw_after_a_replay_shows_the_replayed_scene_not_the_live_one(jupyter, sent):
    """A browser's ``client_ready`` (and the redraw a moment after it) may come after the learner moved
    the replay slider: the canvas is drawn again as shown, the replayed scene, until the env draws anew."""
    env = race_v0.parallel_env(level="race-corridor", n_robots=2, render_mode="human", animation_frames=0, render_fps=0)
    env.reset(seed=0)
    c = env.unwrapped.canvas
    while env.agents:
        env.step({a: 2 for a in env.agents})
    c._replay.slider.value = 0
    drawn, tops = [], []
    draw_robots, draw_top = c._draw_robots, c._draw_top
    c._draw_robots = lambda scene, at=None, poses=None: (drawn.append(scene), draw_robots(scene, at, poses))[1]
    c._draw_top = lambda scene=None, force=False: (tops.append(scene or c.scene), draw_top(scene, force))[1]
    c.redraw()
    for layer in c.widget._canvases:
        layer._handle_frontend_event(None, {"event": "client_ready"}, [])
    start = c.history[0][0]
    assert start != c.scene and drawn == [start, start] and tops == [start, start]
    drawn.clear()
    env.reset(seed=1)  # a new episode: live again
    c.redraw()
    assert drawn[-1] == c.scene


def test_when_sending_a_frame_takes_longer_than_its_share_in_between_frames_are_dropped_never_the_last(clock, monkeypatch):
    """A slow browser or a busy machine: each frame takes 0.2 s to send against 62.5 ms planned.
    The canvas keeps to the clock: in-between frames are dropped, each step still ends on its
    last frame (the robot where it is), the glide never goes back, and nothing blank is sent."""
    fractions: list[float] = []
    real_glide = live.glide

    def spy(scene, t, *args):
        fractions.append(t)
        return real_glide(scene, t, *args)

    def slow(command, buffers=()):
        clock.sent_at.append(clock.now)
        clock.now += 0.2

    monkeypatch.setattr(live, "glide", spy)
    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", slow)
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=4, fps=4)
    c.draw([(1, 1)], animate=False)
    for x in range(2, 6):
        fractions.clear()
        c.draw(walk(x - 1, x))
        drawn = fractions[1:]  # (the first call asks whether anyone moved)
        assert drawn[-1] == 1.0 and len(drawn) < 4  # frames dropped, never the last
        assert drawn == sorted(drawn)
    assert c.pacer.dropped > 0 and c.scene == walk(4, 5)


def test_the_canvas_is_framed_in_the_pages_border_colour():
    """On a dark notebook page a light canvas's dark outer wall merged into the page: the canvas's box
    has a frame in the page's own border colour (a JupyterLab variable, with a grey for other pages)."""
    for fit in (False, True):
        c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), fps=0, pixel_ratio=2, fit=fit)
        assert c.box.layout.border == "1px solid var(--jp-border-color1, #9e9e9e)" and c.box.layout.overflow == "hidden"
