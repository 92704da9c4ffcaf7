"""mkdocs-gen-files script: draws the site's figures from the envs at build time (see figures.py)."""

import sys
from pathlib import Path

import mkdocs_gen_files

sys.path.insert(0, str(Path(__file__).parent))
import figures  # noqa: E402

figures.write_all(mkdocs_gen_files.open)
