"""The package's architecture (docs/architecture.md): layers, no circles, each layer's checks in
its own checks.py, no module over 500 lines, and the page's "to change X, open Y" table true.

The rules and their reading of the code live in ``docs/_scripts/architecture.py`` (the same code
draws the page's picture); the layers in ``pyproject.toml``."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "architecture.md"


def _load():
    spec = importlib.util.spec_from_file_location("architecture", ROOT / "docs" / "_scripts" / "architecture.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("architecture", module)
    spec.loader.exec_module(module)
    return module


arch = _load()


@pytest.fixture(scope="module")
def graph():
    return arch.import_graph()


def test_the_package_has_no_import_circle(graph):
    assert arch.circles(graph) == []


def test_the_package_keeps_every_rule(graph):
    # circles, upward and peer imports, modules over 500 lines, check_* outside checks.py
    assert arch.problems(graph) == []


def test_the_rules_find_each_kind_of_break(tmp_path):
    """The same reading on a small package that breaks every rule once: each break is named."""
    pkg = tmp_path / "pkg"
    for folder in ("core", "envs", "render"):
        (pkg / folder).mkdir(parents=True)
        (pkg / folder / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "core" / "a.py").write_text("from ..envs import b\n")  # upward
    # a deferred import back down: a circle; and a check_* outside a checks.py
    (pkg / "envs" / "b.py").write_text("def f():\n    from ..core import a\n\n\ndef check_x():\n    pass\n")
    (pkg / "render" / "c.py").write_text("from ..core import a\n" + "x = 1\n" * 501)  # too long
    (pkg / "stray.py").write_text("")  # a root module in no layer
    found = "\n".join(arch.problems(arch.import_graph(pkg), pkg))
    assert "circle: core.a <-> envs.b" in found
    assert "upward: core.a (core) -> envs.b (envs)" in found
    assert "long: render.c has 502 lines" in found
    assert "check outside checks.py: envs.b defines check_x" in found
    assert "unknown layer: stray" in found


def test_the_root_holds_the_public_face_only():
    face = {name for row in arch.LAYERS[-1:] for name in row}
    root = {p.stem for p in (ROOT / "babyrobot_marl").glob("*.py")}
    assert root == face
    subpackages = {p.parent.name for p in (ROOT / "babyrobot_marl").glob("*/__init__.py")}
    assert subpackages == {name for row in arch.LAYERS[:-1] for name in row}


def test_the_picture_names_every_layer(graph):
    picture = arch.svg(graph)
    for row in arch.LAYERS[:-1]:
        for layer in row:
            assert f">{layer}<" in picture


def _to_change_table() -> list[tuple[str, list[str]]]:
    text = PAGE.read_text(encoding="utf-8").split("## To change X, open Y", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in text.splitlines() if line.startswith("| ") and not line.startswith("| to change")]
    return [(row.split("|")[1].strip(), re.findall(r"`(babyrobot_marl/[^`]+)`", row.split("|")[2])) for row in rows]


def test_every_path_the_page_names_exists_and_every_subpackage_is_there():
    table = _to_change_table()
    assert len(table) >= 15
    named = set()
    for what, paths in table:
        assert paths, f"{what!r}: no path"
        for path in paths:
            if "<" in path:  # a pattern such as cli/<command>.py: its folder must exist
                path = path.split("<", 1)[0]
            assert (ROOT / path).exists(), f"{what!r}: {path} does not exist"
            named.add(Path(path).parts[1] if len(Path(path).parts) > 2 else Path(path).stem)
    subpackages = {p.parent.name for p in (ROOT / "babyrobot_marl").glob("*/__init__.py")}
    assert subpackages <= named, f"not in the table: {sorted(subpackages - named)}"
