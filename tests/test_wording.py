"""What a user reads states what is true now: no word of this project's issues, briefs, machines or
history in the README, the docs, the command line's help or the docstrings (history is in CHANGELOG.md)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from babyrobot_marl.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]

# a phrase and why a user should not meet it
BANNED = {
    r"\bissue\s*#?\d+": "a project issue's number",
    r"\bthe issue'?s?\b": "the project's issue",
    r"\bthe brief\b": "the project's brief",
    r"\bmeasured before\b|\bbefore issue\b|\bmain before\b": "history (it goes in CHANGELOG.md)",
    r"\bthis project's (shared )?(2-core )?machines?\b": "the project's own machines",
    r"\bmeasured here\b": "'here': say which machine",
    r"\blab notebook\b": "a diary, not a reference",
}
PATTERN = re.compile("|".join(f"(?:{p})" for p in BANNED), re.IGNORECASE)


def hits(text: str) -> list[str]:
    """The banned phrases of ``text``, each with the line it is on."""
    return [line.strip()[:160] for line in text.splitlines() if PATTERN.search(line)]


def pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def docstrings() -> list[tuple[str, str]]:
    """``(where, docstring)`` of every module, class and function of the package."""
    out = []
    for path in sorted((ROOT / "babyrobot_marl").rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in [tree, *ast.walk(tree)]:
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                doc = ast.get_docstring(node)
                if doc:
                    out.append((f"{path.relative_to(ROOT)}:{getattr(node, 'name', '<module>')}", doc))
    return out


def help_texts() -> dict[str, str]:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return {"babyrobot-marl": parser.format_help(), **{name: p.format_help() for name, p in sub.choices.items()}}


def test_the_phrases_are_found_where_they_are():
    # the check itself can fail: each kind of phrase is caught, and a plain sentence is not
    for line in ("see issue 28", "(issue #5)", "the issue's aim", "It covers every rule of the brief",
                 "before issue 28's faster resets", "measured before X", "this project's 2-core machine", "Measured here ("):
        assert hits(line), line
    assert not hits("Issues and pull requests welcome; a robot issues an action")


@pytest.mark.parametrize("page", pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_no_page_speaks_of_issues_briefs_or_history(page):
    assert hits(page.read_text(encoding="utf-8")) == []


def test_no_docstring_speaks_of_issues_briefs_or_history():
    found = [f"{where}: {line}" for where, doc in docstrings() for line in hits(doc)]
    assert len(docstrings()) > 300 and found == []


def test_no_help_text_speaks_of_issues_briefs_or_history():
    texts = help_texts()
    assert {"play", "race", "train", "evaluate", "solve", "levels"} <= set(texts)
    assert {name: hits(text) for name, text in texts.items() if hits(text)} == {}
