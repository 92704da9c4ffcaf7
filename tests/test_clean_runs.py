"""What a user runs in a fresh clone leaves no file behind: property tests (Hypothesis) and the
README's picture script, run in a copy of the checkout, add nothing to it but ``__pycache__``
folders, change no tracked file, and put nothing in the temp folder besides pytest's own."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GUARD = 900  # seconds: a guard against a hung run, not a speed target
ALLOWED = {"__pycache__", ".pytest_cache"}  # what .gitignore lists and Python itself writes


def checkout_files() -> list[str]:
    """The checkout's files as a fresh clone has them (tracked, plus new files not ignored)."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    out = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=ROOT, capture_output=True, check=True, timeout=GUARD,
    ).stdout  # fmt: skip
    return [f for f in out.decode().split("\0") if f and (ROOT / f).is_file()]


def snapshot(folder: Path) -> dict[str, str]:
    """``{relative path: sha256}`` of every file under ``folder`` outside the allowed caches."""
    found = {}
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames[:] = [d for d in dirnames if d not in ALLOWED]
        for name in filenames:
            path = Path(dirpath, name)
            found[str(path.relative_to(folder))] = hashlib.sha256(path.read_bytes()).hexdigest()
    return found


def test_tests_and_picture_script_leave_no_file_in_a_fresh_checkout(tmp_path):
    pytest.importorskip("hypothesis")
    pytest.importorskip("imageio.v3", reason="the picture script needs the video extra (imageio)")
    repo, tmp = tmp_path / "repo", tmp_path / "tmp"
    for rel in checkout_files():
        (repo / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / rel, repo / rel)
    tmp.mkdir()
    before = snapshot(repo)
    env = {**os.environ, "PYTHONPATH": str(repo), "TMPDIR": str(tmp)}
    env.pop("HYPOTHESIS_STORAGE_DIRECTORY", None)
    for cmd in (
        [sys.executable, "-m", "pytest", "-q", "tests/test_observe.py"],  # property tests
        [sys.executable, "examples/readme_pictures.py"],  # rewrites docs/images with the same pictures
    ):
        run = subprocess.run(cmd, cwd=repo, env=env, capture_output=True, text=True, timeout=GUARD)
        assert run.returncode == 0, f"{cmd[1:]} exited {run.returncode}:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    after = snapshot(repo)
    assert sorted(set(after) - set(before)) == [], "new files in the checkout"
    changed = sorted(p for p in before if after.get(p) != before[p])
    # the picture script redraws docs/images: a changed picture means the drawing changed (the README's
    # pictures are checked here, byte for byte): redraw (python examples/readme_pictures.py) and commit
    assert changed == [], "tracked files changed"
    assert sorted(p.name for p in tmp.iterdir() if not p.name.startswith("pytest-of-")) == [], "left in the temp folder"


def test_no_test_writes_to_a_fixed_folder_of_the_system_temp_directory():
    """Tests write under pytest's temporary folder (``tmp_path``, ``tmp_path_factory``): a fixed
    folder in the system temp directory outlives the run and is shared by concurrent runs."""
    fixed = ("gettempdir(", '"/tmp', "'/tmp", "tempfile.mkdtemp(")
    found = [
        f"{path.relative_to(ROOT)}:{n}: {line.strip()}"
        for path in sorted((ROOT / "tests").rglob("*.py"))
        if path != Path(__file__).resolve()
        for n, line in enumerate(path.read_text().splitlines(), 1)
        if any(f in line for f in fixed)
    ]
    assert found == []
