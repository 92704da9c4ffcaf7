#!/usr/bin/env bash
# Issue 23 (each extra runs what it is named for): a fresh venv with the notebook extra ALONE, then
# every notebook of notebooks/ executed top to bottom in a real kernel. nbclient (the headless
# front end, as JupyterLab is a person's) is the only package added; no test extra, no pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS

venv=${NOTEBOOK_VENV:-.venv-ci-notebook}
.ci/venv "$venv"
.ci/locked "$venv/bin/pip" install -q -e ".[notebook]" nbclient
"$venv/bin/pip" check
echo "notebooks: venv ready after $((SECONDS - start)) s"
# run from a temporary folder: whatever a notebook writes stays out of the checkout. With
# BABYROBOT_EXECUTED_NOTEBOOKS=DIR the executed notebooks are written to DIR too: the site build that follows
# in the same CI run (.ci/docs.sh) renders those instead of running every notebook again.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=${BABYROBOT_EXECUTED_NOTEBOOKS:-}
if [ -n "$out" ]; then rm -rf "$out" && mkdir -p "$out"; fi
"$venv/bin/python" - "$PWD/notebooks" "$work" "$out" <<'PY'
import sys
from pathlib import Path

import nbclient
import nbformat

folder, work, out = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
names = sorted(folder.glob("*.ipynb"))
assert names, f"no notebook in {folder}"
for path in names:
    nb = nbformat.read(path, as_version=4)
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": work}}).execute()
    text = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []))
    # a missing extra that a notebook catches prints the package's "pip install '...'" hint: not a pass
    assert "pip install" not in text, f"{path.name} fell back on a missing package:\n{text}"
    assert f"{path.stem} notebook: done" in text, f"{path.name} did not print its last line"
    if out:
        nbformat.write(nb, Path(out) / path.name)
    print(f"notebooks: {path.name} ran top to bottom")
print(f"{len(names)} passed, 0 failed")
PY
echo "notebooks: $((SECONDS - start)) s in all"
