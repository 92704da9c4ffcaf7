"""The live canvas without a browser: the ipycanvas commands it sends, recorded on the Python side.

ipycanvas batches the commands of one ``hold_canvas()`` block into one message
(``_CANVAS_MANAGER._send_custom``); these tests record those messages. What the browser
shows for them is tests/test_browser.py's job.
"""

from __future__ import annotations

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

NAMES = {i: name for name, i in ipc.COMMANDS.items()}


@pytest.fixture
def sent(monkeypatch):
    """Every message the canvas manager sends: a list of (command names, raw commands)."""
    messages: list[list] = []

    def record(command, buffers=()):
        messages.append(command)

    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", record)
    return messages


def names(message) -> list[str]:
    """The command names of one message (a held batch is a list of commands)."""
    cmds = message if message and isinstance(message[0], list) else [message]
    return [NAMES.get(c[0], str(c[0])) for c in cmds]


def python_numbers_only(obj) -> bool:
    """No numpy scalars anywhere (without orjson they are not JSON serialisable)."""
    if isinstance(obj, (list, tuple)):
        return all(python_numbers_only(o) for o in obj)
    if isinstance(obj, dict):
        return all(python_numbers_only(v) for v in obj.values())
    return not isinstance(obj, np.generic) and (obj is None or isinstance(obj, (str, bool, numbers.Number)))


def make(animation_frames=3, level="maze-8x8") -> live.LiveCanvas:
    return live.LiveCanvas(RgbRenderer(levels.get(level), 32), animation_frames=animation_frames, fps=1e6)


def test_the_static_layer_is_drawn_once_in_one_batch(sent):
    c = make()
    assert len(sent) == 1 and "putImageData" in names(sent[0])
    c.draw([(1, 1)], animate=False)
    c.draw([(1, 2)])
    assert all("putImageData" not in names(m) for m in sent[1:])


def test_each_animation_frame_is_one_batch_that_clears_and_redraws_the_robots(sent):
    c = make(animation_frames=3)
    c.draw([(1, 1), (2, 2)], animate=False)
    sent.clear()
    c.draw([(2, 1), (2, 3)])
    assert len(sent) == 3  # three interpolated frames
    for message in sent:
        n = names(message)
        assert n.count("clear") == 1 and n.count("fillCircle") == 2


def test_animation_frames_zero_sends_one_frame_per_step(sent):
    c = make(animation_frames=0)
    sent.clear()
    for cell in [(1, 1), (2, 1), (3, 1)]:
        c.draw([cell])
    assert len(sent) == 3


def test_robots_glide_through_the_points_between_cells(sent):
    c = make(animation_frames=4)
    c.draw([(1, 1)], animate=False)
    sent.clear()
    c.draw([(3, 1)])
    xs = []
    for message in sent:
        for cmd in message:
            if NAMES[cmd[0]] == "fillCircle":
                xs.append(cmd[1][0])
    assert xs == pytest.approx([(1.5 + 0.5 * k) * 32 for k in range(1, 5)])  # a quarter of the way per frame


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
    overlay_batches = [m for m in sent if "fillPolygon" in names(m)]
    assert len(overlay_batches) == 1 and names(overlay_batches[0]).count("fillPolygon") == 64
    sent.clear()
    c.draw([(1, 2)], ov)
    assert all("fillPolygon" not in names(m) for m in sent)


def test_a_client_connecting_gets_everything_redrawn(sent):
    c = make(animation_frames=0)
    c.draw([(4, 4)], update_overlay(Overlay(), levels.get("maze-8x8"), text={(0, 0): "A"}))
    sent.clear()
    c.widget[2]._handle_frontend_event(None, {"event": "client_ready"}, [])  # what a browser sends
    all_names = [n for m in sent for n in names(m)]
    assert "putImageData" in all_names and "fillText" in all_names and "fillCircle" in all_names


def test_a_panel_makes_the_canvas_taller():
    c = make()
    h = c.widget.height
    c.draw([(1, 1)], update_overlay(Overlay(), levels.get("maze-8x8"), panel=["a", "b"]))
    assert c.widget.height == h + 2 * live.PANEL_LINE + 6


def test_human_mode_outside_jupyter_prints_the_text_frame(capsys):
    env = BabyRobotEnv(level="maze-8x8", render_mode="human")
    env.reset(seed=0)
    env.step(2)
    assert env.canvas is None
    assert "step 1" in capsys.readouterr().out


def test_human_mode_in_jupyter_shows_and_updates_a_canvas(monkeypatch, sent):
    monkeypatch.setattr(live, "notebook_available", lambda: True)
    shown = []
    monkeypatch.setattr(live.LiveCanvas, "show", lambda self: shown.append(self))
    env = BabyRobotEnv(level="maze-8x8", render_mode="human", animation_frames=0)
    env.reset(seed=0)
    assert shown and env.canvas is shown[0]
    assert env.canvas.robots == [env.robot_cell]
    env.step(3)
    assert env.canvas.robots == [env.robot_cell]
    env.set_overlay(values=np.zeros((8, 8)))
    assert env.canvas.overlay is env.overlay


def test_race_human_mode_in_jupyter_draws_every_racing_robot(monkeypatch, sent):
    monkeypatch.setattr(live, "notebook_available", lambda: True)
    monkeypatch.setattr(live.LiveCanvas, "show", lambda self: None)
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="human", animation_frames=2)
    env.reset(seed=0)
    env.step({a: 0 for a in env.agents})
    assert env.unwrapped.canvas.robots == env.unwrapped.robot_cells


