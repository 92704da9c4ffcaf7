"""The notebooks in ``notebooks/`` run top to bottom without an error (nbclient, a real ipykernel).

Each notebook's last cell prints ``<name> notebook: done``; a notebook showing the env with
``render_mode="human"`` must put a live canvas widget into its outputs (not the text fallback).
A notebook needing a module that is not in this checkout fails in CI (``CI=true``) and skips
locally, saying which module.
"""

from __future__ import annotations

import base64
import hashlib
import importlib.util
import io
import json
import os
from pathlib import Path

import nbclient  # the test extra installs nbclient, nbformat and ipykernel
import nbformat
import numpy as np
import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")
EXPECTED = {"quickstart.ipynb", "race.ipynb", "planning.ipynb"}
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
# What each notebook must show: a live canvas (a widget view) and the modules it needs.
SHOWS_CANVAS = {"quickstart.ipynb", "race.ipynb", "planning.ipynb", "play.ipynb"}
# notebooks whose every widget output is an env's live canvas (play.ipynb's are the player and editor)
CANVAS_ONLY = {"quickstart.ipynb", "race.ipynb", "planning.ipynb"}
NEEDS = {"planning.ipynb": "babyrobot_marl.planning"}
CELL_TIMEOUT = 300  # seconds: a guard against a hung kernel, not a speed target
PROBE = """
import hashlib, json
from babyrobot_marl.render.canvas import shown_canvases
print("FRAMES " + json.dumps({
    c.view.model_id: [hashlib.sha256(c.picture().tobytes()).hexdigest(), list(c.picture().shape)] for c in shown_canvases()
}))
"""


def notebook_names() -> list[str]:
    return sorted(p.name for p in NOTEBOOKS.glob("*.ipynb"))


def test_the_notebooks_are_there():
    assert set(notebook_names()) >= EXPECTED


@pytest.mark.parametrize("name", notebook_names())
def test_notebook_is_stored_clean(name):
    """Committed without outputs or execution counts, with a kernelspec (diffs stay readable)."""
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    nbformat.validate(nb)
    assert nb.metadata.get("kernelspec", {}).get("name") == "python3"
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "code":
            assert not cell.outputs and cell.execution_count is None, f"cell {i} of {name} is stored with outputs"


def _outputs(nb) -> list[dict]:
    return [out for cell in nb.cells if cell.cell_type == "code" for out in cell.outputs]


@pytest.mark.parametrize("name", notebook_names())
def test_notebook_runs_top_to_bottom(name, monkeypatch, tmp_path):
    module = NEEDS.get(name)
    if module is not None and importlib.util.find_spec(module) is None:
        message = f"{name} needs {module}, which is not in this checkout"
        if IN_CI:
            pytest.fail(message)
        pytest.skip(message)
    # the kernel is a child process: it imports this checkout first, whatever is installed
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p))
    monkeypatch.setenv("JUPYTER_DATA_DIR", str(tmp_path / "jupyter_data"))  # "python3" is this interpreter's ipykernel
    monkeypatch.setenv("IPYTHONDIR", str(tmp_path / "ipython"))  # no user profile or startup files
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=CELL_TIMEOUT, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOKS)}}
    )
    with client.setup_kernel():
        for index, cell in enumerate(nb.cells):
            client.execute_cell(cell, index)  # raises CellExecutionError naming the cell on any error
        # then, in the same kernel: the rgb_array frame of each shown canvas's state, by widget model id
        probe = nbformat.v4.new_code_cell(PROBE)
        nb.cells.append(probe)
        client.execute_cell(probe, len(nb.cells) - 1)
    frames = json.loads(next(o.text for o in probe.outputs if o.output_type == "stream").split("FRAMES ", 1)[1])

    outputs = _outputs(nb)
    errors = [o for o in outputs if o.output_type == "error"]
    assert not errors, errors
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream" and o.name == "stdout")
    assert f"{name.removesuffix('.ipynb')} notebook: done" in text
    if name in SHOWS_CANVAS:
        views = [o for o in outputs if WIDGET_VIEW in o.get("data", {})]
        assert views, f"{name} showed no live canvas (no widget view among its outputs)"
    stills = []
    for view in views if name in CANVAS_ONLY else []:
        # every canvas output is followed by its still: a PNG of the canvas's final picture (at 2x),
        # which a notebook reopened anywhere shows (issue 26)
        k = outputs.index(view)
        still = outputs[k + 1] if k + 1 < len(outputs) else {}
        assert "image/png" in still.get("data", {}), "a canvas output without a still: a saved notebook would show only text"
        assert "babyrobot-still-" in still.data["text/html"]
        stills.append(still)
        png = np.array(Image.open(io.BytesIO(base64.b64decode(still.data["image/png"]))).convert("RGB"))
        model = view.data[WIDGET_VIEW]["model_id"]
        assert model in frames, "a canvas shown but not tracked"
        assert frames[model] == [hashlib.sha256(png.tobytes()).hexdigest(), list(png.shape)]
    if name in CANVAS_ONLY:  # nbviewer and GitHub render through nbconvert: the canvases show as their PNGs
        from nbconvert import HTMLExporter

        html, _ = HTMLExporter().from_notebook_node(nb)
        for still in stills:
            assert f"data:image/png;base64,{still.data['image/png'][:64]}" in html
        assert "IPython.core.display" not in html  # a GIF or image shown, not its Python repr
