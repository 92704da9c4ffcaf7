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

Each ```` ```bash ```` block runs top to bottom in a temporary folder (holding links to
``examples/`` and ``benchmarks/``), every command in order, each exiting 0, except the
commands ``NOT_RUN`` names: set-up lines (``pip install``, ``python3 -m venv``, ...), which
``.ci/run`` runs word for word, getting the code (``git clone``, ``cd babyrobot_marl``),
CI's own commands, benchmarks (CI runs their quick modes; their
figures measure a stated machine) and a command whose comment starts ``# interactive`` (it
waits for a person: a window, the keyboard, a server). ``# requires: EXTRA`` on a block's first
line works as for Python blocks.

What a block claims is checked: an HTML comment right after the block,
``<!-- expect: PATTERN -->`` (or one pattern per line between ``<!-- expect:`` and ``-->``),
gives regular expressions that must each match a line of what the block printed.
"""

from __future__ import annotations

import argparse
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
    expect: tuple[str, ...] = ()  # the patterns of an <!-- expect: --> comment right after the block

    @property
    def id(self) -> str:
        return f"{self.path.relative_to(ROOT)}:{self.line}"


def blocks(path: Path) -> list[Block]:
    """The fenced code blocks of a Markdown file (fences at the start of a line)."""
    out, lang, start, body = [], None, 0, []
    lines = path.read_text(encoding="utf-8").splitlines()
    for n, line in enumerate(lines, start=1):
        if lang is None and line.startswith("```"):
            lang, start, body = line[3:].strip(), n, []
        elif lang is not None and line.rstrip() == "```":
            out.append(Block(path, start, lang, "\n".join(body) + "\n", expectations(lines[n:])))
            lang = None
        elif lang is not None:
            body.append(line)
    assert lang is None, f"{path}: the code block opened on line {start} is never closed"
    return out


def expectations(after: list[str]) -> tuple[str, ...]:
    """The patterns of an ``<!-- expect: ... -->`` comment at the top of ``after`` (blank lines skipped)."""
    text = "\n".join(after).lstrip()
    m = re.match(r"<!--\s*expect:(.*?)-->", text, re.S)
    if not m:
        return ()
    patterns = tuple(p.strip() for p in m.group(1).splitlines() if p.strip())
    for p in patterns:
        re.compile(p)  # a typo in a pattern fails the collection, not silently
    return patterns


ALL = [b for p in DOC_FILES if p.exists() for b in blocks(p)]
PYTHON = [b for b in ALL if b.lang == "python"]
CONSOLE = [b for b in ALL if b.lang == "console"]
SHELL = [b for b in ALL if b.lang in ("bash", "sh", "shell")]

# The commands of shell blocks that this test does not run, and why: narrow, by how a command starts.
NOT_RUN = (
    (r"^(python3 -m venv |\. \.venv/bin/activate$|pip install |apt-get install )", "set-up: .ci/run runs it word for word"),
    (r"^(git clone |cd babyrobot_marl$)", "getting the code: the tests run in a checkout"),
    (r"^pytest\b", "the suite itself: .ci/run runs it"),
    (r"^(bash \.ci/|mkdocs build )", "CI itself: .ci/run and .ci/docs.sh run it"),
    (r"^python benchmarks/", "a benchmark: .ci/run runs it in quick mode; its figures measure a stated machine"),
    (r"^(ray start |python examples/rllib_race\.py )", "RLlib: .ci/rllib.sh runs examples/rllib_race.py (one iteration, quick)"),
    (r"#\s*interactive\b", "waits for a person (marked # interactive)"),
)


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
        if gone and extra in LIBRARIES:  # no extra of this package: name the library, and where CI runs it
            return f"{block.id} needs {extra}, which is no extra of babyrobot_marl (tests_integrations/ runs it in its own venv)"
        if gone:
            return f"{block.id} needs the {extra} extra ({', '.join(gone)} not installed)"
    return None


