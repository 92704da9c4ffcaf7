"""Every code block of the documentation runs as shown.

Each ```` ```python ```` block of ``docs/**/*.md`` and ``README.md`` runs alone, in a fresh
namespace and a temporary working directory (a reader copies one block, not the page). A block
that needs an extra starts with a comment ``# requires: train`` (or ``rllib``, ``notebook``,
``video``, ``play``, ``plot``, several separated by commas) and is skipped only when that extra is
not installed; a snippet for another library (``# requires: torchrl``, ...) only without that library.
``# requires: display`` marks a block that opens a window and waits for a person: never run here.

Each ```` ```console ```` block is a terminal session: every ``$ command`` line runs (with
``babyrobot-marl`` as ``python -m babyrobot_marl``) and its output must be the lines shown
under it, exactly.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC_FILES = sorted((ROOT / "docs").rglob("*.md")) + [ROOT / "README.md"]

# the modules each extra brings, as a block's "# requires:" names them
EXTRAS = {
    "train": ("stable_baselines3", "supersuit"),
    "rllib": ("ray",),
    "notebook": ("ipycanvas", "ipywidgets"),
    "video": ("imageio",),
    "play": ("pygame",),
    "plot": ("matplotlib",),
}
# libraries that are no extra of the package: their snippets run in their own venvs (tests_integrations/)
LIBRARIES = ("torchrl", "benchmarl", "agilerl", "tianshou")
REQUIRES = re.compile(r"^#\s*requires:\s*(.+)$")


@dataclass(frozen=True)
class Block:
    path: Path
    line: int  # 1-based line of the opening fence
    lang: str
    text: str

    @property
    def id(self) -> str:
        return f"{self.path.relative_to(ROOT)}:{self.line}"


def blocks(path: Path) -> list[Block]:
    """The fenced code blocks of a Markdown file (fences at the start of a line)."""
    out, lang, start, body = [], None, 0, []
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        if lang is None and line.startswith("```"):
            lang, start, body = line[3:].strip(), n, []
        elif lang is not None and line.rstrip() == "```":
            out.append(Block(path, start, lang, "\n".join(body) + "\n"))
            lang = None
        elif lang is not None:
            body.append(line)
    assert lang is None, f"{path}: the code block opened on line {start} is never closed"
    return out


ALL = [b for p in DOC_FILES if p.exists() for b in blocks(p)]
PYTHON = [b for b in ALL if b.lang == "python"]
CONSOLE = [b for b in ALL if b.lang == "console"]


def required_extras(block: Block) -> list[str]:
    for line in block.text.splitlines():
        if not line.strip():
            continue
        m = REQUIRES.match(line.strip())
        return [e.strip() for e in m.group(1).split(",")] if m else []
    return []


def missing_extra(block: Block) -> str | None:
    if "display" in required_extras(block):  # a window waiting for a person's keys: not for a test run
        return f"{block.id} opens a window and waits for the keyboard (# requires: display)"
    for extra in required_extras(block):
        if extra not in EXTRAS and extra not in LIBRARIES and extra != "display":
            known = ", ".join([*EXTRAS, *LIBRARIES])
            raise AssertionError(f"{block.id}: '# requires: {extra}' names no known extra or library; known: {known}")
        gone = [m for m in EXTRAS.get(extra, (extra,)) if importlib.util.find_spec(m) is None]
        if gone:
            return f"{block.id} needs the {extra} extra ({', '.join(gone)} not installed)"
    return None


def test_the_docs_have_python_and_console_blocks():
    # the collection itself can fail: a parser that found nothing would make every test below vacuous
    assert len(PYTHON) >= 30, [b.id for b in PYTHON]
    assert len(CONSOLE) >= 2, [b.id for b in CONSOLE]


def test_block_parser_reads_fences_and_requires(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("text\n```python\n# requires: train\nx = 1\n```\n\n```\nplain\n```\n```console\n$ echo hi\nhi\n```\n")
    found = blocks(page)
    assert [(b.lang, b.line) for b in found] == [("python", 2), ("", 7), ("console", 10)]
    assert required_extras(found[0]) == ["train"]
    assert found[2].text == "$ echo hi\nhi\n"


@pytest.mark.parametrize("block", PYTHON, ids=lambda b: b.id)
def test_python_block_runs_alone(block, tmp_path, monkeypatch, capsys):
    why = missing_extra(block)
    if why:
        pytest.skip(why)
    monkeypatch.chdir(tmp_path)  # blocks that save files (GIFs, models) write here
    code = compile(block.text, block.id, "exec")
    if "train" not in required_extras(block):
        exec(code, {"__name__": "__main__"})
        return
    # torch on one thread, as the package's trainers run it: on a busy 2-core machine torch's own
    # thread pool makes these short runs 5-10x slower (its threads wait on each other)
    import torch

    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        exec(code, {"__name__": "__main__"})
    finally:
        torch.set_num_threads(threads)


def console_sessions(block: Block) -> list[tuple[str, str]]:
    """``[(command, expected output)]`` of a console block."""
    sessions: list[tuple[str, list[str]]] = []
    for line in block.text.splitlines():
        if line.startswith("$ "):
            sessions.append((line[2:], []))
        else:
            assert sessions, f"{block.id}: a console block starts with a '$ ' command line"
            sessions[-1][1].append(line)
    return [(cmd, "\n".join(out).rstrip("\n")) for cmd, out in sessions]


@pytest.mark.parametrize("block", CONSOLE, ids=lambda b: b.id)
def test_console_block_shows_what_the_command_prints(block):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]), "NO_COLOR": "1"}
    for cmd, expected in console_sessions(block):
        run = re.sub(r"^babyrobot-marl\b", f"{sys.executable} -m babyrobot_marl", cmd)
        got = subprocess.run(run, shell=True, capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
        assert got.returncode == 0, f"{block.id}: '{cmd}' exited {got.returncode}: {got.stderr}"
        assert got.stdout.rstrip("\n") == expected, f"{block.id}: '{cmd}' printed\n{got.stdout}"


def test_readme_picture_is_what_its_command_draws():
    # README's picture is stored in git; `python docs/_scripts/figures.py --readme` must redraw it exactly
    iio = pytest.importorskip("imageio.v3", reason="drawing the README picture needs the video extra (imageio)")
    sys.path.insert(0, str(ROOT / "docs" / "_scripts"))
    try:
        import figures
    finally:
        sys.path.remove(str(ROOT / "docs" / "_scripts"))
    stored = iio.imread(ROOT / "docs" / "assets" / "readme" / "baby-robot.png")
    assert stored.dtype == "uint8" and stored.shape == figures.readme_picture().shape
    assert (stored[..., :3] == figures.readme_picture()).all()
