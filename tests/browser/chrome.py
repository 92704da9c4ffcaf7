"""Headless Debian Chromium through Playwright: open a notebook in JupyterLab, run it, read canvas pixels.

Never ``playwright install``: the browser is the system's ``/usr/bin/chromium`` (apt package ``chromium``).
"""

from __future__ import annotations

import base64
import contextlib
import os
import shutil
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

CHROMIUM_ARGS = [
    "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--no-first-run", "--disable-dev-shm-usage",
]  # fmt: skip


# seconds: a guard against a dead kernel or browser, not a speed target. Every wait here is for an
# event (a marker printed, the kernel idle, the canvas drawn); a loaded machine (load 10 on 2 cores)
# takes minutes where an idle one takes seconds.
WAIT = 300.0


def chromium_path() -> str | None:
    """The system Chromium, or None: ``$CHROMIUM`` if set, else ``/usr/bin/chromium`` or ``chromium`` on PATH."""
    for candidate in (os.environ.get("CHROMIUM"), "/usr/bin/chromium", shutil.which("chromium")):
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    return None


# The notebook panel in focus, once its kernel is connected and idle.
_KERNEL_IDLE = """() => {
  const app = window.jupyterapp;
  const w = app && app.shell.currentWidget;
  const s = w && w.sessionContext;
  return !!(s && s.session && s.session.kernel && s.session.kernel.connectionStatus === 'connected'
            && s.session.kernel.status === 'idle' && w.content && w.content.widgets.length > 0);
}"""

_CANVASES = """Array.from(document.querySelectorAll('.jp-OutputArea-output canvas'))
      .filter(c => c.width > 0 && c.height > 0)"""

# The ``index``-th canvas in the notebook's outputs as ``{width, height, data}`` (RGBA bytes, base64). An
# ipycanvas (Multi)Canvas view is one <canvas>: a MultiCanvas composites its layers into it (ipycanvas >= 0.13).
_READ_CANVAS = f"""(index) => {{
  const all = {_CANVASES};
  if (index >= all.length) return {{count: all.length}};
  const c = all[index];
  const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let s = '';
  for (let i = 0; i < data.length; i += 0x8000) s += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
  return {{count: all.length, width: c.width, height: c.height, data: btoa(s)}};
}}"""

# The ``index``-th canvas exists and is opaque: drawn (an empty canvas is transparent).
_CANVAS_OPAQUE = f"""(index) => {{
  const all = {_CANVASES};
  if (index >= all.length) return false;
  const c = all[index], data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  for (let i = 3; i < data.length; i += 4) if (data[i] !== 255) return false;
  return true;
}}"""

# No widget output still "Loading widget..." (the manager has restored, or failed to restore, each model).
_WIDGETS_SETTLED = """() => document.querySelectorAll('.jp-OutputArea-output').length > 0 && !Array.from(
  document.querySelectorAll('.jp-OutputArea-output')).some(o => o.innerText.includes('Loading widget'))"""

_MARKER_SHOWN = """(m) => Array.from(document.querySelectorAll('.jp-OutputArea-output')).some(o => o.innerText.includes(m))"""


def _quiet(message: str) -> None:
    pass


