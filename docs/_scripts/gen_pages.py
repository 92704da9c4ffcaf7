"""mkdocs-gen-files script, run at every build: the site's figures, drawn from the envs
(``figures.py``), and the tutorials, the notebooks of ``notebooks/`` executed here.

The notebooks are stored without outputs. Each one runs top to bottom in a real kernel
(nbclient); a cell that fails fails the build. A live-canvas output is an ipywidgets view, which
a static page cannot draw (the canvas is drawn by commands sent to a browser that is not
there); where the output also carries a PNG of the canvas's frame, the page shows that PNG.

With ``BABYROBOT_EXECUTED_NOTEBOOKS=DIR`` the notebooks are not run again: DIR holds them executed
(``bash .ci/notebooks.sh`` writes them there when given the same variable), and each must be this
checkout's notebook, cell for cell, run through to its last cell.
"""

import os
import sys
import tempfile
from pathlib import Path

import mkdocs_gen_files
import nbformat
from nbclient import NotebookClient

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import figures  # noqa: E402
from notebook_copies import already_executed  # noqa: E402

WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"


def executed(path: Path) -> nbformat.NotebookNode:
    ran = os.environ.get("BABYROBOT_EXECUTED_NOTEBOOKS")
    nb = already_executed(path, Path(ran)) if ran else run(path)
    for cell in nb.cells:
        for output in cell.get("outputs", []):
            data = output.get("data", {})
            if WIDGET_VIEW in data and "image/png" in data:
                del data[WIDGET_VIEW]  # the static page shows the canvas's PNG
    nb.metadata.pop("widgets", None)  # no widget state to embed: a static page has no kernel
    return nb


def run(path: Path) -> nbformat.NotebookNode:
    nb = nbformat.read(path, as_version=4)
    with tempfile.TemporaryDirectory() as cwd:  # notebooks that save files (GIFs) write here
        NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": cwd}}).execute()
    return nb


figures.write_all(mkdocs_gen_files.open)

for notebook in sorted((HERE.parents[1] / "notebooks").glob("*.ipynb")):
    with mkdocs_gen_files.open(f"tutorials/{notebook.name}", "w") as f:
        nbformat.write(executed(notebook), f)

# The changelog lives at the repository's root (where people look for it); the site shows the same text
with mkdocs_gen_files.open("changelog.md", "w") as f:
    f.write((HERE.parents[1] / "CHANGELOG.md").read_text(encoding="utf-8"))
