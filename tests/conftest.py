"""Shared test set-up: make the package importable from a source checkout (no install needed), keep
Hypothesis's files out of the checkout (a run leaves nothing behind in the repository), draw plots
headless, and mark the heavy tests that the quick loop ``pytest -q -m "not heavy"`` leaves out."""

from __future__ import annotations

import ast
import contextlib
import functools
import os
import re
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


# How a test file skips when the train extra is missing: a module-level importorskip skips every test
# of the file; one inside a function (a test, a fixture or a helper it calls) skips the tests that use
# it. Those tests are marked ``train``: ``pytest -q -m train`` runs them where the extra is installed.
TRAIN_SIGNS = ('importorskip("torch"', 'importorskip("stable_baselines3', 'importorskip("supersuit"')
# what the skip reason of a test that wants the train extra speaks of
TRAIN_WORDS = re.compile(r"train extra|\btorch\b|stable.baselines3|supersuit", re.I)  # not torchrl: another library


@functools.cache
def _train_names(path: Path) -> frozenset[str] | None:
    """The names of the file's functions that need the train extra (directly or through another of
    its functions), or None when the whole file does."""
    text = path.read_text(encoding="utf-8")
    if not any(sign in text for sign in TRAIN_SIGNS):
        return frozenset()
    tree = ast.parse(text)
    functions: dict[str, ast.AST] = {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            functions[node.name] = node
        elif any(sign in ast.get_source_segment(text, node) for sign in TRAIN_SIGNS):
            return None  # a module-level skip
    needs = {name for name, node in functions.items() if any(s in ast.get_source_segment(text, node) for s in TRAIN_SIGNS)}
    calls = {name: {n.id for n in ast.walk(node) if isinstance(n, ast.Name)} for name, node in functions.items()}
    grown = True
    while grown:  # a function that calls (or takes as a fixture) one that needs the extra needs it too
        more = {name for name, names in calls.items() if names & needs or _arguments(functions[name]) & needs}
        grown = not more <= needs
        needs |= more
    return frozenset(needs)


def _arguments(node: ast.AST) -> set[str]:
    return {a.arg for a in node.args.args} if isinstance(node, ast.FunctionDef) else set()


def _needs_train(item: pytest.Item) -> bool:
    names = _train_names(item.path)
    if names is None:
        return True
    owner = item.cls.__name__ if getattr(item, "cls", None) is not None else getattr(item, "originalname", item.name)
    return owner in names or bool(set(getattr(item, "fixturenames", ())) & names)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """``heavy``: the browser, notebook, training and soak tests (``slow`` ones included); ``train``:
    the tests of files that skip without the train extra."""
    for item in items:
        if item.path.name in HEAVY_FILES or item.get_closest_marker("slow") or any(n in item.name for n in HEAVY_NAMES):
            item.add_marker(pytest.mark.heavy)
        if _needs_train(item):
            item.add_marker(pytest.mark.train)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo) -> pytest.TestReport:
    """A test that skips for want of the train extra but is not marked ``train`` fails: the run with
    the train extra (``-m train``) would never run it."""
    report = yield
    if report.skipped and item.get_closest_marker("train") is None:
        reason = str(report.longrepr[-1]) if isinstance(report.longrepr, tuple) else str(report.longrepr)
        if TRAIN_WORDS.search(reason):
            report.outcome = "failed"
            report.longrepr = f"skipped ({reason}) but not marked train: mark it, or 'pytest -m train' never runs it"
    return report
