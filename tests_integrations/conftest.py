"""Integration tests: each library runs the README's snippet, as its own docs show it plugged in."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

SNIPPETS = Path(__file__).parent / "snippets"
README = Path(__file__).parent.parent / "docs" / "guides" / "other-libraries.md"  # the snippets moved from README.md to the site


def run_snippet(name: str, tmp_path: Path, timeout: float = 600) -> str:
    """Run ``snippets/<name>.py`` in a fresh interpreter (cwd: a temporary folder); its stdout."""
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    proc = subprocess.run(
        [sys.executable, str(SNIPPETS / f"{name}.py")], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=timeout
    )
    assert proc.returncode == 0, proc.stderr[-4000:]
    return proc.stdout


def readme_has(name: str) -> bool:
    """The README shows the snippet exactly as the test runs it."""
    return (SNIPPETS / f"{name}.py").read_text().strip() in README.read_text()


@pytest.fixture
def snippet(tmp_path):
    return lambda name: run_snippet(name, tmp_path)
