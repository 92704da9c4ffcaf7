"""Shared test set-up: make the package importable from a source checkout (no install needed), and
keep Hypothesis's files out of the checkout: a run leaves nothing behind in the repository."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

# the real-browser tests' fixtures: one JupyterLab and one Chromium for the session
from tests.browser.fixtures import browser_log, browser_ready, lab, page, screenshots  # noqa: E402, F401

try:
    from hypothesis import settings
except ImportError:  # the test extra is not installed: the property tests skip or fail on their own
    settings = None
else:
    # No example database (it would be ./.hypothesis/examples) and no deadline: a loaded machine
    # runs an example slower, and a property test checks the property, not the speed.
    settings.register_profile("babyrobot_marl", database=None, deadline=None)
    settings.load_profile("babyrobot_marl")


@pytest.hookimpl(trylast=True)  # after pytest's tmp_path plugin has set up its factory
def pytest_configure(config: pytest.Config) -> None:
    """Hypothesis still caches the constants it reads from the source (``.hypothesis/constants``
    under the working directory, written while the tests are collected): under pytest's temporary
    folder instead."""
    if settings is not None:
        from hypothesis import configuration

        configuration.set_hypothesis_home_dir(config._tmp_path_factory.mktemp("hypothesis"))
