"""Terminal key decoding and the games behind the keys (no terminal needed)."""

from __future__ import annotations

import pytest

from babyrobot_marl import BabyRobotEnv, policies
from babyrobot_marl.core.actions import Action
from babyrobot_marl.envs.keys import QUIT, RESTART, SWITCH, decode
from babyrobot_marl.envs.race import RaceEnv
from babyrobot_marl.play.game import RaceGame, SingleGame, ordinal


def test_arrow_keys_in_both_cursor_modes_wasd_and_the_control_keys():
    assert decode("\x1b[A\x1b[B\x1b[C\x1b[D") == ([Action.NORTH, Action.SOUTH, Action.EAST, Action.WEST], "")
    assert decode("\x1bOA\x1bOC") == ([Action.NORTH, Action.EAST], "")  # application mode (tmux, some terminals)
    assert decode("wasd .rq\t\x03") == (
        [Action.NORTH, Action.WEST, Action.SOUTH, Action.EAST, Action.STAY, Action.STAY, RESTART, QUIT, SWITCH, QUIT], ""
    )


def test_unknown_keys_are_none_and_a_cut_escape_sequence_waits_for_the_rest():
    assert decode("x\x1b[5~") == ([None, None], "")  # page up: a whole sequence, no meaning here
    assert decode("d\x1b[") == ([Action.EAST], "\x1b[")
    assert decode("\x1b") == ([], "\x1b")
    assert decode("\x1b" + "[" + "B") == ([Action.SOUTH], "")
    assert decode("\x1bx") == ([None], "")  # Alt+x: the x alone


def test_a_step_after_the_end_changes_nothing_and_says_how_to_go_on():
    g = SingleGame(BabyRobotEnv(level="default"), seed=0)
    for a in (Action.EAST, Action.EAST, Action.SOUTH, Action.SOUTH):
        assert g.act(a)
    assert g.terminated and not g.act(Action.WEST) and "r: play again" in g.message
    assert g.command(RESTART) and g.steps == 0 and g.episode == 2 and g.robots == [(0, 0)]


def test_a_race_game_refuses_a_robot_without_policy_and_a_driven_robot_out_of_range():
    env = RaceEnv(level="race-2", n_robots=2)
    pol = policies.make("random", env.table, 0)
    with pytest.raises(ValueError, match="robot 1 has no policy"):
        RaceGame(env, [pol, None], driven=0)
    with pytest.raises(ValueError, match="driven: must be a robot number in 0..1"):
        RaceGame(env, [pol, pol], driven=2)
    g = RaceGame(env, [None, pol], driven=0, switchable=False)  # the terminal's race: robot 0 is yours only
    assert not g.switch() and g.driven == 0 and "one robot only" in g.message


def test_ordinals():
    assert [ordinal(k) for k in (1, 2, 3, 4, 11, 12, 13, 21, 22, 101)] == [
        "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "101st",
    ]  # fmt: skip


def test_the_notebook_module_imports_no_widget_library_until_it_is_used():
    import subprocess
    import sys

    code = (
        "import sys, babyrobot_marl, babyrobot_marl.play.notebook, babyrobot_marl.envs.keys, babyrobot_marl.play.editor;"
        "print(sorted(m for m in ('ipycanvas', 'ipywidgets', 'pygame', 'IPython') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True).stdout
    assert out.strip() == "[]"


@pytest.mark.parametrize("finished", ["remove", "freeze"])
def test_the_keys_leave_a_finished_robot_and_tab_skips_the_finished_ones_in_both_finished_modes(finished):
    env = RaceEnv(level="race-2", n_robots=3, start="fill", finished=finished)
    stay = lambda obs: 0  # noqa: E731
    g = RaceGame(env, [stay, stay, stay], driven=0)
    env.set_cells([(1, 2), (4, 4), (0, 4)])  # robot 0 one step west of the exit at (2, 2)
    assert g.act(Action.EAST) and env.ranks == [1, 0, 0]
    assert g.driven == 1 and g.racing == [1, 2]  # the keys moved on by themselves
    seen = []
    for _ in range(4):
        assert g.switch()
        seen.append(g.driven)
    assert seen == [2, 1, 2, 1]  # TAB never hands the keys to the finished robot 0
    before = env.robot_cells
    assert g.act(Action.NORTH)
    assert env.robot_cells[1] == (4, 3) and env.robot_cells[0] == before[0]  # the press moved robot 1
