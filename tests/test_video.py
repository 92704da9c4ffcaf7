"""Saving episodes to GIF and MP4 with imageio (the video extra, part of the test extra)."""

from __future__ import annotations

import numpy as np
import pytest

iio = pytest.importorskip("imageio.v3", reason="imageio is part of the test extra; CI installs it")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.envs.single import BabyRobotEnv  # noqa: E402
from babyrobot_marl.policies import make as make_policy  # noqa: E402
from babyrobot_marl.render.video import episode_frames, save_gif, save_video  # noqa: E402


def episode_frames_by_hand(n_max: int = 30) -> list[np.ndarray]:
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array", cell_size=16)
    env.reset(seed=0)
    policy = make_policy("shortest", env.table)
    frames = [env.render()]
    for _ in range(n_max):
        _, _, term, trunc, _ = env.step(policy(env.robot_cell))
        frames.append(env.render())
        if term or trunc:
            break
    return frames


def test_a_gif_holds_every_frame_of_the_episode(tmp_path):
    frames = episode_frames_by_hand()
    path = save_gif(frames, tmp_path / "ep.gif", fps=5)
    back = iio.imread(path, index=None)
    assert back.shape[0] == len(frames) and back.shape[1:3] == frames[0].shape[:2]
    # GIF quantises colours: the frames still differ where the robot moved
    assert not np.array_equal(back[0], back[-1])


def test_an_mp4_is_written_with_even_sides(tmp_path):
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg is part of the test extra; CI installs it")
    frames = [f[:-1, :-1] for f in episode_frames_by_hand(8)]  # odd sides: padded for H.264
    path = save_video(frames, tmp_path / "ep.mp4", fps=8)
    back = iio.imread(path, index=None)
    assert back.shape[0] == len(frames) and back.shape[1] % 2 == 0 and back.shape[2] % 2 == 0


@pytest.mark.parametrize(
    "frames, match",
    [
        ([], "frames"),
        ([np.zeros((4, 4), dtype=np.uint8)], "frames"),
        ([np.zeros((4, 4, 3), dtype=np.float32)], "frames"),
        ([np.zeros((4, 4, 3), dtype=np.uint8), np.zeros((6, 4, 3), dtype=np.uint8)], "frames"),
    ],
)
def test_bad_frames_are_value_errors_naming_frames(tmp_path, frames, match):
    with pytest.raises(ValueError, match=f"^{match}"):
        save_gif(frames, tmp_path / "x.gif")


@pytest.mark.parametrize("fps", [0, -1, 1000, "fast", True])
def test_bad_fps_is_a_value_error_naming_fps(tmp_path, fps):
    with pytest.raises(ValueError, match="^fps"):
        save_gif([np.zeros((4, 4, 3), dtype=np.uint8)], tmp_path / "x.gif", fps=fps)


def test_episode_frames_are_the_frames_of_the_episode_played_by_hand():
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array", cell_size=16)
    policy = make_policy("shortest", env.table)
    frames, by_hand = episode_frames(env, policy, seed=0), episode_frames_by_hand(n_max=1000)
    assert len(frames) == len(by_hand) and all((a == b).all() for a, b in zip(frames, by_hand))
    assert env.unwrapped.robot_cell in env.level.exits  # played to the end


def test_episode_frames_of_a_race_end_when_every_robot_has_finished(tmp_path):
    env = race_v0.parallel_env(level="race-4", n_robots=4, render_mode="rgb_array", cell_size=16)
    policy = make_policy("shortest", env.unwrapped.table)
    frames = episode_frames(env, policy, seed=0)
    assert not env.agents and len(frames) == env.unwrapped.elapsed_steps + 1
    again = episode_frames(env, {a: policy for a in env.possible_agents}, seed=0)
    assert len(again) == len(frames) and all((a == b).all() for a, b in zip(frames, again))
    back = iio.imread(save_gif(frames, tmp_path / "race.gif"), index=None)
    assert back.shape[0] == len(frames)


