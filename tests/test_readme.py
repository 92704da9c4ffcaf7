"""The README a newcomer reads in five minutes: short, in the order they need it, its two commands
the ones CI runs, its figures linked to where their commands and spread live, and its checked claims
true on any CPU (a range or a property, never one machine's exact count)."""

from __future__ import annotations

import re
from pathlib import Path

from tests.test_docs_blocks import ROOT, blocks

README = ROOT / "README.md"
TEXT = README.read_text(encoding="utf-8")
MAIN_JOB = "babyrobot-marl race --level race-4 --robots 4 --policies shortest,shortest,random,random"
SET_UP = "python3 -m venv .venv && . .venv/bin/activate && pip install -e ."


def headings() -> list[str]:
    return re.findall(r"^## (.+)$", TEXT, re.M)


def test_at_most_120_lines():
    assert len(TEXT.splitlines()) <= 120


def test_what_it_is_and_a_picture_come_first_then_the_sections_in_a_newcomers_order():
    intro = TEXT.split("\n## ", 1)[0]
    assert re.search(r"^!\[[^\]]+\]\(docs/[^)]+\.(png|gif)\)$", intro, re.M), "a picture before the first section"
    assert len(intro.split("![", 1)[0].split()) >= 30, "a paragraph of what it is and for whom before the picture"
    order = ["Get it", "Two commands for a fresh machine", "Quick start: one robot", "Quick start: a race",
             "Quick start: a notebook", "Quick start: training", "Figures", "Documentation"]
    assert headings() == order


def test_get_it_says_how_which_pythons_and_that_it_is_not_on_pypi():
    section = TEXT.split("## Get it", 1)[1].split("\n## ", 1)[0]
    assert "git clone " in section and "\ncd babyrobot_marl\n" in section
    assert "Python 3.10" in section and "3.11" in section and "not on PyPI" in section


def test_the_two_commands_are_the_main_job_and_the_tests_each_with_what_you_see():
    section = TEXT.split("## Two commands for a fresh machine", 1)[1].split("\n## ", 1)[0]
    shell = [b.text.strip() for b in blocks(README) if b.lang == "bash" and b.line > TEXT[: TEXT.index(section)].count("\n")]
    assert shell[0] == f"{SET_UP} && {MAIN_JOB}"
    assert shell[1] == f'{SET_UP.removesuffix(" .")} ".[test]" && pytest -q'
    after_main, after_tests = section.split("```bash")[1].split("```", 1)[1], section.split("```bash")[2].split("```", 1)[1]
    assert "table" in after_main and "key" in after_main  # what the race shows
    assert "passed" in after_tests and "minutes on two idle cores" in after_tests


def test_no_history_test_counts_or_machines():
    assert not re.search(r"\b\d,\d{3} tests\b|\b\d+:\d\d\b|\bCI\b|\bbefore\b.*\b(was|gave)\b", TEXT)
    assert len(re.findall(r"minutes", TEXT)) == 1  # "about N minutes on two idle cores", once


def test_each_headline_figure_is_one_line_linked_to_the_benchmarks_page():
    section = TEXT.split("## Figures", 1)[1].split("\n## ", 1)[0]
    figures = [line for line in section.splitlines() if line.startswith("- ")]
    assert 3 <= len(figures) <= 5
    anchors = set(re.findall(r"^#+ (.+)$", (ROOT / "docs/guides/benchmarks.md").read_text(encoding="utf-8"), re.M))
    slugs = {re.sub(r"[^a-z0-9 -]", "", a.lower()).replace(" ", "-") for a in anchors}
    for line in figures:
        links = re.findall(r"\(docs/guides/benchmarks\.md#([a-z0-9-]+)\)", line)
        assert links and set(links) <= slugs, line


def test_the_training_claim_accepts_what_another_cpu_gives():
    """The same seed gave 95% of the optimum first at 1,114,112 timesteps on one CPU and 1,179,648 on
    another: the README's check holds for both, and still fails past its stated bound of 1.5M."""
    block = next(b for b in blocks(README) if "babyrobot-marl train" in b.text)
    pattern = next(p for p in block.expect if "first reached at" in p)
    line = ("fast PPO on maze-8x8: greedy return -35 (+- 0, 20/20 reached the exit), optimal -35; "
            "95% of it first reached at {} timesteps, 0.4 s")
    for seen in (1114112, 1179648, 917504, 1499999):
        assert re.search(pattern, line.format(seen)), seen
    for past in (1500000, 1572864, 11141120):
        assert not re.search(pattern, line.format(past)), past
    assert "before 1.5M timesteps" in TEXT
    assert not any(n in p for p in block.expect for n in ("1114112", "1,114,112", "1179648", "1,179,648"))


def test_every_link_of_the_readme_points_at_a_file_that_exists():
    for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", TEXT):
        if not target.startswith("http"):
            assert (ROOT / target).exists(), target


def test_the_readme_links_the_changelog_and_the_site_shows_it():
    assert Path(ROOT / "CHANGELOG.md").is_file() and "(CHANGELOG.md)" in TEXT
    assert "Changelog: changelog.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