class NotebookPage:
    """One JupyterLab page in a persistent headless Chromium profile (``with NotebookPage(...) as nb:``)."""

    def __init__(
        self, lab, profile_dir: Path, executable: str, viewport=(1280, 1000), device_scale_factor: float = 1,
        log: Callable[[str], None] = _quiet,
    ):  # fmt: skip
        self.lab, self.profile_dir, self.executable, self.viewport = lab, Path(profile_dir), executable, viewport
        self.device_scale_factor = device_scale_factor
        self.log = log  # progress lines: a browser test takes seconds idle, minutes on a loaded machine
        self._pw = self.context = self.page = None

    def __enter__(self) -> NotebookPage:
        from playwright.sync_api import sync_playwright

        self._pw = sync_playwright().start()
        try:
            self.context = self._pw.chromium.launch_persistent_context(
                str(self.profile_dir), executable_path=self.executable, headless=True, args=CHROMIUM_ARGS,
                viewport={"width": self.viewport[0], "height": self.viewport[1]},
                device_scale_factor=self.device_scale_factor,
            )  # fmt: skip
            self.context.set_default_timeout(WAIT * 1000)  # clicks, locators: Playwright's own default is 30 s
            self.context.set_default_navigation_timeout(WAIT * 1000)
            self.page = self.context.pages[0] if self.context.pages else self.context.new_page()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self.context is not None:
            self.context.close()
            self.context = None
        if self._pw is not None:
            self._pw.stop()
            self._pw = None

    def run_all(self, notebook: str, marker: str, timeout: float = WAIT) -> None:
        """Open ``notebook`` (relative to the server root), run all cells, wait for ``marker`` in an output."""
        page, ms = self.page, timeout * 1000
        self.log(f"{notebook}: opening")
        page.goto(self.lab.url(f"lab/tree/{notebook}", reset=""), timeout=ms)
        page.wait_for_function(_KERNEL_IDLE, timeout=ms, polling=200)
        self.log(f"{notebook}: kernel ready, running all cells")
        page.evaluate("() => window.jupyterapp.commands.execute('notebook:run-all-cells')")
        try:
            page.wait_for_function(_MARKER_SHOWN, arg=marker, timeout=ms, polling=200)
        except Exception as e:
            raise AssertionError(f"marker {marker!r} never appeared; outputs:\n{self.outputs_text()}") from e
        self.log(f"{notebook}: all cells ran")

    def save(self, timeout: float = WAIT) -> None:
        """Save the notebook in focus and wait until it is saved."""
        self.page.evaluate("() => window.jupyterapp.commands.execute('docmanager:save')")
        self.page.wait_for_function(
            "() => { const w = window.jupyterapp.shell.currentWidget; return !!w && !w.context.model.dirty; }",
            timeout=timeout * 1000,
            polling=200,
        )

    def save_and_reopen(self, notebook: str, marker: str, timeout: float = WAIT) -> None:
        """Save the notebook, load the page again (a browser reconnecting to the same kernel), wait for ``marker``."""
        page, ms = self.page, timeout * 1000
        self.save(timeout)
        self.log(f"{notebook}: saved, loading the page again")
        page.goto(self.lab.url(f"lab/tree/{notebook}"), timeout=ms)
        page.wait_for_function(_KERNEL_IDLE, timeout=ms, polling=200)
        page.wait_for_function(_MARKER_SHOWN, arg=marker, timeout=ms, polling=200)
        self.log(f"{notebook}: reopened, kernel connected")

    def reopen_with_a_new_kernel(self, notebook: str, timeout: float = WAIT) -> None:
        """Save the notebook, end its kernel, open it again: a learner coming back to it another day
        (the saved file, signed by this server, is trusted; a new kernel that ran nothing)."""
        page, ms = self.page, timeout * 1000
        self.save(timeout)
        self.lab.shutdown_sessions()
        self.log(f"{notebook}: saved, kernel shut down, opening it again")
        page.goto(self.lab.url(f"lab/tree/{notebook}"), timeout=ms)
        page.wait_for_function(_KERNEL_IDLE, timeout=ms, polling=200)
        # the widget manager has looked for the outputs' models: each widget output is drawn or says why not
        page.wait_for_function(_WIDGETS_SETTLED, timeout=ms, polling=200)
        self.log(f"{notebook}: reopened with a new kernel")

    def outputs_text(self) -> str:
        return self.page.evaluate(
            "() => Array.from(document.querySelectorAll('.jp-OutputArea-output')).map(o => o.innerText).join('\\n')"
        )

    def canvas_pixels(
        self, index: int = 0, ready: Callable[[np.ndarray], bool] | None = None, timeout: float = WAIT
    ) -> np.ndarray:
        """The ``index``-th canvas output as ``uint8[H, W, 4]`` RGBA, once it is drawn (opaque: an empty
        canvas is transparent), two reads agree (its layers arrive one after another) and ``ready(rgba)``
        holds. After ``timeout`` seconds without that, the last read, for the caller's checks to explain."""
        from playwright.sync_api import TimeoutError as PlaywrightTimeout

        deadline, last = time.monotonic() + timeout, None
        while True:
            left = deadline - time.monotonic()
            # the cheap check in the page first: no pixels cross to Python until the canvas is drawn
            with contextlib.suppress(PlaywrightTimeout):  # not drawn in time: read what there is
                self.page.wait_for_function(_CANVAS_OPAQUE, arg=index, timeout=max(left, 1) * 1000, polling=300)
            got = self.page.evaluate(_READ_CANVAS, index)
            if "data" in got:
                img = np.frombuffer(base64.b64decode(got["data"]), dtype=np.uint8).reshape(got["height"], got["width"], 4)
                drawn = last is not None and np.array_equal(img, last) and (img[..., 3] == 255).all()
                if drawn and (ready is None or ready(img)):
                    return img
                last = img
            if time.monotonic() > deadline:
                if last is None:
                    raise AssertionError(f"no canvas output #{index} (found {got['count']}); outputs:\n{self.outputs_text()}")
                return last
            time.sleep(0.3)

    def canvas_size(self, index: int = 0) -> dict:
        """The ``index``-th canvas output's backing store and CSS size, and the page's devicePixelRatio."""
        return self.page.evaluate(
            """(index) => {
              const all = Array.from(document.querySelectorAll('.jp-OutputArea-output canvas')).filter(c => c.width > 0);
              const c = all[index], r = c.getBoundingClientRect();
              return {width: c.width, height: c.height, css_width: r.width, css_height: r.height, dpr: window.devicePixelRatio};
            }""",
            index,
        )

    def screenshot(self, path: Path) -> Path:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.page.screenshot(path=str(path), full_page=True)
        return path
