"""``examples/readme_pictures.py`` draws the committed README pictures again, pixel for pixel.

The script runs as ``python examples/readme_pictures.py --out DIR`` into pytest's temporary folder
(run without it, it rewrites ``docs/images``); a picture that differs means the drawing code changed:
run ``python examples/readme_pictures.py`` and commit the pictures it writes. This is the example's
run in the suite (``tests/test_examples.py`` leaves it to this file).
"""

from __future__ import annotations

import hashlib
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
IMAGES = ROOT / "docs" / "images"
PICTURES = ["race.gif", "planning.png", "action_values.png", "themes.png", "poses.png"]
GUARD = 600  # seconds: a guard against a hung script, not a speed target


def digests(folder: Path) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir())}


def test_readme_pictures_script_redraws_the_committed_pictures(tmp_path):
    iio = pytest.importorskip("imageio.v3", reason="the pictures need the video extra (imageio)")
    committed = digests(IMAGES)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "readme_pictures.py"), "--out", str(tmp_path)],
        check=True, capture_output=True, text=True, cwd=tmp_path, env=env, timeout=GUARD,
    )  # fmt: skip
    assert re.search(r"^wrote .*poses\.png", run.stdout, re.M), run.stdout[-3000:]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(PICTURES)
    assert digests(IMAGES) == committed, "--out DIR wrote into docs/images"
    for name in PICTURES:
        new, old = iio.imread(tmp_path / name), iio.imread(IMAGES / name)  # a GIF: every frame
        assert new.shape == old.shape, f"{name}: {new.shape} drawn, {old.shape} committed"
        differ = int((new != old).any(axis=-1).sum())
        assert differ == 0, f"{name}: {differ} pixels differ from docs/images/{name}; redraw: python examples/readme_pictures.py"


def test_the_gif_holds_the_colours_the_script_chose(tmp_path):
    """Given at most 256 colours, the GIF encoder keeps every pixel (its own choice of colours,
    for frames of more, could change with the Pillow version)."""
    iio = pytest.importorskip("imageio.v3", reason="the pictures need the video extra (imageio)")
    from babyrobot_marl.render.video import save_gif

    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import readme_pictures
    finally:
        sys.path.remove(str(ROOT / "examples"))
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
