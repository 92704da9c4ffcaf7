"""The live canvas: the grid drawn in the Jupyter cell with ipycanvas and updated as the episode runs.

A ``MultiCanvas`` of three layers, its backing store ``pixel_ratio`` (default 2) times its CSS
size so it is crisp on HiDPI screens:

0. the level with the overlay's tints, arrows and numbers: the ``rgb_array`` picture at
   ``pixel_ratio`` times the cell size, sent pixel for pixel once (as rectangles of one colour,
   drawn before the page can show the canvas: ``put_picture``), and again only when the
   overlay's cells change (as lossless PNG);
1. the robots, the marks of collisions and the rank badges (``scene``), redrawn each step
   as canvas paths: ``animation_frames`` interpolated frames glide the robots from cell to
   cell (0: jump), each frame one ``hold_canvas()`` batch of one ``fill_styled_polygons``
   call plus the robots' numbers, paced at ``fps`` steps per second;
2. the START / EXIT labels (always on top) and the panel under the grid: the overlay's text,
   the colour bar, the race legend, redrawn when they change.

Both renderers draw the same operations (``paint``), so the canvas and ``rgb_array`` show the
same picture. Without a ``cell_size`` of its own (``fit``) the canvas fills about 90% of the
notebook column (less for tall levels) and its backing store has the pixels for that. The panel's
height is reserved when an episode starts: the lines, colour bar and legend the overlay shows then,
and (``reserve_values``) room for a colour bar or ``RESERVED_LINES`` lines of text, so the canvas
does not grow mid-episode when values or a step's lines come; past it, into spare rows kept below
the picture, by CSS alone (``crop``); past them the canvas is made taller, never shown empty.

Shown with a still of its latest frame (``still.Still``), refreshed when an episode ends, when
the env closes and after every notebook cell that changed it (``snapshot``): a notebook saved
and reopened, in JupyterLab with a new kernel, on GitHub, nbviewer or in nbconvert's HTML,
shows the picture. After an episode a slider and a play button under the canvas replay its
steps (``replay``) from the scenes kept, without stepping the env.

``on_client_ready`` redraws everything when a browser (re)connects. Needs the ``notebook``
extra (ipycanvas, ipywidgets, orjson); imported lazily. Every number sent is a Python number.
"""

from __future__ import annotations

import time  # noqa: F401  (the clock pacing reads: tests set it as canvas.time)
from collections import deque
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.level import Cell
from .canvas_calls import _css, _frame_bars, _rect, _send, _Styles, marked_frame  # noqa: F401  (_css: read as canvas._css)
from .checks import MAX_ANIMATION_FRAMES, MAX_CELL_SIZE, MIN_CELL_SIZE, check_animation_frames, check_fps  # noqa: F401
from .crop import SPARE_LINES, backing_height, crop_margin
from .overlay import Overlay
from .pacing import Pacer
from .panel_room import panel_room
from .rgb import RgbRenderer
from .scene import Scene, as_scene, glide, robot_sprites
from .shapes import Fill, Op, Text
from .still import NARROW_FIT, Still, png_bytes  # noqa: F401  (png_bytes: read as canvas.png_bytes)
from .transfer import picture_calls, put_picture

PIXEL_RATIO = 2
REDRAW_AFTER = 1.0  # seconds after a browser (re)connects: everything drawn once more
FIT_WIDTH, FIT_HEIGHT = 940, 940  # CSS pixels: a fitted canvas's largest grid (90% of a 1,032-pixel column)
FIT_SHARE = "90%"  # of the notebook column, a fitted canvas's width
FRAME_PX = 1  # the frame round the canvas, in the page's own border colour: the picture stands out on a dark page
FRAME = f"{FRAME_PX}px solid var(--jp-border-color1, #9e9e9e)"
FIT_VIEW = 80  # percent of the window's height a fitted canvas may take (tall levels are narrower)
MAX_REPLAY = 10_000  # scenes an episode's replay keeps (the latest)
RESERVED_LINES = 2  # lines of panel text a canvas has room for from the start (a step's and a return's)
MAX_TRACKED = 16  # canvases whose saved PNG is refreshed after each cell (the most recent ones)
_shown: deque[LiveCanvas] = deque(maxlen=MAX_TRACKED)
_hooked = False


