"""The suite's own set-up: the quick loop's list of heavy files is true, and the suite prints no
spurious warning (gymnasium's "matplotlib is not installed" on a machine without a display)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import HEAVY_FILES

ROOT = Path(__file__).resolve().parents[1]


def test_every_heavy_file_exists_and_the_marker_is_registered():
    missing = [name for name in HEAVY_FILES if not (ROOT / "tests" / name).is_file()]
    assert HEAVY_FILES and missing == []
    assert "heavy:" in (ROOT / "pyproject.toml").read_text(encoding="utf-8")


def test_a_plot_before_gymnasiums_player_leaves_no_matplotlib_warning():
    pytest.importorskip("pygame", reason="gymnasium.utils.play needs pygame (the play extra); without it, it warns nothing")
    pytest.importorskip("matplotlib")
    code = ("import tests.conftest, matplotlib.pyplot as plt; plt.figure(); "
            "import gymnasium.utils.play as play; assert play.plt is not None; print(plt.get_backend())")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MPLBACKEND")}
    done = subprocess.run([sys.executable, "-W", "error::UserWarning", "-c", code], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "matplotlib is not installed" not in done.stderr, done.stderr[-2000:]
    assert done.stdout.strip().lower() == "agg"
