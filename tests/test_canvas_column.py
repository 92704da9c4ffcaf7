"""A canvas never overflows its notebook column: the layout and the still's CSS let it scale down
whole (height following width) while its backing store keeps every pixel."""

from __future__ import annotations

import pytest

pytest.importorskip("ipycanvas", reason="the notebook extra (ipycanvas) is part of the test extra; CI installs it")

from babyrobot_marl import levels  # noqa: E402
from babyrobot_marl.play import notebook  # noqa: E402
from babyrobot_marl.render import canvas as live  # noqa: E402
from babyrobot_marl.render.overlay import Overlay, update_overlay  # noqa: E402
from babyrobot_marl.render.rgb import RgbRenderer  # noqa: E402
from babyrobot_marl.render.still import Still  # noqa: E402


def css_of(text: str) -> dict[str, str]:
    return {k.strip(): v.strip() for k, v in (part.split(":", 1) for part in text.split(";") if part.strip())}


@pytest.mark.parametrize("cs", [32, 64, 72])
def test_a_canvas_with_its_own_cell_size_scales_down_in_a_narrow_column(cs):
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), cs), fps=0)
    box, layout = c.box.layout, c.widget.layout  # the canvas, cropped to its picture by its box
    assert (box.width, box.max_width, layout.width, layout.height) == (f"{8 * cs + 2}px", "100%", "100%", "auto")  # + frame
    assert box.align_self == layout.align_self == "flex-start"  # in a row of widgets its height stays its own
    assert c.widget.width == 2 * 8 * cs  # the backing store keeps its resolution
    assert css_of(c.css) == {"width": f"{8 * cs}px", "max-width": "100%", "height": "auto"}


def test_a_canvas_that_grows_keeps_scaling_down_in_a_narrow_column():
    c = live.LiveCanvas(RgbRenderer(levels.get("maze-8x8"), 64), fps=0)
    h, backing = c.shown, c.widget.height
    c.draw([(1, 1)], update_overlay(Overlay(), levels.get("maze-8x8"), panel=["a", "b", "c"]))
    assert c.shown > h and c.widget.height == backing  # into the spare rows
    assert (c.box.layout.max_width, c.widget.layout.height) == ("100%", "auto")
    c.draw([(1, 1)], update_overlay(Overlay(), levels.get("maze-8x8"), panel=["a"] * 30))
    assert c.widget.height > backing  # past them: a taller canvas
    assert (c.box.layout.max_width, c.widget.layout.height) == ("100%", "auto")


def test_a_still_without_a_css_of_its_own_scales_down_in_a_narrow_column():
    from ipywidgets import HTML

    r = RgbRenderer(levels.get("maze-8x8"), 128)
    bundle, _ = Still(HTML(), lambda: r.frame(()), None, 2).bundle()
    style = bundle["text/html"].split('style="', 1)[1].split('"', 1)[0]
    assert css_of(style) == {"width": "512px", "max-width": "100%", "height": "auto"}


def test_the_editor_s_canvas_scales_down_in_a_narrow_column():
    e = notebook.edit("walls", cell_size=64)
    layout = e.canvas.layout
    assert (layout.width, layout.max_width, layout.height) == (f"{e.level.width * 64}px", "100%", "auto")
    assert layout.align_self == "flex-start"  # beside the tools: not stretched to the row's height
    assert e.canvas.width == 2 * e.level.width * 64
