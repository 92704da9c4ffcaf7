"""The notebook player and editor driven from Python (no browser): keys, buttons, TAB, the panel, clicks."""

from __future__ import annotations

import pytest

pytest.importorskip("ipycanvas")
pytest.importorskip("ipywidgets")

from babyrobot_marl import BabyRobotEnv, race_v0  # noqa: E402
from babyrobot_marl.core.actions import Action  # noqa: E402
from babyrobot_marl.play import notebook  # noqa: E402
from babyrobot_marl.play.game import RaceGame, SingleGame  # noqa: E402
from babyrobot_marl.policies import ShortestPathPolicy  # noqa: E402


def drawn(player) -> list:
    """Where the canvas shows each robot, by robot number."""
    return [v.cell for v in sorted(player.canvas.scene.robots, key=lambda v: v.number)]


def _button(player, name):
    return next(b for b in player.widget.children[1].children if f"babyrobot-{name}" in b._dom_classes)


def test_keys_and_buttons_move_the_robot_on_the_canvas_and_the_panel_follows():
    p = notebook.play("default", seed=0)
    assert isinstance(p.game, SingleGame) and drawn(p) == [(0, 0)]
    p.press("ArrowRight")
    _button(p, "east").click()
    p.press("s")
    _button(p, "south").click()
    assert drawn(p) == [(2, 2)] and p.game.terminated
    assert "reached the exit in 4 steps, return -3" in p.text
    p.press("ArrowLeft")  # after the end: nothing moves
    assert drawn(p) == [(2, 2)] and "the episode is over" in p.text
    _button(p, "reset").click()
    assert drawn(p) == [(0, 0)] and p.game.steps == 0
    p.press("w")
    assert "NORTH -> bumped into a wall" in p.text


def test_the_player_takes_an_env_made_by_gymnasium_or_pettingzoo():
    import gymnasium

    env = gymnasium.make("babyrobot_marl/BabyRobot-v0", level="walls")
    assert notebook.play(env).game.env is env.unwrapped
    race = race_v0.parallel_env(level="race-2", n_robots=2)
    assert isinstance(notebook.play(race).game, RaceGame)
    with pytest.raises(ValueError, match="robots: the env given has 2"):
        notebook.play(race, robots=3)
    with pytest.raises(ValueError, match="render_mode='human' draws a canvas of its own"):
        notebook.play(BabyRobotEnv(level="walls", render_mode="human"))
    with pytest.raises(ValueError, match="robots: must be None"):
        notebook.play("race-4", robots=0)
    with pytest.raises(TypeError, match="play\\(\\) got an unexpected keyword argument 'polices'; known: robots, policies"):
        notebook.play("race-4", polices="shortest")
    with pytest.raises(TypeError, match="edit\\(\\) got an unexpected keyword argument 'size'; known: race, cell_size, theme"):
        notebook.edit(size=(3, 3))
    with pytest.raises(ValueError, match="width: the editor takes an integer in 1..64, got 0"):
        notebook.edit((0, 3))


def test_in_a_race_tab_switches_the_robot_you_drive_and_the_others_follow_their_policy():
    p = notebook.play("race-4", policies="shortest", seed=0)
    env = p.game.env
    shortest = ShortestPathPolicy(env.table)
    assert p.game.driven == 0 and "you drive #0 (robot_0)" in p.text
    start = env.robot_cells
    p.press(" ")  # robot_0 stays, the others take their shortest step
    assert env.robot_cells[0] == start[0] and all(env.robot_cells[i] != start[i] for i in (1, 2, 3))
    p.press("Tab")
    assert p.game.driven == 1 and "you drive #1 (robot_1)" in p.text
    before = env.robot_cells
    p.press(" ")  # now robot_1 stays while robot_0 follows its policy
    assert env.robot_cells[1] == before[1]
    assert env.robot_cells[0] != before[0] and shortest([*before[0]]) != Action.STAY


