"""``examples/readme_pictures.py``: where it writes the README pictures, and its GIF colours.

The script itself runs in ``tests/test_clean_runs.py`` as a user runs it, in a fresh copy of the
checkout: it rewrites ``docs/images`` and must leave every picture byte for byte as committed (a
picture that differs means the drawing code changed: run ``python examples/readme_pictures.py``
and commit the pictures it writes). ``tests/test_examples.py`` leaves the example to these files.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
IMAGES = ROOT / "docs" / "images"
PICTURES = ["race.gif", "planning.png", "action_values.png", "themes.png", "poses.png"]


def readme_pictures_module():
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import readme_pictures
    finally:
        sys.path.remove(str(ROOT / "examples"))
    return readme_pictures


def test_the_script_draws_into_docs_images_or_the_folder_out_names(tmp_path, monkeypatch):
    """Where the pictures go; what they are is checked where the script runs as a user runs it, in a
    fresh copy of the checkout, redrawing ``docs/images`` byte for byte (``tests/test_clean_runs.py``)."""
    module = readme_pictures_module()
    assert module.OUT.resolve() == IMAGES.resolve()
    drawn = []

    def drawer(*names):
        def draw(out):
            drawn.append(out)
            paths = [out / n for n in names]
            for path in paths:
                path.write_bytes(b"picture")
            return paths if len(paths) > 1 else paths[0]

        return draw

    monkeypatch.setattr(module, "race_gif", drawer("race.gif"))
    monkeypatch.setattr(module, "planning_png", drawer("planning.png", "action_values.png"))
    monkeypatch.setattr(module, "themes_png", drawer("themes.png"))
    monkeypatch.setattr(module, "poses_png", drawer("poses.png"))
    module.main(["--out", str(tmp_path / "new")])
    assert drawn == [tmp_path / "new"] * 4
    assert sorted(p.name for p in (tmp_path / "new").iterdir()) == sorted(PICTURES)


def test_the_gif_holds_the_colours_the_script_chose(tmp_path):
    """Given at most 256 colours, the GIF encoder keeps every pixel (its own choice of colours,
    for frames of more, could change with the Pillow version)."""
    iio = pytest.importorskip("imageio.v3", reason="the pictures need the video extra (imageio)")
    from babyrobot_marl.render.video import save_gif

    readme_pictures = readme_pictures_module()
    y, x = np.mgrid[0:40, 0:60]
    frames = []
    for t in range(3):  # gradients (2300 colours a frame) and a block of one colour, the most common
        f = np.stack([x * 4 + t, y * 6, (x + y) * 2], axis=-1).astype(np.uint8)
        f[:10, :10] = (200, 30, 40)
        frames.append(f)
    out = readme_pictures.gif_colours(frames)
    assert len(np.unique(np.concatenate([f.reshape(-1, 3) for f in out]), axis=0)) <= 256
    assert (out[0][:10, :10] == (200, 30, 40)).all()
    decoded = iio.imread(save_gif(out, tmp_path / "g.gif", fps=12))
    assert (decoded == np.stack(out)).all()
