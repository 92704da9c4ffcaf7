"""The site build renders the notebooks CI executed earlier in the same run (``BABYROBOT_EXECUTED_NOTEBOOKS``)
only when each copy is this checkout's notebook, cell for cell, run through (docs/_scripts/notebook_copies.py)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("notebook_copies", ROOT / "docs" / "_scripts" / "notebook_copies.py")
notebook_copies = importlib.util.module_from_spec(spec)
spec.loader.exec_module(notebook_copies)


def notebook(*sources: str, ran: bool) -> nbformat.NotebookNode:
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell("# A tutorial")])
    for n, source in enumerate(sources, start=1):
        cell = nbformat.v4.new_code_cell(source)
        if ran:
            cell.execution_count = n
            cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text=f"{n}\n")]
        nb.cells.append(cell)
    return nb


@pytest.fixture
def folders(tmp_path: Path) -> tuple[Path, Path]:
    stored, executed = tmp_path / "notebooks", tmp_path / "executed"
    stored.mkdir(), executed.mkdir()
    nbformat.write(notebook("print(1)", "print(2)", ran=False), stored / "tour.ipynb")
    return stored / "tour.ipynb", executed


def test_an_executed_copy_of_the_same_cells_is_rendered_with_its_outputs(folders):
    path, executed = folders
    nbformat.write(notebook("print(1)", "print(2)", ran=True), executed / "tour.ipynb")
    nb = notebook_copies.already_executed(path, executed)
    assert [o.text for c in nb.cells if c.cell_type == "code" for o in c.outputs] == ["1\n", "2\n"]


def test_a_copy_of_other_cells_is_refused(folders):
    path, executed = folders
    nbformat.write(notebook("print(1)", "print(3)", ran=True), executed / "tour.ipynb")
    with pytest.raises(ValueError, match="their cells differ"):
        notebook_copies.already_executed(path, executed)


def test_a_copy_not_run_through_is_refused(folders):
    path, executed = folders
    nb = notebook("print(1)", "print(2)", ran=True)
    nb.cells[-1].execution_count = None  # the kernel stopped before the last cell
    nbformat.write(nb, executed / "tour.ipynb")
    with pytest.raises(ValueError, match="not run through"):
        notebook_copies.already_executed(path, executed)


def test_a_missing_copy_is_refused_naming_it(folders):
    path, executed = folders
    with pytest.raises(FileNotFoundError, match="tour.ipynb"):
        notebook_copies.already_executed(path, executed)
