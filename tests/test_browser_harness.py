"""The browser tests' harness without a browser: its progress lines reach the terminal under
``pytest -q`` while output is captured (a browser test may take minutes on a loaded machine)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_progress_lines_show_under_pytest_q_with_output_captured(tmp_path):
    (tmp_path / "test_steps.py").write_text(
        "import pytest\n"
        "from tests.browser.fixtures import terminal_writer\n"
        "@pytest.fixture(scope='session')\n"
        "def say(pytestconfig):\n"
        "    return terminal_writer(pytestconfig, 'browser')\n"
        "def test_one(say):\n"
        "    print('captured print')\n"
        "    say('step one of a long test')\n"
        "def test_two(say):\n"
        "    say('step two')\n"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tmp_path / "test_steps.py")],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout + run.stderr
    lines = run.stdout.splitlines()
    assert "captured print" not in run.stdout  # pytest still captures the tests' own output
    steps = [ln for ln in lines if ln.startswith("browser [")]
    assert [s.split("] ", 1)[1] for s in steps] == ["step one of a long test", "step two"], run.stdout
