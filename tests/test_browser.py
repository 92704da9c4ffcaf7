"""Real-browser test: JupyterLab + headless Chromium (Playwright) run notebooks and we read the canvas pixels.

Needs the system Chromium (``apt-get install chromium fonts-liberation``, done by ``.ci/browser.sh``)
and the ``test`` extra (jupyterlab, playwright, ipycanvas). Locally the tests skip when Chromium is
absent; with ``CI=true`` a missing browser fails them. Screenshots go to ``$BABYROBOT_SCREENSHOTS``
(default: ``<tmp>/babyrobot_marl_screenshots``) and their paths are printed.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import pytest

from tests.browser.chrome import chromium_path
from tests.browser.lab import LabServer, processes_mentioning
from tests.browser.notebook_files import write_notebook

ROOT = Path(__file__).resolve().parents[1]
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")
MARKER = "BROWSER-TEST-DONE"
SCREENSHOTS = Path(os.environ.get("BABYROBOT_SCREENSHOTS", Path(tempfile.gettempdir()) / "babyrobot_marl_screenshots"))


def _unavailable() -> str | None:
    if chromium_path() is None:
        return "Chromium not installed (apt-get install chromium fonts-liberation; .ci/browser.sh does it in CI)"
    for module in ("playwright", "jupyterlab", "ipycanvas"):
        try:
            __import__(module)
        except ImportError:
            return f"{module} not installed (pip install -e '.[test]')"
    return None


@pytest.fixture(scope="module")
def browser_ready():
    reason = _unavailable()
    if reason is not None:
        if IN_CI:
            pytest.fail(f"CI=true and the browser test cannot run: {reason}")
        pytest.skip(reason)


@pytest.fixture(scope="module")
def lab(browser_ready, tmp_path_factory):

    root, work = tmp_path_factory.mktemp("lab_root"), tmp_path_factory.mktemp("lab_work")
    with LabServer(root, work, pythonpath=ROOT) as server:
        yield server
    left = processes_mentioning(str(root)) + processes_mentioning(str(work))  # the server and its kernels
    assert not left, f"processes left behind by JupyterLab: {left}"


@pytest.fixture(scope="module")
def page(lab, tmp_path_factory):
    from tests.browser.chrome import NotebookPage

    profile = tmp_path_factory.mktemp("chromium_profile")
    with NotebookPage(lab, profile, chromium_path()) as nb:
        yield nb
    left = processes_mentioning(str(profile))
    assert not left, f"Chromium processes left behind: {left}"


def run_in_browser(lab, page, name: str, cells: list[str], capsys) -> np.ndarray:
    """Write ``name``.ipynb into the server root, run it in the browser, screenshot it, return canvas 0 (RGB)."""
    write_notebook(lab.root_dir / f"{name}.ipynb", [*cells, f"print({MARKER!r})"])
    try:
        page.run_all(f"{name}.ipynb", MARKER)
        pixels = page.canvas_pixels(0)
    finally:
        shot = page.screenshot(SCREENSHOTS / f"{name}.png")
        with capsys.disabled():
            print(f"\nscreenshot: {shot}")
    assert (pixels[..., 3] == 255).all(), "the canvas has transparent pixels: something was not drawn"
    return pixels[..., :3]


def test_plain_ipycanvas_pixels(lab, page, capsys):
    """The harness itself: a canvas drawn with plain ipycanvas reads back with the colours drawn."""
    img = run_in_browser(lab, page, "plain_ipycanvas", [
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
    ], capsys)  # fmt: skip
    assert img.shape == (60, 120, 3)
    assert tuple(img[30, 30]) == (0xDC, 0x3C, 0x32)
    assert tuple(img[30, 90]) == (0x32, 0x5A, 0xD2)
