"""Fixtures of the real-browser tests (imported by ``tests/conftest.py``, so one JupyterLab server and
one Chromium serve every browser test of the session).

They say what they are doing on the terminal as they go, also under ``pytest -q`` with output
captured: a browser test takes seconds on an idle machine and minutes on a loaded one, and a run
should not sit silent meanwhile.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from tests.browser.chrome import chromium_path
from tests.browser.lab import LabServer, processes_mentioning

ROOT = Path(__file__).resolve().parents[2]
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")


def unavailable() -> str | None:
    """Why the browser tests cannot run here, or None."""
    if chromium_path() is None:
        return "Chromium not installed (apt-get install chromium fonts-liberation; .ci/browser.sh does it in CI)"
    for module in ("playwright", "jupyterlab", "ipycanvas", "nbformat"):
        try:
            __import__(module)
        except ImportError:
            return f"{module} not installed (pip install -e '.[test]')"
    return None


def terminal_writer(config: pytest.Config, prefix: str) -> Callable[[str], None]:
    """A function printing ``prefix [elapsed] message`` lines on the terminal at once, past pytest's
    output capturing (as pytest prints its own progress)."""
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    capture = config.pluginmanager.get_plugin("capturemanager")
    start = time.monotonic()

    def say(message: str) -> None:
        line = f"{prefix} [{time.monotonic() - start:5.0f} s] {message}"
        if reporter is None:  # -p no:terminal
            return
        with capture.global_and_fixture_disabled() if capture is not None else contextlib.nullcontext():
            if getattr(reporter._tw, "width_of_current_line", 0):  # after -q's dots: a line of its own
                reporter.write("\n")
            reporter.write_line(line)

    return say


@pytest.fixture(scope="session")
def browser_log(pytestconfig: pytest.Config) -> Callable[[str], None]:
    return terminal_writer(pytestconfig, "browser")


@pytest.fixture(scope="session")
def browser_ready() -> None:
    reason = unavailable()
    if reason is not None:
        if IN_CI:
            pytest.fail(f"CI=true and the browser test cannot run: {reason}")
        pytest.skip(reason)


@pytest.fixture(scope="session")
def screenshots(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where the browser tests save screenshots: ``$BABYROBOT_SCREENSHOTS``, else pytest's temporary folder."""
    chosen = os.environ.get("BABYROBOT_SCREENSHOTS")
    return Path(chosen) if chosen else tmp_path_factory.mktemp("screenshots")


@pytest.fixture(scope="session")
def lab(browser_ready, tmp_path_factory, browser_log) -> Iterator[LabServer]:
    root, work = tmp_path_factory.mktemp("lab_root"), tmp_path_factory.mktemp("lab_work")
    browser_log("starting JupyterLab")
    with LabServer(root, work, pythonpath=ROOT) as server:
        browser_log(f"JupyterLab answers at {server.base}")
        yield server
        browser_log("stopping JupyterLab")
    left = processes_mentioning(str(root)) + processes_mentioning(str(work))  # the server and its kernels
    assert not left, f"processes left behind by JupyterLab: {left}"


@pytest.fixture(scope="session")
def page(lab, tmp_path_factory, browser_log):
    from tests.browser.chrome import NotebookPage

    profile = tmp_path_factory.mktemp("chromium_profile")
    browser_log("starting Chromium")
    with NotebookPage(lab, profile, chromium_path(), device_scale_factor=2, log=browser_log) as nb:  # a HiDPI screen
        browser_log("Chromium started")
        yield nb
    left = processes_mentioning(str(profile))
    assert not left, f"Chromium processes left behind: {left}"
