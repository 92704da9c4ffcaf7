"""mkdocs-gen-files script, run at every build: the site's figures, drawn from the envs
(``figures.py``), and the tutorials, the notebooks of ``notebooks/`` (stored without outputs;
mkdocs-jupyter executes them)."""

import sys
from pathlib import Path

import mkdocs_gen_files

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import figures  # noqa: E402

figures.write_all(mkdocs_gen_files.open)

for notebook in sorted((HERE.parents[1] / "notebooks").glob("*.ipynb")):
    with mkdocs_gen_files.open(f"tutorials/{notebook.name}", "wb") as f:
        f.write(notebook.read_bytes())