def test_the_docs_have_python_and_console_blocks():
    # the collection itself can fail: a parser that found nothing would make every test below vacuous
    assert len(PYTHON) >= 30, [b.id for b in PYTHON]
    assert len(CONSOLE) >= 2, [b.id for b in CONSOLE]
    assert len(SHELL) >= 20, [b.id for b in SHELL]
    assert len(SHELL_RUN) >= 8, [b.id for b in SHELL_RUN]


def test_block_parser_reads_expectations(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "```bash\nbabyrobot-marl levels\n```\n\n<!-- expect:\n^race-4 \nwalls\n-->\n```bash\nx\n```\n<!-- expect: exit$ -->\n"
    )
    first, second = blocks(page)
    assert first.expect == ("^race-4", "walls") and second.expect == ("exit$",)
    assert blocks(page)[1].text == "x\n"


def test_shell_commands_run_all_but_set_up_ci_benchmarks_and_interactive_ones(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "```bash\n"
        "python3 -m venv .venv && . .venv/bin/activate && pip install -e . && babyrobot-marl levels  # set up, then run\n"
        "babyrobot-marl play --level puddles --policy keys   # interactive: you play\n"
        "python benchmarks/bench_single.py --quick\n"
        "python examples/train_fast.py --steps 10\n"
        "pytest -q\n"
        "```\n"
    )
    ran = [cmd for cmd, why in shell_commands(blocks(page)[0]) if why is None]
    assert ran == ["babyrobot-marl levels", "python examples/train_fast.py --steps 10"]