def test_episode_frames_stop_after_max_steps():
    env = BabyRobotEnv(level="maze-8x8", render_mode="rgb_array", cell_size=16)
    assert len(episode_frames(env, lambda obs: 0, seed=0, max_steps=5)) == 6  # STAY forever: cut after 5 steps


@pytest.mark.parametrize(
    "make_env, policy, name",
    [
        (lambda: BabyRobotEnv(level="maze-8x8"), lambda obs: 0, "env"),
        (lambda: BabyRobotEnv(level="maze-8x8", render_mode="ansi"), lambda obs: 0, "env"),
        (lambda: BabyRobotEnv(level="maze-8x8", render_mode="rgb_array"), "shortest", "policy"),
        (lambda: BabyRobotEnv(level="maze-8x8", render_mode="rgb_array"), {"robot_0": lambda obs: 0}, "policy"),
        (lambda: race_v0.parallel_env(n_robots=2, render_mode="rgb_array"), {"robot_0": lambda obs: 0}, "policy"),
    ],
)
def test_episode_frames_bad_arguments_are_value_errors_naming_them(make_env, policy, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        episode_frames(make_env(), policy)


def test_episode_frames_with_in_between_frames_glide_and_end_each_step_on_its_render():
    env = BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=32)
    plain = episode_frames(env, lambda obs: 2, seed=0, max_steps=2)
    smooth = episode_frames(env, lambda obs: 2, seed=0, max_steps=2, animation_frames=4)
    assert len(smooth) == 1 + 2 * 4
    assert all((a == b).all() for a, b in zip(plain, smooth[::4]))  # each step ends on its own frame
    assert not (smooth[1] == smooth[0]).all() and not (smooth[1] == smooth[4]).all()  # in between
    with pytest.raises(ValueError, match="^animation_frames"):
        episode_frames(env, lambda obs: 2, seed=0, animation_frames=-1)


def test_a_gif_shows_in_nbconvert_html_not_as_its_python_repr(tmp_path):
    """nbconvert's HTML has no image/gif renderer: ``Gif`` carries the same image as HTML too."""
    pytest.importorskip("nbconvert")
    import nbformat
    from nbconvert import HTMLExporter

    from babyrobot_marl.render.video import Gif

    path = save_gif(episode_frames(BabyRobotEnv(level="default", render_mode="rgb_array", cell_size=64),
                                   lambda obs: 3, seed=0, max_steps=3), tmp_path / "e.gif")  # fmt: skip
    nb = nbformat.v4.new_notebook()
    out = nbformat.v4.new_output("display_data", data=Gif(path)._repr_mimebundle_())
    nb.cells = [nbformat.v4.new_code_cell("Gif(path)", outputs=[out])]
    html, _ = HTMLExporter().from_notebook_node(nb)
    assert 'src="data:image/gif;base64,' in html and "IPython.core.display.Image object" not in html


@pytest.mark.parametrize("name", ['a" onerror="alert(1).gif', "<b onclick=alert(1)>x.gif", "x' src='y&amp;.gif"])
def test_a_gif_s_file_name_is_text_in_its_html_whatever_its_characters(tmp_path, name):
    """A file name with quotes or markup stays the ``alt`` text: no attribute or element of its own."""
    from html.parser import HTMLParser

    from babyrobot_marl.render.video import Gif

    path = save_gif([np.zeros((8, 8, 3), dtype=np.uint8)] * 2, tmp_path / name)
    seen: list[tuple[str, list]] = []

    class Tags(HTMLParser):
        def handle_starttag(self, tag, attrs):
            seen.append((tag, attrs))

    Tags().feed(Gif(path)._repr_mimebundle_()["text/html"])
    assert [tag for tag, _ in seen] == ["img"]
    attrs = dict(seen[0][1])
    assert sorted(attrs) == ["alt", "src"] and attrs["alt"] == name
