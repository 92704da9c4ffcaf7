"""A live widget shown with a still picture of it: the picture a saved notebook keeps.

JupyterLab draws a saved widget output only while a kernel holds the widget's model: a notebook
reopened with a new kernel shows "Error displaying widget: model not found" in its place
(jupyterlab-manager's ``WidgetRenderer``; it never falls back to the output's other mimetypes, and
it is chosen over them whenever the notebook is trusted). So ``show`` displays two outputs:

1. the widget's view, its text empty (GitHub and nbconvert, which have no model, show nothing);
2. the still: a PNG of the widget's picture at two device pixels per CSS pixel (``image/png`` with
   its CSS size, and ``text/html`` of the same image with a style).

The style makes the page show one of the two: the still is hidden while the live widget is on the
page, and the widget's output (its "model not found" box) is hidden while it is not. The still is
refreshed (``Still.refresh``) as the widget changes; a saved notebook keeps its last picture.
"""

from __future__ import annotations

import base64
import html
import itertools
import zlib
from collections.abc import Callable
from typing import Any

import numpy as np

WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
NARROW_FIT = "100%"  # a picture's widest in its column: a narrow column shows it scaled down whole
_ids = itertools.count()


def png_bytes(img: np.ndarray) -> bytes:
    """``uint8[H, W, 3]`` as a PNG file (zlib from the standard library: no image package needed)."""
    h, w = img.shape[:2]
    raw = np.concatenate([np.zeros((h, 1), dtype=np.uint8), img.reshape(h, w * 3)], axis=1).tobytes()

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return len(data).to_bytes(4, "big") + body + zlib.crc32(body).to_bytes(4, "big")

    header = w.to_bytes(4, "big") + h.to_bytes(4, "big") + bytes([8, 2, 0, 0, 0])
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")


def still_style(uid: str) -> str:
    """The rules that show either the live widget (class ``babyrobot-live-<uid>``) or its still."""
    live, still = f"babyrobot-live-{uid}", f"babyrobot-still-{uid}"
    return (
        # the live widget on the page: its still is not shown
        f".jp-OutputArea:has(.{live}) .jp-OutputArea-child:has(.{still}) {{display: none}}\n"
        # the output just before the still, when it holds no live widget (a box saying the model was
        # not found, or nothing): not shown, the still stands in for it
        f".jp-OutputArea-child:has(+ .jp-OutputArea-child .{still}):not(:has(.{live})) {{display: none}}\n"
        # the still as wide as the live widget was: in the output's whole width, as a widget is
        f".jp-OutputArea-output:has(> .{still}) {{padding: 0; overflow: visible}}"
    )


class Still:
    """``widget`` (an ipywidgets widget) shown with a still of ``picture()`` (``uint8[H, W, 3]`` at
    ``ratio`` device pixels per CSS pixel), ``css`` the CSS of its size (the live view's)."""

    def __init__(self, widget: Any, picture: Callable[[], np.ndarray], css: str | None = None, ratio: int = 2):
        self.widget, self.picture, self.css, self.ratio = widget, picture, css, ratio
        self.uid = f"{next(_ids)}-{widget.model_id[:8]}"
        widget.add_class(f"babyrobot-live-{self.uid}")
        self._handle: Any = None

    def show(self) -> None:
        from IPython.display import display

        display(self.widget_bundle(), raw=True)
        data, metadata = self.bundle()
        self._handle = display(data, raw=True, metadata=metadata, display_id=True)

    def refresh(self) -> None:
        """The still brought up to the widget's picture (nothing before ``show``)."""
        if self._handle is not None:
            data, metadata = self.bundle()
            self._handle.update(data, raw=True, metadata=metadata)

    def widget_bundle(self) -> dict[str, Any]:
        return {WIDGET_VIEW: self.widget._repr_mimebundle_()[WIDGET_VIEW], "text/plain": ""}

    def bundle(self) -> tuple[dict[str, Any], dict[str, Any]]:
        img = self.picture()
        h, w = img.shape[0] // self.ratio, img.shape[1] // self.ratio
        data = base64.b64encode(png_bytes(img)).decode("ascii")
        css = self.css or f"width: {w}px; max-width: {NARROW_FIT}; height: auto"
        tag = (f'<style>{still_style(self.uid)}</style><img class="babyrobot-still-{self.uid}" '
               f'src="data:image/png;base64,{data}" width="{w}" height="{h}" '
               f'style="{html.escape(css)}" alt="the last frame">')  # fmt: skip
        return {"image/png": data, "text/html": tag, "text/plain": "(the last frame)"}, {"image/png": {"width": w, "height": h}}