def test_when_your_robot_finishes_the_keys_move_on_to_a_robot_still_racing():
    p = notebook.play("race-2", policies="random", seed=3)
    env = p.game.env
    shortest = ShortestPathPolicy(env.table)
    while "robot_0" in env.agents and not p.game.over:
        p.press({1: "ArrowUp", 2: "ArrowRight", 3: "ArrowDown", 4: "ArrowLeft", 0: " "}[shortest(list(env.robot_cells[0]))])
    assert env.ranks[0] == 1 and not p.game.over  # robot_1 (random) is still on its way
    assert p.game.driven == 1 and "you drive #1 (robot_1)" in p.text
    finished = next(v for v in p.canvas.scene.robots if v.number == 0)
    assert finished.rank == 1 and finished.cell in env.level.exits  # drawn at the exit with its rank
    assert [r.name for r in p.canvas.scene.legend] == ["random", "you"]


def test_the_editor_builds_a_level_from_clicks_and_plays_it():
    e = notebook.edit((3, 2), cell_size=40)
    e.click(100, 20)  # cell (2, 0): floor -> small puddle
    e.click(78, 60)  # just left of the line between (1, 1) and (2, 1): a wall
    assert e.text == "+-+-+-+\n|S   p|\n+ + + +\n|   |E|\n+-+-+-+"
    assert e.level.small_puddles == frozenset({(2, 0)}) and "ok: a 3x2 level" in e.verdict.value
    e.click_edge((2, 0), (2, 1))  # the exit walled off: the verdict names the unreachable start
    assert "the start (column 0, row 0) cannot reach an exit: click a wall on the way" in e.verdict.value
    assert e.play_button.disabled
    with pytest.raises(ValueError, match="cannot reach any exit"):
        _ = e.level
    e.click_edge((2, 0), (2, 1))  # wall -> glass: reachable again
    e.width_box.value = 4
    assert e.text.splitlines()[1] == "|S   p  |" and not e.play_button.disabled
    player = e.play(seed=0)
    assert player.level == e.level and e.player_box.children == (player.widget,)


def test_the_editor_starts_from_a_level_and_counts_race_starts():
    e = notebook.edit("race-2")
    assert e.race_box.value and e.level == BabyRobotEnv(level="race-2").level
    e.click_cell((1, 0))
    for _ in range(3):
        e.click_cell((1, 0))
    assert e.text.splitlines()[1][3] == "2" and "3 starts" in e.verdict.value


def test_the_editor_draws_the_level_as_the_game_does_at_twice_its_css_size():
    """Same renderer and theme as the game (START and EXIT in the game's colours, not flat ones)."""
    from babyrobot_marl.render.rgb import RgbRenderer

    for theme in ("light", "dark"):
        e = notebook.edit("walls", cell_size=40, theme=theme)
        assert (e.picture() == RgbRenderer(e.level, 80, theme).frame(())).all()
        assert e.canvas.width == 2 * e.level.width * 40 and e.canvas.layout.width == f"{e.level.width * 40}px"


def test_the_editor_sends_a_new_canvas_its_picture_as_rectangles_and_edits_as_png(monkeypatch):
    """A new or resized canvas (the browser's is empty) gets the picture as one-colour rectangles,
    drawn as they arrive: a PNG decodes later, and the canvas showed blank until then. An edit on a
    canvas that shows a picture comes as a PNG (the old one stays until it is decoded)."""
    import ipycanvas.canvas as ipc

    from tests.test_canvas import pictures

    got: list = []
    monkeypatch.setattr(ipc._CANVAS_MANAGER, "_send_custom", lambda command, buffers=(): got.extend(pictures(command, buffers)))
    e = notebook.edit((3, 2), cell_size=40)
    assert [how for how, _ in got] == ["fillStyledRects"] and (got[0][1] == e.picture()).all()
    got.clear()
    e.click_cell((1, 1))
    assert [how for how, _ in got] == ["putImageData"] and (got[0][1][..., :3] == e.picture()).all()
    got.clear()
    e.width_box.value = 4
    assert [how for how, _ in got] == ["fillStyledRects"] and (got[0][1] == e.picture()).all()


