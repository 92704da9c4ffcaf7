"""Shared test set-up: make the package importable from a source checkout (no install needed), keep
Hypothesis's files out of the checkout (a run leaves nothing behind in the repository), draw plots
headless, and mark the heavy tests that the quick loop ``pytest -q -m "not heavy"`` leaves out."""

from __future__ import annotations

import contextlib
import os
import sys
from pathlib import Path

# Plots headless (matplotlib's Agg backend). gymnasium.utils.play asks for TkAgg when imported, which
# fails once pyplot is loaded on a machine without a display, and it then warns "matplotlib is not
# installed": import it first, while pyplot is not loaded (the request only sets a name), then go
# back to Agg.
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
with contextlib.suppress(Exception):  # no pygame (the play extra): the module does not load, and warns nothing
    import gymnasium.utils.play  # noqa: E402, F401
try:
    import matplotlib  # noqa: E402
except ImportError:
    pass
else:
    matplotlib.use("Agg")

import pytest  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
# Test files that start a browser, run notebooks in a kernel, train, soak, fuzz or property-test with
# many random examples, or run every command of the docs: the full suite runs them, the quick loop does
# not (docs blocks that train are marked in tests/test_docs_blocks.py too)
HEAVY_FILES = (
    "test_browser.py", "test_browser_harness.py", "test_browser_play.py", "test_browser_reopen.py", "test_browser_replay.py",
    "test_notebooks.py", "test_reliability_soak.py", "test_ppo.py", "test_family_trainer.py", "test_training_race.py",
    "test_training_single.py", "test_train_cli.py", "test_examples.py", "test_policy_files.py", "test_cli_solve_train.py",
    "test_reliability_properties.py", "test_reliability_levels_fuzz.py", "test_reliability_render.py", "test_cli_fuzz.py",
    "test_docs_blocks.py", "test_clean_runs.py", "test_readme_pictures.py", "test_overlay.py",
)
HEAVY_NAMES = ("learns",)  # a test that trains in a file of quick ones: its name says it learns
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


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """``heavy``: the browser, notebook, training and soak tests (``slow`` ones included)."""
    for item in items:
        if item.path.name in HEAVY_FILES or item.get_closest_marker("slow") or any(n in item.name for n in HEAVY_NAMES):
            item.add_marker(pytest.mark.heavy)
