"""The README's main job, watched on a terminal: paced by the race, a legend, a summary once every place is known."""

from __future__ import annotations

import re
import sys

import pytest

from babyrobot_marl import cli, policies
from babyrobot_marl.envs.race import RaceEnv
from babyrobot_marl.play.watch import LEAD, OPENING, legend, play_ahead, podium_steps, schedule, settled_step
from tests.streams import TextSink

README_JOB = ["race", "--level", "race-4", "--robots", "4", "--policies", "shortest,shortest,random,random"]
OLD_DELAY = 0.15  # the CLI's pause between frames on a terminal


def test_every_place_is_known_when_at_most_one_robot_is_still_racing():
    assert settled_step([6, 12, 70, None], 196) == 70  # the fourth is last whatever it does
    assert settled_step([6, None, None, None], 196) == 6  # nobody else finishes: all places known at step 6
    assert settled_step([None, None, None], 196) == 196  # nobody finishes: known when the race is cut
    assert settled_step([5, 5, 5, 9], 9) == 5  # three finish together: the fourth is last
    assert settled_step([None, 40], 60) == 40  # two robots: the first finisher settles both places
    assert settled_step([17], 100) == 17 and settled_step([None], 100) == 100  # alone: when it finishes


def test_podium_steps_are_the_first_three_finishing_steps():
    assert podium_steps([6, 12, 70, 82]) == [6, 12, 70]
    assert podium_steps([6, 6, 9, 30, None]) == [6, 9]  # a tie shares a place and a step


def test_the_schedule_is_full_speed_near_each_decision_and_fast_elsewhere():
    finish, n_steps, delay = [6, 12, 70, 82], 82, 0.15
    plan = schedule(finish, n_steps, delay)
    assert len(plan) == 70  # frames 1..70: it stops when every place is known
    slow = {k + 1 for k, (_, fast) in enumerate(plan) if not fast}
    expected = set(range(1, OPENING + 1)) | {k for e in (6, 12, 70) for k in range(e - LEAD + 1, e + 1)}
    assert slow == expected
    assert all(p == delay for p, fast in plan if not fast)
    fast = [p for p, f in plan if f]
    assert fast and all(p < delay for p in fast)
    assert sum(fast) <= 2 * 1.0 + 1e-9  # two fast stretches (13..66, and 7..8): at most a second each


def test_no_pause_at_all_without_a_delay():
    assert all(p == 0 for p, _ in schedule([6, 12, 70, 82], 82, 0.0))


def test_play_ahead_sees_the_race_the_cli_will_show_and_leaves_the_originals_alone():
    env = RaceEnv(level="race-4", n_robots=4, start="fill")
    names = ["shortest", "shortest", "random", "random"]
    pols = [policies.make(n, env.table, seed=5 + 7919 * (i + 1)) for i, n in enumerate(names)]
    finish, n_steps = play_ahead(env, pols, seed=5)
    # the originals: never reset, the random robots' generators untouched; now play the race for real
    assert env.elapsed_steps == 0 and not env.agents
    obs, _ = env.reset(seed=5)
    real = [None] * 4
    while env.agents:
        obs, _, _, _, infos = env.step({a: pols[env.possible_agents.index(a)](obs[a]) for a in env.agents})
        for a, info in infos.items():
            if info.get("rank"):
                real[env.possible_agents.index(a)] = real[env.possible_agents.index(a)] or env.elapsed_steps
    assert (finish, n_steps) == (real, env.elapsed_steps)


def test_the_legend_names_every_robot_and_explains_the_footer():
    lines = legend(["shortest", "shortest", "random", "random"])
    assert lines[0] == "robots: A robot_0 shortest  B robot_1 shortest  C robot_2 random  D robot_3 random"
    assert "'A#2': A finished 2nd" in lines[1]
    board = legend(["shortest"] * 4, level=RaceEnv(level="race-4", n_robots=4).level)[1]
    assert board.startswith("key: +-| wall, # blocked cell, * glass wall") and "E exit" in board
    many = legend(["random"] * 12)
    assert many[0] == "robots: A..L robot_0..robot_11 (12 random)"


@pytest.mark.parametrize(
    "seed, last",
    [
        (1, "D (robot_3) finished at step 82"),  # C's finish at step 70 leaves D alone: last
        (7, "C (robot_2) did not finish, D (robot_3) did not finish"),  # nobody finishes after A at step 8
    ],
)
def test_the_readme_race_on_a_terminal_stops_its_frames_once_every_place_is_known(seed, last, monkeypatch):
    tty = TextSink(tty=True)
    monkeypatch.setattr(sys, "stdout", tty)
    assert cli.main([*README_JOB, "--seed", str(seed), "--delay", "0"]) == 0
    monkeypatch.undo()
    text = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", tty.text.replace("\x1b[H", "\f"))  # \f: one redraw per frame
    shown = text.split("\f")[1:]
    m = re.search(r"every place was known at step (\d+), the race ran (\d+) steps: (.*)", text)
    assert m, text[-2000:]
    end, n_steps = int(m[1]), int(m[2])
    assert m[3] == last
    assert end < n_steps and len(shown) == end + 1
    assert f"step {end}/" in shown[-1] and "robots: A robot_0 shortest" in shown[-1]
    assert "step 1/" in shown[1] and "step 0/" in shown[0]
    # the results table is the whole race's: the same as into a pipe, which shows every frame
    pipe = TextSink(tty=False)
    monkeypatch.setattr(sys, "stdout", pipe)
    assert cli.main([*README_JOB, "--seed", str(seed), "--no-delay"]) == 0
    monkeypatch.undo()
    assert text[text.index("rank  robot"):] == pipe.text[pipe.text.index("rank  robot"):]
    assert f"{n_steps} steps" in text
    # into a pipe: the first and the last frame, the legend once, the results
    assert pipe.text.count("step ") == 3 and f"({n_steps - 1} frames left out" in pipe.text
    assert pipe.text.count("robots: A robot_0 shortest") == 1 and "key: +-| wall, # blocked cell" in pipe.text


def test_the_readme_race_is_watched_in_seconds_instead_of_until_the_last_random_robot_stops():
    """Over 20 seeds, the time the README's race spends on screen (the schedule's pauses) against the
    old fixed 0.15 s per frame to the end of the race."""
    env = RaceEnv(level="race-4", n_robots=4, start="fill")
    names = ["shortest", "shortest", "random", "random"]
    old, new = [], []
    for seed in range(20):
        pols = [policies.make(n, env.table, seed=seed + 7919 * (i + 1)) for i, n in enumerate(names)]
        finish, n_steps = play_ahead(env, pols, seed)
        old.append(OLD_DELAY * n_steps)
        new.append(sum(p for p, _ in schedule(finish, n_steps, OLD_DELAY)))
    assert max(new) <= 6.0, new  # the opening, three podium approaches and at most 4 fast stretches of 1 s
    assert sum(new) < sum(old) / 3, (sum(new), sum(old))