def test_a_missing_exit_is_asked_for_in_plain_words_and_outlines_no_cell():
    from babyrobot_marl.render.rgb import RgbRenderer

    e = notebook.edit((3, 2), cell_size=40)
    e.click_cell((2, 1))  # the exit -> floor: no exit
    assert "the level needs an exit: click a cell, then press E" in e.verdict.value
    assert "line 1" not in e.verdict.value and e._bad_cell is None
    start = (0, 0)
    box = lambda img: img[start[1] * 80 : (start[1] + 1) * 80, start[0] * 80 : (start[0] + 1) * 80]  # noqa: E731
    assert (box(e.picture()) == box(RgbRenderer(notebook.ed.sketch(e.draft), 80).frame(()))).all()
    assert not (box(e.picture()) == (0xE0, 0x31, 0x31)).all(axis=2).any()  # no red on START
    e.click_cell((1, 1))  # floor -> small puddle, and the cell is the one the keys change
    e.press("E")
    assert e.text.splitlines()[3] == "|  E  |" and "ok: a 3x2 level" in e.verdict.value


def test_the_player_under_the_editor_follows_every_edit():
    e = notebook.edit((3, 2), cell_size=40)
    first = e.play(seed=0)
    e.click_cell((1, 0))  # a small puddle: a new level, a new player of it
    assert e.player is not first and e.player.level == e.level and e.player_box.children == (e.player.widget,)
    e.click_cell((2, 1))  # no exit: no player, and why (said once, in the verdict above it)
    assert e.player is None and "comes back" in e.player_box.children[0].value and "needs an exit" in e.verdict.value
    e.press("e")
    assert e.player is not None and e.player.level.exits == frozenset({(2, 1)})


def test_the_player_panel_says_where_the_robots_are_in_words_and_frames_the_driven_robot():
    p = notebook.play("race-4", policies="shortest", seed=0, cell_size=32)
    assert "robots at" not in p.text and "None" not in p.text and "(you) is at column" in p.text
    img = p.canvas.picture()
    you = p.game.robots[p.game.driven]
    cs = p.canvas.hi.cell_size
    colour = p.canvas.hi.theme.robots[p.game.driven]
    frame = img[you[1] * cs : you[1] * cs + 8, you[0] * cs : (you[0] + 1) * cs]  # the top bar of its cell's frame
    assert (frame == colour).all(axis=2).sum() > cs
    p.press("Tab")
    assert p.canvas.marked == p.game.driven == 1
    single = notebook.play("walls", seed=0)
    assert "Baby Robot is at column 0, row 0" in single.text and single.canvas.marked is None
    assert single.canvas.fit  # no cell size: the canvas fills the column


def test_the_player_offers_a_replay_of_the_episode_that_draws_without_stepping():
    p = notebook.play("default", seed=0)
    assert p.replay.widget.layout.display == "none"  # no replay during an episode
    for key in ("ArrowRight", "ArrowRight", "s", "s"):
        p.press(key)
    assert p.game.terminated and p.replay.widget.layout.display == "flex"
    assert p.replay.slider.max == 4 and p.replay.slider.value == 4  # five scenes: the start and four steps
    assert "the slider under the buttons replays it" in p.text and "q: quit" not in p.text  # no q in a notebook
    sent, steps = p.canvas.frames_sent, p.game.steps
    p.replay.slider.value = 0
    assert p.canvas.frames_sent > sent and p.game.steps == steps  # drawn again, the env not stepped
    assert [v.cell for v in p.canvas.history[0][0].robots] == [(0, 0)]
    _button(p, "reset").click()  # a new episode: its own replay, offered when it ends
    assert p.replay.widget.layout.display == "none" and len(p.canvas.history) == 1


def test_the_single_robot_players_canvas_has_no_empty_band_under_the_grid():
    """A player's episode shows no panel on its canvas (its steps and returns are in the text
    under it): the canvas is the grid, with no room kept for values it never shows."""
    from babyrobot_marl.play.notebook import Player

    p = Player("mixed-8x8")
    assert p.canvas.shown == p.canvas.hi.grid_height == p.canvas.widget.height  # no spare rows under it either
    p.press("ArrowDown")
    assert p.canvas.shown == p.canvas.hi.grid_height