def test_block_parser_reads_fences_and_requires(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("text\n```python\n# requires: train\nx = 1\n```\n\n```\nplain\n```\n```console\n$ echo hi\nhi\n```\n")
    found = blocks(page)
    assert [(b.lang, b.line) for b in found] == [("python", 2), ("", 7), ("console", 10)]
    assert required_extras(found[0]) == ["train"]
    assert found[2].text == "$ echo hi\nhi\n"


def params(found: list[Block]) -> list:
    """The blocks as test parameters; a block that trains is ``heavy`` (the quick loop leaves it out) and ``train``."""
    trains = [pytest.mark.heavy, pytest.mark.train]
    return [pytest.param(b, id=b.id, marks=trains if "train" in required_extras(b) else []) for b in found]


@pytest.mark.parametrize("block", params(PYTHON))
def test_python_block_runs_alone(block, tmp_path, monkeypatch, capsys):
    why = missing_extra(block)
    if why:
        pytest.skip(why)
    monkeypatch.chdir(tmp_path)  # blocks that save files (GIFs, models) write here
    code = compile(block.text, block.id, "exec")
    if "train" not in required_extras(block):
        exec(code, {"__name__": "__main__"})
        check_claims(block, capsys.readouterr().out)
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
    check_claims(block, capsys.readouterr().out)


def check_claims(block: Block, printed: str) -> None:
    """Each pattern of the block's ``<!-- expect: -->`` comment matches a line of what it printed."""
    for pattern in block.expect:
        assert re.search(pattern, printed, re.M), f"{block.id}: nothing printed matches {pattern!r}; printed:\n{printed[-3000:]}"


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


def not_run(command: str) -> str | None:
    """Why a shell command is not run here (``NOT_RUN``), or None: it runs."""
    return next((why for pattern, why in NOT_RUN if re.search(pattern, command)), None)


def shell_commands(block: Block) -> list[tuple[str, str | None]]:
    """``[(command, why it is not run or None)]`` of a shell block: one per line, ``a && b`` split."""
    out = []
    for line in block.text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        if re.search(r"#\s*interactive\b", line):
            out.append((line, not_run(line)))
            continue
        line = re.sub(r"\s+#.*$", "", line)  # a trailing comment (no '#' inside this project's commands)
        out += [(cmd.strip(), not_run(cmd.strip())) for cmd in line.split("&&")]
    return out


# babyrobot-marl and python as a reader's activated venv has them: this interpreter, this checkout
SHELL_PRELUDE = """set -eo pipefail
babyrobot-marl() { "$DOCS_PYTHON" -m babyrobot_marl "$@"; }
python() { "$DOCS_PYTHON" "$@"; }
"""


# blocks with a command to run here (a block of set-up lines only, for one, is run by .ci/run)
SHELL_RUN = [b for b in SHELL if any(why is None for _, why in shell_commands(b))]


@pytest.mark.parametrize("block", params(SHELL_RUN))
def test_shell_block_runs_and_prints_what_the_page_claims(block, tmp_path):
    why = missing_extra(block)
    if why:
        pytest.skip(why)
    commands = [cmd for cmd, why in shell_commands(block) if why is None]
    for folder in ("examples", "benchmarks"):  # a reader runs them from the checkout's root
        (tmp_path / folder).symlink_to(ROOT / folder)
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
        "DOCS_PYTHON": sys.executable,
        "NO_COLOR": "1",
        "OMP_NUM_THREADS": "1",  # torch on one thread, as the package's trainers run it on a busy machine
    }
    printed = ""
    for cmd in commands:
        key = run_key(cmd, required_extras(block), tmp_path)
        if key in RUNS:  # the same command on the same files ran for another block: its output and files
            out, written = RUNS[key]
            for name, data in written.items():
                (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
                (tmp_path / name).write_bytes(data)
            printed += out
            continue
        before = folder_files(tmp_path)
        # a guard against a hung command, not a speed target
        script = ["bash", "-c", SHELL_PRELUDE + cmd]
        got = subprocess.run(script, capture_output=True, text=True, cwd=tmp_path, env=env, timeout=1800)
        assert got.returncode == 0, f"{block.id}: '{cmd}' exited {got.returncode}:\n{got.stdout[-2000:]}\n{got.stderr[-3000:]}"
        printed += got.stdout
        if key is not None:
            after = folder_files(tmp_path)
            RUNS[key] = (got.stdout, {name: data for name, data in after.items() if before.get(name) != data})
    check_claims(block, printed)


# Two pages may show the same command word for word (README's quick start and the fast trainer's
# guide train the same policy): it runs once, and the second block gets that run's output and the
# files it wrote, against which its own expectations are checked. Only babyrobot-marl commands are
# kept: they read no file but those they name, so the key (the command, the block's extras and the
# contents of the folder's files the command names) says everything the run depended on.
RUNS: dict[tuple, tuple[str, dict[str, bytes]]] = {}


def run_key(command: str, extras: list[str], folder: Path) -> tuple | None:
    """What a run of ``command`` in ``folder`` depends on, or None: a command whose run is not kept."""
    if not re.match(r"babyrobot-marl\b", command) or re.search(r"[|<>;`$]", command):
        return None
    words = {part for word in command.split() for part in re.split(r"[=,]", word)}
    named = sorted(w for w in words if w and (folder / w).is_file())
    return (command, tuple(extras), tuple((w, (folder / w).read_bytes()) for w in named))


def folder_files(folder: Path) -> dict[str, bytes]:
    """The files under ``folder`` by relative path (os.walk does not enter the links to examples/ and benchmarks/)."""
    return {str((Path(top) / name).relative_to(folder)): (Path(top) / name).read_bytes()
            for top, _, names in os.walk(folder) for name in names if not (Path(top) / name).is_symlink()}


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


def _docstring_markers() -> list[tuple[str, str | None]]:
    marker = re.compile(r"^<!-- docstring: ([\w.]+)(?::(\w+))? -->$", re.MULTILINE)
    return sorted({m.groups() for path in DOC_FILES for m in marker.finditer(path.read_text(encoding="utf-8"))},
                  key=str)


@pytest.mark.parametrize(("module", "attr"), _docstring_markers())
def test_every_docstring_a_page_includes_has_its_sections(module, attr):
    """The site's env pages include an env's docstring from its first ``## `` heading
    (docs/_scripts/hooks.py); a line indented less than the rest hides every heading from it."""
    sys.path.insert(0, str(ROOT / "docs" / "_scripts"))
    try:
        import hooks
    finally:
        sys.path.remove(str(ROOT / "docs" / "_scripts"))
    sections = hooks.docstring_sections(module, attr)
    assert sections.startswith("## ") and sections.count("\n## ") >= 2


# ---------------------------------------------------------------------------- the commands the pages name
# pages whose result tables each name the babyrobot-marl command that produced them
RESULT_PAGES = [ROOT / "docs" / "guides" / "fast-trainer.md"]
INLINE_CODE = re.compile(r"`([^`\n]+)`")


def cli_commands(text: str) -> list[str]:
    """Every ``babyrobot-marl ...`` command of a page's text: in code blocks (one per line, up to a trailing comment,
    ``&&`` or a pipe) and in inline code."""
    found = []
    for piece in [*INLINE_CODE.findall(text), *text.splitlines()]:
        for part in re.split(r"&&|\||;", re.sub(r"\s+#.*$", "", piece)):
            m = re.search(r"(?:^|\s|\$ )(babyrobot-marl(?: .*)?)$", part.strip())
            if m:
                found.append(m.group(1).strip())
    return sorted(set(found))


def unknown_flag(command: str) -> str | None:
    """What in ``command`` the command line does not have (a command, a flag), or None."""
    import shlex

    from babyrobot_marl.cli.entry import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    words = shlex.split(command)[1:]
    if not words or words[0].startswith("-"):
        known = set(parser._option_string_actions)
    elif words[0] in sub.choices:
        known, words = set(sub.choices[words[0]]._option_string_actions), words[1:]
    else:
        return f"no command {words[0]!r}"
    return next((f"no flag {w.split('=')[0]!r}" for w in words if w.startswith("-") and w != "-"
                 and not re.fullmatch(r"-\d.*", w) and w.split("=")[0] not in known), None)


def tables(text: str) -> list[tuple[str, str]]:
    """``[(the paragraph right above a table, the table)]`` of a Markdown page."""
    out, lines = [], text.splitlines()
    n = 0
    while n < len(lines):
        if lines[n].startswith("|"):
            end = n
            while end < len(lines) and lines[end].startswith("|"):
                end += 1
            start = n - 1
            while start >= 0 and not lines[start].strip():
                start -= 1
            top = start
            while top >= 0 and lines[top].strip() and not lines[top].startswith("|"):
                top -= 1
            out.append(("\n".join(lines[top + 1:start + 1]), "\n".join(lines[n:end])))
            n = end
        n += 1
    return out


def test_the_command_checker_finds_a_flag_or_command_that_does_not_exist():
    page = ("Run `babyrobot-marl train --level maze:8..8 --blocked-cost 0.5`.\n"
            "```bash\nbabyrobot-marl evaluate p.pt --robotz 3\n```\n")
    assert cli_commands(page) == ["babyrobot-marl evaluate p.pt --robotz 3", "babyrobot-marl train --level maze:8..8 "
                                  "--blocked-cost 0.5"]
    assert unknown_flag("babyrobot-marl evaluate p.pt --robotz 3") == "no flag '--robotz'"
    assert unknown_flag("babyrobot-marl trian --steps 3") == "no command 'trian'"
    assert unknown_flag("babyrobot-marl train --level maze:8..8 --blocked-cost 0.5 --seed=1") is None
    assert tables("intro\n\nmeasured by `babyrobot-marl x`:\n\n| a |\n|---|\n| 1 |\n\nafter\n") == [
        ("measured by `babyrobot-marl x`:", "| a |\n|---|\n| 1 |")]


@pytest.mark.parametrize("path", DOC_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_command_a_page_names_has_those_flags(path):
    text = path.read_text(encoding="utf-8")
    wrong = {cmd: why for cmd in cli_commands(text) if (why := unknown_flag(cmd))}
    assert not wrong, f"{path.relative_to(ROOT)}: commands the command line does not take: {wrong}"


@pytest.mark.parametrize("path", RESULT_PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_result_table_names_the_command_that_produced_it(path):
    found = tables(path.read_text(encoding="utf-8"))
    assert found, f"{path.relative_to(ROOT)} has no result table"
    for caption, table in found:
        named = [c for c in cli_commands(caption + "\n" + table) if len(c.split()) > 2]
        assert named, f"{path.relative_to(ROOT)}: no babyrobot-marl command above or in the table:\n{table[:300]}"


def test_a_kept_run_is_keyed_by_the_command_its_extras_and_the_files_it_names(tmp_path):
    (tmp_path / "ppo.pt").write_bytes(b"one")
    key = run_key("babyrobot-marl play --policy ppo.pt", ["train"], tmp_path)
    assert key == run_key("babyrobot-marl play --policy ppo.pt", ["train"], tmp_path)
    assert key != run_key("babyrobot-marl play --policy ppo.pt", [], tmp_path)
    assert key != run_key("babyrobot-marl play --policy ppo.pt --no-delay", ["train"], tmp_path)
    (tmp_path / "ppo.pt").write_bytes(b"two")  # the file it reads changed: another run
    assert key != run_key("babyrobot-marl play --policy ppo.pt", ["train"], tmp_path)
    assert ("ppo.pt", b"two") in run_key("babyrobot-marl race --policies ppo.pt,random", [], tmp_path)[2]
    assert ("ppo.pt", b"two") in run_key("babyrobot-marl race --policies=ppo.pt", [], tmp_path)[2]
    assert run_key("python examples/train_fast.py", [], tmp_path) is None  # a script may read any file
    assert run_key("babyrobot-marl levels | head -3", [], tmp_path) is None


def test_a_command_two_blocks_show_runs_once_and_each_block_checks_its_claims(tmp_path, monkeypatch):
    calls = []

    def fake_run(script, cwd, **kwargs):  # a "training" that saves a file and prints a line
        calls.append(script[-1])
        (Path(cwd) / "out.pt").write_bytes(b"weights")
        return subprocess.CompletedProcess(script, 0, stdout="trained 5 timesteps\n", stderr="")

    monkeypatch.setattr(subprocess, "run", fake_run)
    monkeypatch.setattr(sys.modules[__name__], "RUNS", {})
    command = "babyrobot-marl train --steps 5 --save out.pt\n"
    first = Block(ROOT / "docs" / "a.md", 1, "bash", command, ("^trained 5 timesteps$",))
    second = Block(ROOT / "README.md", 1, "bash", command, ("^trained 5 timesteps$",))
    (tmp_path / "a").mkdir(), (tmp_path / "b").mkdir(), (tmp_path / "c").mkdir()
    test_shell_block_runs_and_prints_what_the_page_claims(first, tmp_path / "a")
    test_shell_block_runs_and_prints_what_the_page_claims(second, tmp_path / "b")
    assert len(calls) == 1 and (tmp_path / "b" / "out.pt").read_bytes() == b"weights"
    wrong = Block(ROOT / "README.md", 9, "bash", command, ("^trained 6 timesteps$",))
    with pytest.raises(AssertionError, match="trained 6 timesteps"):
        test_shell_block_runs_and_prints_what_the_page_claims(wrong, tmp_path / "c")
    assert len(calls) == 1


def test_the_readme_trains_with_the_fast_trainer_guides_command():
    # the quick start repeats the guide's first command word for word: one run serves both pages
    def trainings(name: str) -> set[str]:
        return {cmd for b in SHELL_RUN if b.path.name == name for cmd, why in shell_commands(b)
                if why is None and cmd.startswith("babyrobot-marl train")}

    assert trainings("README.md") and trainings("README.md") <= trainings("fast-trainer.md")
    races = {cmd for cmd in trainings("training.md") if "--level race-4" in cmd}  # and the training guide's race
    assert races and races <= trainings("fast-trainer.md")