def test_an_env_with_a_canvas_still_pickles_and_the_copy_has_none(monkeypatch, sent):
    import pickle

    monkeypatch.setattr(live, "notebook_available", lambda: True)
    monkeypatch.setattr(live.LiveCanvas, "show", lambda self: None)
    env = BabyRobotEnv(level="maze-8x8", render_mode="human")
    env.reset(seed=0)
    copy = pickle.loads(pickle.dumps(env))
    assert env.canvas is not None and copy.canvas is None and copy.robot_cell == env.robot_cell


def test_bad_animation_frames_is_a_value_error_naming_it():
    for bad in (-1, 61, 1.5, True, "4"):
        with pytest.raises(ValueError, match="^animation_frames"):
            BabyRobotEnv(animation_frames=bad)


# ------------------------------------------------------------------ layers, shared pixels, pacing
@pytest.fixture
def sent_images(monkeypatch):
    """The images put on the canvas, decoded: a list of (layer-less) uint8 arrays, in order."""
    from PIL import Image

    images: list[np.ndarray] = []

    def record(command, buffers=()):
        images.extend(np.array(Image.open(io.BytesIO(bytes(b)))) for b in buffers)

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


def test_tints_go_under_the_robots_and_arrows_text_and_panel_over_them(sent):
    c = make(animation_frames=0)  # its first message switches to layer 0: layer_commands follows from there
    lv = levels.get("maze-8x8")
    values, arrows = np.arange(64.0).reshape(8, 8), np.full((8, 8), 3)
    ov = update_overlay(Overlay(), lv, values=values, arrows=arrows, text={(1, 1): "A"}, panel="p")
    c.draw([(1, 1)], ov)
    where: dict[str, set[int]] = {}
    for layer, name in layer_commands(sent, c):
        where.setdefault(name, set()).add(layer)
    assert where["putImageData"] == {0} and sum(n == "putImageData" for _, n in layer_commands(sent, c)) >= 2  # level + tints
    assert where["fillCircle"] == {1}  # the robots
    assert where["fillPolygon"] == {2} and where["fillText"] == {2} and 2 in where["fillRect"]  # arrows, text, panel


def test_the_level_layer_shows_exactly_the_rgb_array_pixels_with_the_tints(sent_images):
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array", cell_size=32)
    env.reset(seed=0)
    values = np.random.default_rng(1).normal(size=(8, 8))
    values[3, 3] = np.nan
    env.set_overlay(values=values)
    c = live.LiveCanvas(env.rgb_renderer, animation_frames=0, fps=0)
    assert len(sent_images) == 1 and (sent_images[0][:, :, :3] == env.rgb_renderer.background).all()
    c.draw([], env.overlay)
    assert len(sent_images) == 2
    img = sent_images[1]
    assert img.shape[2] == 4 and (img[:, :, 3] == 255).all()  # RGBA: sent as lossless PNG, opaque
    env.set_overlay(values=values)  # the same overlay without the robot: what rgb_array shows under it
    assert (img[:, :, :3] == env.rgb_renderer.tinted(env.overlay)).all()
    nan_cell = (slice(3 * 32, 4 * 32), slice(3 * 32, 4 * 32))  # values[3, 3] is NaN: the plain level there
    assert (img[nan_cell][:, :, :3] == env.rgb_renderer.background[nan_cell]).all()
    assert not (img[:64, :64, :3] == env.rgb_renderer.background[:64, :64]).all()


def test_changing_only_arrows_or_text_does_not_resend_the_level(sent):
    c = make(animation_frames=0)
    lv = levels.get("maze-8x8")
    ov = update_overlay(Overlay(), lv, values=np.ones((8, 8)))
    c.draw([(1, 1)], ov)
    sent.clear()
    ov = update_overlay(ov, lv, arrows=np.full((8, 8), 2), text={(0, 0): "x"})
    c.set_overlay(ov)
    all_names = [n for m in sent for n in names(m)]
    assert "putImageData" not in all_names and "fillPolygon" in all_names
    assert "fillCircle" not in all_names  # the robots stay as they are
    sent.clear()
    c.set_overlay(update_overlay(ov, lv, values=np.zeros((8, 8))))
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


@pytest.mark.parametrize("frames", [0, 1, 2, 4])
def test_robot_frames_are_paced_at_fps_steps_per_second(clock, frames):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=frames, fps=4)
    c.draw([(1, 1)], animate=False)
    clock.sent_at.clear()
    for x in range(2, 6):
        c.draw([(x, 1)])
    per_step = max(1, frames)
    assert len(clock.sent_at) == 4 * per_step
    gaps = np.diff(clock.sent_at)
    assert gaps == pytest.approx(np.full(len(gaps), 0.25 / per_step))  # 4 steps a second, frames evenly spaced


def test_time_spent_between_steps_is_not_added_to_the_pace(clock):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=2, fps=4)
    c.draw([(1, 1)], animate=False)
    c.draw([(2, 1)])
    clock.now += 1.0  # the program thinks for a second
    clock.sleeps.clear()
    c.draw([(3, 1)])
    assert clock.sleeps == [pytest.approx(0.125)]  # only between this step's two frames


def test_fps_zero_never_sleeps(clock):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 32), animation_frames=3, fps=0)
    for x in range(1, 6):
        c.draw([(x, 1)])
    assert clock.sleeps == [] and len(clock.sent_at) == 1 + 1 + 4 * 3


def test_render_fps_is_the_env_own_and_reaches_the_canvas(monkeypatch, sent):
    monkeypatch.setattr(live, "notebook_available", lambda: True)
    monkeypatch.setattr(live.LiveCanvas, "show", lambda self: None)
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
