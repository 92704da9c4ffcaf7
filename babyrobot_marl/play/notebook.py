"""Play Baby Robot and build levels in a Jupyter notebook (needs the ``notebook`` extra).

::

    from babyrobot_marl.play import notebook
    notebook.play("walls")                    # one robot: buttons, or click the grid and use the arrow keys
    notebook.play("race-4", policies="shortest")  # a race: you drive robot_0, TAB drives the next one
    editor = notebook.edit((6, 4))            # click cells and edges; editor.level, editor.text

``play`` returns a ``Player`` (the live canvas, buttons, keys), ``edit`` an ``Editor``.
ipycanvas and ipywidgets are imported when ``play`` or ``edit`` is called, not before. Both
objects display themselves in a cell, and can be driven from Python too
(``player.press("ArrowUp")``, ``editor.click_cell((1, 2))``), which is what a test without a
browser does.

Keys reach the canvas once it has the focus (click it; a blue frame shows it has): arrows or
WASD move, space stays, ``r`` restarts, TAB drives the next robot of a race (the driven robot's
cell is framed in its colour). Each widget is shown with a still of its picture
(``render.still``): a saved notebook reopened with a new kernel shows it.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from types import SimpleNamespace
from typing import Any

from .. import policies as policy_lib
from ..core.actions import Action
from ..core.level import Level
from ..envs.keys import BROWSER_KEYS, RESTART, SWITCH, Command
from ..envs.race import RaceEnv
from ..envs.single import BabyRobotEnv
from ..levels.resolve import resolve_level
from ..render.canvas import FIT_SHARE, LiveCanvas, fit_cell_size
from ..render.rgb import RgbRenderer
from ..render.still import NARROW_FIT, Still
from ..render.transfer import put_picture
from . import editor as ed
from .checks import check_keywords, check_robots
from .game import RaceGame, SingleGame, ordinal

PLAY_ARGS = ("robots", "policies", "seed", "cell_size", "theme")
EDIT_ARGS = ("race", "cell_size", "theme")


def play(env_or_level: Any = "default", **kwargs: Any) -> Player:
    """Play a level (a name, a level text or a ``Level``) or an env (``BabyRobotEnv``, ``RaceEnv``):
    the live canvas with move, stay and reset buttons, keys when the canvas has the focus, and a panel
    of steps and returns. Keywords: ``robots`` (a race of that many; default: the level's starts),
    ``policies`` of the robots you do not drive (``"random"`` or ``"shortest"``, one or one per robot),
    ``seed``, ``cell_size``, ``theme``."""
    check_keywords("play", kwargs, PLAY_ARGS)
    return Player(env_or_level, **kwargs)


def edit(level_or_size: Any = (5, 5), **kwargs: Any) -> Editor:
    """The level editor, on a blank ``(width, height)`` grid or on a level to change. Keywords: ``race``
    (numbered starts), ``cell_size``, ``theme``. ``.level`` and ``.text`` give the result; "play it" plays it."""
    check_keywords("edit", kwargs, EDIT_ARGS)
    return Editor(level_or_size, **kwargs)

FOCUS = "#1c7ed6"  # the frame of a canvas that has the keys
FOCUS_STYLE = (  # a canvas (or the element in it) with the focus is framed: the keys go to it
    # inside its box: an outline outside it is cut off where the output area clips its content
    "<style>.babyrobot-keys:focus, .babyrobot-keys:focus-within, .babyrobot-keys canvas:focus"
    f" {{outline: 3px solid {FOCUS}; outline-offset: -3px}}</style>"
)

NOTEBOOK_OVER_HINT = "r or reset plays again; the slider under the buttons replays it"

BUTTONS = (  # (label, command, css class): the class names stable selectors for tests
    ("\u2190", Action.WEST, "west"), ("\u2191", Action.NORTH, "north"), ("\u2193", Action.SOUTH, "south"),
    ("\u2192", Action.EAST, "east"), ("stay", Action.STAY, "stay"), ("reset", RESTART, "reset"),
)  # fmt: skip


def make_game(
    env_or_level: Any = "default", robots: int | None = None, policies: str | Sequence[str] = "random", seed: int | None = None
) -> SingleGame | RaceGame:
    """A game from an env (``BabyRobotEnv``, ``RaceEnv``, or a wrapper of one) or a level (name, text,
    ``Level``): one robot, or a race of ``robots`` (default: the level's starts, when it has several)."""
    robots = check_robots(robots)
    env = getattr(env_or_level, "unwrapped", env_or_level)
    if getattr(env, "render_mode", None) == "human":
        raise ValueError("env: render_mode='human' draws a canvas of its own at every step; "
                         "pass an env made without render_mode, or its level, to play it here")
    if not isinstance(env, (BabyRobotEnv, RaceEnv)):
        level = resolve_level(env_or_level)
        n = robots if robots is not None else max(len(level.starts), 1)
        env = BabyRobotEnv(level=level) if n == 1 else RaceEnv(level=level, n_robots=n, start="fill")
    elif robots is not None and robots != getattr(env, "n_robots", 1):
        raise ValueError(f"robots: the env given has {getattr(env, 'n_robots', 1)} robot(s); leave robots out or pass a level")
    if isinstance(env, BabyRobotEnv):
        return SingleGame(env, seed)
    n = env.n_robots
    names = [policies] * n if isinstance(policies, str) else list(policies)
    if len(names) != n:
        raise ValueError(f"policies: give one policy for all robots or one per robot ({n}), got {len(names)}")
    pols = [policy_lib.make(p, env.table, None if seed is None else seed + 7919 * (i + 1)) for i, p in enumerate(names)]
    return RaceGame(env, pols, driven=0, seed=seed, switchable=True)


class Player:
    """The game on a live canvas, with buttons for the moves, stay and reset (and the next robot in a race),
    keys when the canvas has the focus, and a panel of steps and returns. ``widget`` is what is shown."""

    def __init__(
        self,
        env_or_level: Any = "default",
        robots: int | None = None,
        policies: str | Sequence[str] = "random",
        seed: int | None = None,
        cell_size: int | None = None,
        theme: str = "light",
    ):
        from ipywidgets import HTML, Button, HBox, Layout, VBox

        self.game = make_game(env_or_level, robots, policies, seed)
        self.game.over_hint = NOTEBOOK_OVER_HINT
        if isinstance(self.game, RaceGame):
            self.game.labels = lambda i: f"#{i}"  # the canvas numbers its robots 0, 1, ...
        self.level: Level = self.game.env.level
        renderer = RgbRenderer(self.level, cell_size, theme)
        self.canvas = LiveCanvas(renderer, animation_frames=0, fps=0, fit=cell_size is None, reserve_values=False)
        self.canvas.widget.on_key_down(self._on_key)
        self.canvas.widget.add_class("babyrobot-keys")
        buttons = []
        specs = list(BUTTONS) + ([("next robot (TAB)", SWITCH, "switch")] if self.is_race else [])
        for label, cmd, name in specs:
            b = Button(description=label, layout=Layout(width="auto" if len(label) > 1 else "40px"))
            b.add_class(f"babyrobot-{name}")
            b.on_click(lambda _b, cmd=cmd: self.command(cmd))
            buttons.append(b)
        self.panel = HTML()
        self.panel.add_class("babyrobot-panel")
        hint = HTML(FOCUS_STYLE + "<small>click the picture (a blue frame shows it has the keys), then: "
                    "arrows/WASD move, space stays, r restarts"
                    + (", TAB drives the next robot (its cell framed in its colour)" if self.is_race else "")
                    + "</small>")  # fmt: skip
        self.replay = self.canvas.replay_bar()  # shown when an episode ends
        self._steps = -1  # the game's step count drawn last: less now, a new episode
        self.widget = VBox([self.canvas.box, HBox(buttons), self.replay.widget, hint, self.panel])
        self.widget.add_class("babyrobot-player")
        self.still = Still(self.widget, self.canvas.picture, self.canvas.css)
        self._refresh()

    @property
    def is_race(self) -> bool:
        return isinstance(self.game, RaceGame)

    def _ipython_display_(self) -> None:
        """Shown in a cell: the widget, and a still of its picture for the saved notebook."""
        self.still.show()

    # ------------------------------------------------------------------ input
    def _on_key(self, key: str, shift: bool = False, ctrl: bool = False, meta: bool = False) -> None:
        if ctrl or meta:
            return  # the browser's shortcuts are not game keys
        self.command(BROWSER_KEYS.get(key))

    def press(self, key: str) -> None:
        """A key by its browser name (``"ArrowUp"``, ``"w"``, ``" "``, ``"r"``, ``"Tab"``), as if typed on the canvas."""
        self._on_key(key)

    def command(self, cmd: Command | None) -> None:
        self.game.command(cmd)
        self._refresh()

    # ------------------------------------------------------------------ output
    def _refresh(self) -> None:
        g = self.game
        if self.is_race:  # the legend over the grid says who is who: you, and the others' policies
            names = ["you" if i == g.driven else getattr(p, "name", "policy") for i, p in enumerate(g.policies)]
            if names != getattr(self, "_names", None):
                g.env.set_overlay(names=names)
                self._names = names
        # the env's own scene (poses, bumps, finished robots at their exits), as render_mode="human" draws it
        scene = g.env._scene() if hasattr(g.env, "_scene") else g.robots
        self.canvas.marked = g.driven if self.is_race else None
        steps = g.steps
        if steps < self._steps:  # restarted: the replay is of the episode from now on
            self.canvas.new_episode()
        self._steps = steps
        self.canvas.draw(scene, g.env.overlay, animate=False)
        self.panel.value = "<pre style='margin:0'>" + html.escape(self.text) + "</pre>"
        self.still.refresh()

    @property
    def text(self) -> str:
        """The panel as plain text: steps, returns, the last move, and where each robot is."""
        g = self.game
        lines = list(g.status())
        if self.is_race:
            others = ", ".join(f"{g.glyph(i)} {getattr(p, 'name', 'policy')}" for i, p in enumerate(g.policies) if i != g.driven)
            lines.insert(1, f"you drive {g.glyph(g.driven)} (robot_{g.driven}); the others: {others}")
        return "\n".join([*lines, *where(g)])


def where(game: SingleGame | RaceGame) -> list[str]:
    """Where the robots are, in words: one line each (a race), or Baby Robot's line."""
    if isinstance(game, SingleGame):
        x, y = game.robots[0]
        return [f"Baby Robot is at column {x}, row {y}"]
    ranks = game.env.ranks
    out = []
    for i, cell in enumerate(game.robots):
        who = f"{game.glyph(i)}" + (" (you)" if i == game.driven else "")
        if ranks[i]:
            out.append(f"{who} finished {ordinal(ranks[i])}")
        elif cell is None:
            out.append(f"{who} is out of the race")
        else:
            out.append(f"{who} is at column {cell[0]}, row {cell[1]}")
    return out


# ---------------------------------------------------------------------- the level editor
ERROR = "#e03131"  # the outline of the cell a message points at
OK = "#2b8a3e"


class Editor:
    """Click a cell to cycle floor, small puddle, large puddle, blocked, start, exit (or click it and
    press a key: E exit, S start, B blocked, p / P puddles, F or space floor); click between two
    cells to cycle open, wall, glass. Width and height boxes resize. The level is drawn as the game
    draws it (same renderer and theme, two device pixels per CSS pixel); under it, what is missing in
    plain words (the cell at fault outlined). ``level`` and ``text`` give the result; "play it" opens
    it in a ``Player`` below, which follows every edit."""

    def __init__(self, level_or_size: Any = (5, 5), race: bool | None = None, cell_size: int | None = None,
                 theme: str = "light"):  # fmt: skip
        from ipycanvas import Canvas
        from ipywidgets import HTML, BoundedIntText, Button, Checkbox, HBox, Layout, VBox

        if isinstance(level_or_size, tuple) and len(level_or_size) == 2:
            self.draft = ed.blank(*level_or_size, race=bool(race))
        else:
            self.draft = ed.from_level(resolve_level(level_or_size))
            if race is not None:
                self.draft = ed.with_race(self.draft, race)
        # without a cell size, the canvas fills the column as the game's canvas does (fitted cells)
        self.fit, self._cell_size, self.theme, self.ratio = cell_size is None, int(cell_size or 0), theme, 2
        self.player: Player | None = None
        self._playing = False  # "play it" was clicked: a player follows the edits
        self._syncing, self._bad_cell, self._selected = False, None, None
        self._image = None
        self._drawn = False  # the canvas has had a picture
        w, h = ed.size(self.draft)
        self.canvas = Canvas(width=w * self.cell_size * self.ratio, height=h * self.cell_size * self.ratio)
        self.canvas.add_class("babyrobot-keys")
        # the mouse is reported in the backing store's pixels: the editor thinks in CSS pixels
        self.canvas.on_mouse_down(lambda x, y: self.click(x / self.ratio, y / self.ratio))
        self.canvas.on_key_down(self._on_key)
        self.canvas.on_client_ready(lambda *_: self._draw(fresh=True))
        box = Layout(width="150px")
        self.width_box = BoundedIntText(value=w, min=1, max=ed.MAX_SIDE, description="width", layout=box)
        self.height_box = BoundedIntText(value=h, min=1, max=ed.MAX_SIDE, description="height", layout=box)
        self.width_box.observe(self._on_size, "value")
        self.height_box.observe(self._on_size, "value")
        self.race_box = Checkbox(value=ed.is_race(self.draft), description="race (numbered starts)")
        self.race_box.observe(lambda ch: self._set(ed.with_race(self.draft, ch["new"])), "value")
        self.play_button = Button(description="play it")
        self.play_button.add_class("babyrobot-play-it")
        self.play_button.on_click(lambda _b: self.play())
        self.verdict = HTML()
        self.verdict.add_class("babyrobot-verdict")
        self.text_view = HTML()
        self.text_view.add_class("babyrobot-level-text")
        self.player_box = VBox()
        hint = HTML(FOCUS_STYLE + "<small>click a cell to change it (or click it, then press E exit, S start, "
                    "B blocked, P puddle, F floor); click the line between two cells: wall, glass, open</small>")  # fmt: skip
        controls = HBox([self.width_box, self.height_box, self.race_box, self.play_button])
        drawing = [self.canvas, self.text_view] if self.fit else [HBox([self.canvas, self.text_view])]
        self.widget = VBox([controls, *drawing, hint, self.verdict, self.player_box])
        self.widget.add_class("babyrobot-editor")
        self.still = Still(self.widget, self.picture)
        self._set(self.draft)

    def _ipython_display_(self) -> None:
        """Shown in a cell: the widget, and a still of the level drawn for the saved notebook."""
        self.still.show()

    # ------------------------------------------------------------------ results
    @property
    def cell_size(self) -> int:
        """The cells' size in CSS pixels: the one given, else the fitted one for the draft's size."""
        if not self.fit:
            return self._cell_size
        w, h = ed.size(self.draft)
        return fit_cell_size(SimpleNamespace(width=w, height=h))

    @property
    def text(self) -> str:
        """The level text drawn so far (valid or not)."""
        return ed.text(self.draft)

    @property
    def level(self) -> Level:
        """The level drawn; the parser's ValueError if the drawing is not a valid level yet."""
        return Level.from_ascii(self.text)

    # ------------------------------------------------------------------ edits
    def click(self, px: float, py: float) -> None:
        """A click at ``(px, py)`` CSS pixels: a cell or an edge changes; the border and corners do nothing."""
        w, h = ed.size(self.draft)
        target = ed.hit(px, py, self.cell_size, w, h)
        if target is None:
            return
        if target[0] == "cell":
            self.click_cell(target[1])
        else:
            self.click_edge(target[1], target[2])

    def click_cell(self, cell: tuple[int, int]) -> None:
        self._selected = cell
        self._set(ed.cycle_cell(self.draft, cell, self.race_box.value))

    def click_edge(self, a: tuple[int, int], b: tuple[int, int]) -> None:
        self._set(ed.cycle_edge(self.draft, a, b))

    def press(self, key: str) -> None:
        """A key by its browser name, as if typed on the canvas: it sets the cell clicked last."""
        self._on_key(key)

    def resize(self, width: int, height: int) -> None:
        self._selected = None
        self._set(ed.resize(self.draft, width, height))

    def play(self, **kwargs: Any) -> Player | None:
        """Open the level in a ``Player`` under the editor (None, with the verdict, if it is not valid);
        from then on the player follows every edit."""
        self._playing, self._play_args = True, kwargs
        level, _, _ = ed.verdict(self.draft)
        if level is None:
            return None
        self.player = Player(level, **kwargs)
        self.player_box.children = (self.player.widget,)
        return self.player

    def _on_key(self, key: str, shift: bool = False, ctrl: bool = False, meta: bool = False) -> None:
        kind = ed.KEY_KINDS.get(key, ed.KEY_KINDS.get(key.lower()) if len(key) == 1 else None)
        if ctrl or meta or kind is None or self._selected is None:
            return
        if key == "p" and shift:
            kind = "P"
        self._set(ed.set_cell(self.draft, self._selected, kind, self.race_box.value))

    def _on_size(self, _change: dict) -> None:
        if not self._syncing:
            self.resize(int(self.width_box.value), int(self.height_box.value))

    def _set(self, draft: ed.Draft) -> None:
        from ipywidgets import HTML

        before, self.draft = self.draft, draft
        w, h = ed.size(draft)
        self._syncing = True  # the boxes show the draft's size without resizing it again
        try:
            self.width_box.value, self.height_box.value = w, h
        finally:
            self._syncing = False
        level = ed.verdict(draft)[0]
        moved = ed.moved_start(before, draft)  # said, not done silently
        message, self._bad_cell = ed.advice(draft)
        colour = OK if level is not None else ERROR
        shown = f"{moved}\n{message}" if moved else message
        self.verdict.value = f"<pre style='margin:0;color:{colour}'>" + html.escape(shown) + "</pre>"
        self.text_view.value = "<pre style='margin:0 0 0 12px'>" + html.escape(self.text) + "</pre>"
        self.play_button.disabled = level is None
        self._image = None
        self._draw()
        if self._playing:  # the player below plays the level as it is now
            if level is not None:
                self.play(**self._play_args)
            else:
                self.player = None
                self.player_box.children = (HTML("<small>the player comes back when the level is ready (see above)</small>"),)
        self.still.refresh()

    def picture(self) -> Any:
        """The level as the game draws it (at two device pixels per CSS pixel), the cell at fault
        outlined in red and the cell clicked last framed in blue."""
        import numpy as np

        if self._image is None:
            cs = self.cell_size * self.ratio
            img = RgbRenderer(ed.sketch(self.draft), cs, self.theme).frame(())
            t = max(3, cs // 16)
            for cell, colour in ((self._selected, FOCUS), (self._bad_cell, ERROR)):
                if cell is not None:
                    x0, y0 = cell[0] * cs + t, cell[1] * cs + t
                    rgb = np.array([int(colour[k : k + 2], 16) for k in (1, 3, 5)], dtype=np.uint8)
                    img[y0 : y0 + t, x0 : x0 + cs - 2 * t] = rgb
                    img[y0 + cs - 3 * t : y0 + cs - 2 * t, x0 : x0 + cs - 2 * t] = rgb
                    img[y0 : y0 + cs - 2 * t, x0 : x0 + t] = rgb
                    img[y0 : y0 + cs - 2 * t, x0 + cs - 3 * t : x0 + cs - 2 * t] = rgb
            self._image = img
        return self._image

    def _draw(self, fresh: bool = False) -> None:
        """The picture on the canvas; ``fresh``: the browser's canvas may be empty (see ``put_picture``)."""
        from ipycanvas import hold_canvas

        img = self.picture()
        c = self.canvas
        h, w = img.shape[:2]
        with hold_canvas():
            resized = (c.width, c.height) != (w, h)  # resizing clears the browser's canvas
            if resized:
                c.width, c.height = w, h
            # the height follows the width: a narrow column shows the whole level scaled down
            if self.fit:  # as the game's fitted canvas: 90% of the column, never wider than its pixels
                c.layout.width, c.layout.max_width, c.layout.height = FIT_SHARE, f"{w // self.ratio}px", "auto"
            else:
                c.layout.width, c.layout.max_width, c.layout.height = f"{w // self.ratio}px", NARROW_FIT, "auto"
            c.layout.align_self = "flex-start"  # beside the editor's tools: its own height, not the row's
            put_picture(c, img, fresh=fresh or resized or not self._drawn)
        self._drawn = True
