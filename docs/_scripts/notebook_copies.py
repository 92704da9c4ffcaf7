"""The executed copies of the notebooks that a site build may render instead of running them again
(``BABYROBOT_EXECUTED_NOTEBOOKS``, read by ``gen_pages.py``)."""

from pathlib import Path

import nbformat


def already_executed(path: Path, folder: Path) -> nbformat.NotebookNode:
    """The executed copy of ``path`` in ``folder``; a copy of another version of the notebook, or one
    not run through, fails the build (the page would show outputs of code it does not hold)."""
    copy = folder / path.name
    if not copy.is_file():
        raise FileNotFoundError(f"{copy}: no executed copy of {path.name} (run .ci/notebooks.sh with the same variable)")
    nb, stored = nbformat.read(copy, as_version=4), nbformat.read(path, as_version=4)
    if [(c.cell_type, c.source) for c in nb.cells] != [(c.cell_type, c.source) for c in stored.cells]:
        raise ValueError(f"{copy} is not the executed {path}: their cells differ")
    code = [c for c in nb.cells if c.cell_type == "code"]
    if any(c.execution_count is None for c in code if c.source.strip()):
        raise ValueError(f"{copy} was not run through: a code cell has no execution count")
    return nb