def shown_canvases() -> list[LiveCanvas]:
    """The canvases shown in this kernel (the most recent ``MAX_TRACKED``), oldest first."""
    return list(_shown)


def _after_cell(*_: Any) -> None:
    """IPython's ``post_run_cell``: each shown canvas's PNG brought up to its latest frame, and
    its replay bar offered for what it drew (an episode stopped before its end has one too)."""
    for c in list(_shown):
        c.snapshot(only_if_changed=True)
        c.offer_replay()


def _track(c: LiveCanvas) -> None:
    global _hooked
    _shown.append(c)
    if not _hooked:
        from IPython import get_ipython

        shell = get_ipython()
        if shell is not None:
            shell.events.register("post_run_cell", _after_cell)
            _hooked = True


def notebook_available() -> bool:
    """True inside a running IPython kernel (Jupyter) with ipycanvas installed."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    if shell is None or getattr(shell, "kernel", None) is None:
        return False
    try:
        import ipycanvas  # noqa: F401
    except ImportError:
        return False
    return True


def fit_cell_size(level: Any) -> int:
    """The CSS cell size of a canvas fitted to the notebook column (capped for tall levels)."""
    cs = min(FIT_WIDTH // level.width, FIT_HEIGHT // level.height)
    return int(np.clip(cs, MIN_CELL_SIZE, MAX_CELL_SIZE // PIXEL_RATIO))


class LiveCanvas:
    """Draws one env's level, robots and overlay on an ipycanvas ``MultiCanvas`` (``widget``).

    ``renderer`` draws the ``rgb_array`` frames (and fixes the cell size and theme);
    ``fps``: steps per second (0: as fast as drawn); frames are sent at most
    ``fps * max(1, animation_frames)`` a second, measured from the frame before, so the
    time a program spends between steps is not added to it; ``animation_frames``: frames
    per step (0: robots jump); ``pixel_ratio``: backing-store pixels per CSS pixel; ``fit``:
    the canvas fills about 90% of the notebook column (``renderer``'s cell size is then only
    the ``rgb_array`` frames'); else each cell is ``renderer.cell_size`` CSS pixels;
    ``reserve_values``: the panel has room for values or a few lines of text from the start (a
    program may show them mid-episode), else only for what each episode starts with (a player).
    """

    def __init__(self, renderer: RgbRenderer, animation_frames: int = 4, fps: float = 4.0, pixel_ratio: int = PIXEL_RATIO,
                 fit: bool = False, reserve_values: bool = True):  # fmt: skip
        from ipycanvas import MultiCanvas
        from ipywidgets import Box

        self.renderer = renderer
        self.animation_frames = check_animation_frames(animation_frames)
        self.fps = check_fps(fps, "fps")
        if isinstance(pixel_ratio, bool) or pixel_ratio not in (1, 2):
            raise ValueError(f"pixel_ratio: must be 1 or 2, got {pixel_ratio!r}")
        self.ratio, self.fit, self.reserve_values = pixel_ratio, bool(fit), bool(reserve_values)
        css_cell = fit_cell_size(renderer.level) if self.fit else renderer.cell_size
        same = css_cell * pixel_ratio == renderer.cell_size and renderer.panel_ratio == pixel_ratio
        self.hi = renderer if same else RgbRenderer(renderer.level, css_cell * pixel_ratio, renderer.theme, pixel_ratio)
        self.width, self.grid_height = self.hi.width // self.ratio, self.hi.grid_height // self.ratio  # CSS pixels
        self.widget = MultiCanvas(3, width=self.hi.width, height=self.hi.grid_height)
        self.box = Box([self.widget])  # the canvas cropped to its picture (``crop``): what is shown
        self.shown = self.hi.grid_height  # the backing store's rows the page shows
        self.scene = Scene()
        self.overlay = Overlay()
        self.frames_sent = 0  # hold_canvas batches sent (tests, benchmarks)
        self._static: np.ndarray | None = None  # what layer 0 shows
        self._goals: tuple = ()  # the robots' own targets layer 0 shows (``Scene.goals``)
        self._drawn: list[tuple] | None = None  # the keys of the panel's pieces on layer 2
        self.pacer = Pacer()  # when the next robot frame is due; frames dropped when late
        self._still: Still | None = None  # the still shown with the canvas (``show``)
        self.view: Any = self.widget  # what ``show`` displays: the canvas, and the replay bar under it
        self._replay: Any = None  # the replay bar (``show``)
        self.history: deque[tuple[Scene, Overlay]] = deque(maxlen=MAX_REPLAY)  # this episode's scenes
        self._replaying: int | None = None  # the scene of ``history`` shown by the replay bar (None: the live one)
        self._styles = _Styles()
        self._snapped: tuple[Scene, Overlay] | None = None  # what the still shows
        self.marked: int | None = None  # the robot whose cell is framed in its colour (the one a player drives)
        # each layer is its own canvas in the browser, ready in its own time: each ready one has the
        # picture drawn again, and once more a moment later (a reloading page may drop the first
        # commands: the widget that carries them to the layers is not always ready before them)
        for k, layer in enumerate(self.widget._canvases):
            layer.on_client_ready(lambda *_, k=k: self._on_ready(lambda: self._show(*self._shown(), layer=k)))
        self._redraw_due = False
        self._batched = False  # inside ``_resize``: every layer's commands in its one batch
        shown = self.hi.grid_height + self._reserved(self.scene)
        self._set_height(self._backing(shown), shown)
        self._draw_static(fresh=True)
        self._draw_top()

    # ------------------------------------------------------------------ public
    @property
    def css(self) -> str:
        """The CSS of the canvas's size (its still has the same)."""
        if self.fit:
            return f"width: {FIT_SHARE}; max-width: {self._max_width()}; height: auto"
        return f"width: {self.width}px; max-width: {NARROW_FIT}; height: auto"

    def show(self) -> None:
        """Display the canvas in the current notebook cell, with a still of its frame for saved notebooks
        and a replay bar (shown when an episode ends)."""
        from ipywidgets import VBox

        self.view = VBox([self.box, self.replay_bar().widget])
        self._still = Still(self.view, self.picture, self.css, self.ratio)
        self._snapped = (self.scene, self.overlay)
        self._still.show()
        _track(self)

    def replay_bar(self) -> Any:
        """A new replay bar (``replay.ReplayBar``: slider and play button) for this canvas: the one it
        offers each finished episode to, shown under it by ``show`` (or by a player)."""
        from .replay import ReplayBar

        self._replay = ReplayBar(self)
        return self._replay

    def snapshot(self, only_if_changed: bool = False) -> None:
        """Refresh the still shown with the canvas (the frame ``rgb_array`` gives for the same
        state, at the canvas's resolution); done when an episode ends, when the env closes and
        after each notebook cell."""
        if self._still is None or (only_if_changed and self._snapped == (self.scene, self.overlay)):
            return
        self._snapped = (self.scene, self.overlay)
        self._still.css = self.css
        self._still.refresh()

    def offer_replay(self) -> None:
        """The replay bar offered for the scenes drawn so far, if it is not already (a notebook
        cell that ran a few steps of an episode, not to its end, then finished)."""
        bar, n = self._replay, len(self.history)
        if bar is not None and n >= 2 and (bar.widget.layout.display == "none" or bar.slider.max != n - 1):
            bar.offer(n)

    def frame(self) -> np.ndarray:
        """The ``rgb_array`` frame of what the canvas shows."""
        return self.renderer.frame(self.scene, self.overlay)

    def picture(self) -> np.ndarray:
        """What the canvas shows, at its backing store's resolution (the panel's reserved strip included)."""
        img = self.hi.frame(self.scene, self.overlay)
        for f in marked_frame(self.hi, self.scene, self.marked):  # axis-aligned bars: painted as they are
            (x0, y0), (x1, y1) = f.points.min(axis=0).astype(int), f.points.max(axis=0).astype(int)
            img[y0:y1, x0:x1] = f.colour
        img = img[: self.shown]
        if img.shape[0] < self.shown:
            pad = np.empty((self.shown - img.shape[0], *img.shape[1:]), dtype=np.uint8)
            pad[:] = self.hi.theme.panel
            img = np.concatenate([img, pad])
        return img

    def draw(self, robots: Scene | Sequence[Cell | None], overlay: Overlay | None = None, animate: bool = True) -> None:
        """Show ``robots`` (a ``Scene``, or robot ``i`` at ``robots[i]``), gliding from where they
        came from unless ``animate`` is False; redraw the overlay and panel if they changed. The
        panel (the race's legend) changes with the frame that shows the robots where they end."""
        scene = as_scene(robots)
        self.renderer.check_frame(overlay or self.overlay, scene)  # the whole frame within the limit: nothing drawn else
        self._goals = scene.goals  # the robots' own targets: on the bottom layer
        if overlay is not None:
            self.set_overlay(overlay, self.scene, top=False)
        self._sync_static()  # a replay may have left another overlay's cells there
        if not self.history:  # an episode's first frame: the panel's room for the whole episode
            self._grow(self.hi.grid_height + self._reserved(scene), scene)
        self.scene, self._replaying = scene, None
        steps = self.animation_frames if animate else 0
        if steps == 0 or not glide(scene, 0.0)[0]:  # nobody moved (or a reset's first frame)
            # a reset's frame stays one frame's time too: else the first step followed at once, the start unseen
            step = 1.0 / self.fps if self.fps > 0 else 0.0
            self.pacer.wait(step if animate else step / max(1, self.animation_frames))
            self._draw_robots(scene)
        else:
            interval = 1.0 / (self.fps * steps) if self.fps > 0 else 0.0
            self.pacer.start_step()
            for k in range(1, steps + 1):
                if k < steps and self.pacer.late(interval):
                    continue  # behind the clock: this in-between frame dropped, never the step's last
                self.pacer.wait(interval)
                at, poses = glide(scene, k / steps, self.hi.labelled, self.hi.label_top)
                self._draw_robots(scene, at, poses)
        self._draw_top()
        self._record(scene)
        if scene.done:
            self.snapshot()

    def new_episode(self) -> None:
        """Forget the replay of the episode before (an env's reset)."""
        self.history.clear()
        self._replaying = None
        if self._replay is not None:
            self._replay.hide()

    def replay(self, index: int) -> None:
        """Show the episode's ``index``-th scene (0: its start) as it was drawn; the env is not stepped."""
        self._replaying = index
        self._show(*self.history[index])

    def _shown(self) -> tuple[Scene, Overlay]:
        """What the canvas shows: the scene the replay bar points at, else the live one."""
        if self._replaying is not None and self._replaying < len(self.history):
            return self.history[self._replaying]
        return self.scene, self.overlay

    def _show(self, scene: Scene, overlay: Overlay, force: bool = False, layer: int | None = None) -> None:
        """``scene`` under ``overlay`` (a replayed one), the live overlay kept; ``force``: every layer
        again; ``layer``: that layer alone, again (0: the level, 1: the robots, 2: labels and panel)."""
        live, self.overlay = self.overlay, overlay
        goals, self._goals = self._goals, scene.goals
        again = force or layer is not None
        try:
            if layer in (None, 0):
                self._draw_static(fresh=True) if again else self._sync_static()
            if layer in (None, 2):
                self._draw_top(scene, force=again)  # before the robots: a taller panel redraws the live ones
            if layer in (None, 1):
                self._draw_robots(scene)
        finally:
            self.overlay, self._goals = live, goals

    def set_overlay(self, overlay: Overlay, scene: Scene | None = None, top: bool = True) -> None:
        """Show ``overlay``: the bottom layer again if its cells changed, the panel if it did."""
        if overlay is self.overlay:
            return
        self.renderer.check_frame(overlay, scene or self.scene)
        self.overlay = overlay
        self._sync_static()
        if top:
            self._draw_top(scene)

    def _record(self, scene: Scene) -> None:
        if not self.history or self.history[-1] != (scene, self.overlay):
            self.history.append((scene, self.overlay))
        if scene.done and self._replay is not None:
            self._replay.offer(len(self.history))

    def _on_ready(self, draw: Any) -> None:
        draw()
        if self._redraw_due:
            return
        try:
            import asyncio

            loop = asyncio.get_running_loop()  # the kernel's, running the comm message handlers
        except RuntimeError:  # no running loop (not in a kernel): nothing to wait for
            return
        self._redraw_due = True

        def again() -> None:
            self._redraw_due = False
            self.redraw()

        loop.call_later(REDRAW_AFTER, again)

    def redraw(self, *_: Any) -> None:
        """Everything again (a browser connected: it starts from an empty canvas), as it was shown:
        the replayed scene while the replay bar points at one (a late redraw must not undo a replay)."""
        self._show(*self._shown(), force=True)

    # ------------------------------------------------------------------ layers
    def _reserved(self, scene: Scene) -> int:
        """The panel's height kept for an episode that starts with ``scene`` (``panel_room``)."""
        return panel_room(self.hi, self.overlay, scene.legend, self.ratio, RESERVED_LINES if self.reserve_values else 0)

    def _backing(self, shown: int) -> int:
        """``shown`` rows and spare ones when a program may add lines mid-episode (``reserve_values``)."""
        return backing_height(shown, self.hi.cell_size, self.ratio, SPARE_LINES if self.reserve_values else 0)

    def _grow(self, height: int, scene: Scene) -> None:
        """The picture made ``height`` pixels tall if it is less (never shrinks): by CSS, else a resize."""
        if height > self.widget[0].height:
            self._resize(height, lambda: self._draw_top(scene, force=True), scene)
        elif height > self.shown:
            self._crop(height)

    def _set_height(self, backing: int, shown: int) -> None:
        """The backing store's height (resizing clears every layer) and the CSS that shows its top
        ``shown`` rows: the height follows the width, so a canvas in a narrow column scales down
        whole. The height is sent last: the caller's batch of commands follows it at once (``_resize``)."""
        self.widget.layout.width, self.widget.layout.height = "100%", "auto"
        self.widget.layout.align_self = "flex-start"  # its own height, not its box's
        self.box.layout.overflow, self.box.layout.border = "hidden", FRAME
        self.box.layout.align_self = "flex-start"  # in a row of widgets: its own height, not the row's
        self._crop(shown, backing)
        self.widget.height = backing

    def _crop(self, shown: int, backing: int | None = None) -> None:
        """The page shows the backing store's top ``shown`` rows (a CSS change: nothing is cleared)."""
        self.shown = shown
        self.box.layout.width = f"{self.width + 2 * FRAME_PX}px" if not self.fit else FIT_SHARE  # border-box: + the frame
        self.box.layout.max_width = self._max_width(shown) if self.fit else NARROW_FIT
        self.widget.layout.margin = crop_margin(backing or self.widget.height, shown, self.hi.width)

    def _max_width(self, height: int | None = None) -> str:
        """A fitted canvas's widest: its backing store's (never blurred up) and, for a tall level,
        what keeps it within ``FIT_VIEW`` percent of the window's height (``height``: the shown rows')."""
        return f"min({self.width}px, calc({FIT_VIEW}vh * {self.hi.width / (height or self.shown):.4f}))"

    def _hold(self) -> Any:
        """One batch of canvas commands (one message); inside ``_resize``'s batch, that one."""
        from contextlib import nullcontext

        from ipycanvas import hold_canvas

        if self._batched:
            return nullcontext()
        self.frames_sent += 1
        return hold_canvas()

    def _sync_static(self) -> None:
        """Layer 0 again if it does not show the overlay's cells."""
        if self._static is None or self.hi.static(self.overlay, self._goals) is not self._static:
            self._draw_static()

    def _draw_static(self, fresh: bool = False) -> None:
        """Layer 0: the level under the overlay; ``fresh``: the browser's layer may be empty (a new,
        resized or reconnected canvas), see ``put_picture``."""
        img = self._static = self.hi.static(self.overlay, self._goals)
        with self._hold():
            put_picture(self.widget[0], img, fresh)

    def _draw_top(self, scene: Scene | None = None, force: bool = False) -> None:
        """Labels and panel (layer 2): only the strips of the panel whose content changed (a
        legend row's return, say), everything when the canvas's height changed or ``force``.
        The picture never shrinks; a taller one is shown once its panel is drawn."""
        from .annotate import value_range
        from .panel import panel_sections, shifted

        scene = scene or self.scene
        r = self.hi
        sections = panel_sections(r.width, r.cell_size, r.theme, self.overlay.panel, value_range(self.overlay),
                                  scene.legend, self.ratio)  # fmt: skip
        need, height = r.grid_height + sum(sec.height for sec in sections), self.widget[0].height
        if need > height:
            self._resize(need, lambda: self._draw_top(scene, force=True), scene)
            return
        drawn = self._drawn if not force else None
        if force or drawn is None:
            self._styles.reset()
        ops: list[Op] = [] if drawn is not None else [Fill(_rect(0, r.grid_height, r.width, height), r.theme.panel), *r.labels]
        now: list[tuple] = []
        y = r.grid_height
        for k, sec in enumerate(sections):
            old = drawn[k] if drawn is not None and k < len(drawn) else None
            pieces = sec.parts or ((0, r.width, sec.key, sec.build),)
            keys = tuple(part[2] for part in pieces)
            now.append(keys)
            for j, (x0, x1, key, build) in enumerate(pieces):
                if old is not None and len(old) == len(keys) and old[j] == key:
                    continue  # this piece shows already
                ops.append(Fill(_rect(x0, y, x1, y + sec.height), sec.background))
                ops += [shifted(op, y) for op in build()]
            y += sec.height
        if drawn is not None and len(drawn) > len(now) and y < height:  # strips gone: their place blank
            ops.append(Fill(_rect(0, y, r.width, height), r.theme.panel))
        self._drawn = now
        if ops:
            with self._hold():
                if drawn is None:
                    self.widget[2].clear()
                _send(self.widget[2], ops, self._styles)
        if need > self.shown and not self._batched:  # drawn first: the rows shown next hold the panel
            self._crop(need)

    def _resize(self, shown: int, draw_top: Any, scene: Scene) -> None:
        """A taller canvas showing ``shown`` rows (``crop``), never shown empty. The browser clears
        a canvas it resizes; the page shows the ``MultiCanvas``'s own canvas, which it redraws from the layers after each batch
        of commands. So: the layers first (the page still shows the picture before), every layer
        drawn at the new height in one message (the level's rectangles computed before), then the
        shown canvas and, sent right after it, a small batch made before it: the browser composes
        the layers into the canvas again after each batch.
        ``draw_top``: the labels and panel, drawn at the new height."""
        height = self._backing(shown)
        img = self.hi.static(self.overlay, self._goals)
        put = picture_calls(img, fresh=True)
        for layer in self.widget._canvases:
            layer.height = height
        with self._hold():
            self._batched = True
            try:
                put(self.widget[0])
                self._static = img
                self._draw_robots(scene)
                draw_top()
            finally:
                self._batched = False
        with self._hold():  # the robots' batch made first, sent right after the resize: the browser
            self._batched = True  # composes every layer into the resized canvas after it
            try:
                self._draw_robots(scene)
                self._set_height(height, shown)
            finally:
                self._batched = False

    def _draw_robots(self, scene: Scene, at: dict[int, tuple[float, float]] | None = None,
                     poses: dict[int, str] | None = None) -> None:  # fmt: skip
        layer = self.widget[1]
        sprites = robot_sprites(scene, self.hi.cell_size, self.hi.theme, poses, at, self.hi.labelled)
        marks = marked_frame(self.hi, scene, self.marked)
        with self._hold():
            layer.clear()
            if marks:
                _send(layer, marks, self._styles)
            if not sprites:
                return
            # the polygons of all robots in one call (drawn in order), then their numbers
            layer.fill_styled_polygons(
                np.concatenate([s.points + (x, y) for s, x, y in sprites]),
                np.concatenate([s.colours for s, _, _ in sprites]),
                np.concatenate([s.alphas for s, _, _ in sprites]),
                points_per_polygon=np.concatenate([s.counts for s, _, _ in sprites]),
            )
            texts = [Text(t.x + x, t.y + y, t.text, t.size, t.colour, t.align, t.baseline, t.alpha)
                     for s, x, y in sprites for t in s.texts]  # fmt: skip
            _send(layer, texts, self._styles)
