"""Watching a race in the terminal: full speed where places are decided, fast forward elsewhere.

A race of scripted robots is decided in a few steps, then random robots may wander for a hundred
more. The race is played ahead on a copy (same seed, same policies: the same race), so the pace
is known in advance:

- the opening and the ``LEAD`` steps before each podium finish go at the normal delay;
- every other stretch is fast-forwarded (at most ``STRETCH`` seconds, marked ``>> fast forward``);
- the frames stop when every place is known (at most one robot still racing: it is last; or
  nobody finishes any more: the robots left never make it), and the summary follows at once;
  the race itself is finished without frames, so the results table is the whole race's.

A legend under the frame says which letter is which robot and what ``A#2`` in the footer means.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable, Iterable, Sequence
from typing import Any, TextIO

from ..render.ansi import ROBOT_COLOURS, robot_glyph, symbols
from .screen import CLEAR_SCREEN, HIDE_CURSOR, SHOW_CURSOR, draw

OPENING = 6  # the first steps at full speed: everyone leaves the start
LEAD = 4  # full speed for this many steps up to each podium finish
PODIUM = 3
STRETCH = 1.0  # seconds a fast-forwarded stretch lasts at most
MIN_FAST = 0.01  # seconds per fast frame at least: still a visible motion
FAST_FACTOR = 3  # a fast frame takes at most delay / FAST_FACTOR


def settled_step(finish_steps: Sequence[int | None], n_steps: int) -> int:
    """The step at which every place is known: at most one robot still racing (it is last whatever it
    does), or the last finish of the race (the robots left never finish), else the race's last step.
    ``finish_steps[i]``: the step robot i finished, None if it did not."""
    done = sorted(s for s in finish_steps if s is not None)
    if not done:
        return n_steps
    need = max(len(finish_steps) - 1, 1)  # one robot alone: the race is decided when it finishes
    return min(done[need - 1] if len(done) >= need else n_steps, done[-1])


def podium_steps(finish_steps: Sequence[int | None], podium: int = PODIUM) -> list[int]:
    """The steps at which the first ``podium`` places were decided (robots finishing together share one)."""
    done = sorted(s for s in finish_steps if s is not None)
    return sorted(set(done[:podium]))


def schedule(finish_steps: Sequence[int | None], n_steps: int, delay: float) -> list[tuple[float, bool]]:
    """``(pause before frame k, fast?)`` for the frames k = 1 .. ``settled_step`` (frame 0 shows at once)."""
    end = settled_step(finish_steps, n_steps)
    keys = [*podium_steps(finish_steps), end]
    slow = [k <= OPENING or any(e - LEAD < k <= e for e in keys) for k in range(1, end + 1)]
    plan: list[tuple[float, bool]] = []
    k = 0
    while k < end:
        j = k
        while j < end and slow[j] == slow[k]:
            j += 1
        run = j - k
        pause = delay if slow[k] else min(delay / FAST_FACTOR, max(MIN_FAST, STRETCH / run))
        plan += [(pause, not slow[k])] * run
        k = j
    return plan


def play_ahead(env: Any, robot_policies: Sequence[Callable], seed: int) -> tuple[list[int | None], int]:
    """Each robot's finishing step (None: did not finish) and the race's length, from a copy of ``env``
    and the policies reset with ``seed``: the race ``race`` is about to show. The originals are untouched."""
    env, robot_policies = copy.deepcopy((env, list(robot_policies)))
    obs, _ = env.reset(seed=seed)
    finish: list[int | None] = [None] * env.n_robots
    while env.agents:
        actions = {a: robot_policies[env.possible_agents.index(a)](obs[a]) for a in env.agents}
        obs, _, _, _, infos = env.step(actions)
        for a, info in infos.items():
            i = env.possible_agents.index(a)
            if info.get("rank") and finish[i] is None:
                finish[i] = env.elapsed_steps
    return finish, env.elapsed_steps


def legend(names: Sequence[str], colour: bool = False, level: Any = None, goals: str = "exit",
           lifelong: bool = False) -> list[str]:
    """Two lines under the frame: which letter is which robot (and policy), and what the level's symbols
    (``level``: those it uses; else the exit and puddles) and the footer say (``goals="own"``: a robot
    finishes on its own target; ``lifelong``: it gets a new one instead)."""
    n = len(names)

    def glyph(i: int) -> str:
        g = robot_glyph(i, n)
        return f"\x1b[1;{ROBOT_COLOURS[i % len(ROBOT_COLOURS)]}m{g}\x1b[0m" if colour else g

    if n <= 6:
        robots = "  ".join(f"{glyph(i)} robot_{i} {p}" for i, p in enumerate(names))
    else:
        counts = {p: names.count(p) for p in dict.fromkeys(names)}
        robots = f"{glyph(0)}..{glyph(n - 1)} robot_0..robot_{n - 1} (" + ", ".join(f"{c} {p}" for p, c in counts.items()) + ")"
    first = robot_glyph(0, n)
    board = symbols(level) if level is not None else "E exit, p/P puddle"
    if lifelong:
        return [f"robots: {robots}", f"{board}; 'targets:' each robot's target, a new one once it is reached"]
    where = "reached its target" if goals == "own" else "finished"
    if n == 1:
        return [f"robots: {robots}", f"{board}; footer '{first}#1': {first} {where} and left the board"]
    return [f"robots: {robots}", f"{board}; footer '{first}#2': {first} {where} 2nd and left the board"]


def watch_race(
    env: Any,
    robot_policies: Sequence[Callable],
    seed: int,
    frames: Iterable[str],
    names: Sequence[str],
    delay: float,
    colour: bool,
    out: TextIO,
    sleep: Callable[[float], None] = time.sleep,
) -> int:
    """Show ``frames`` (one per step of the race, from the reset on) paced by ``schedule``, redrawn in
    place, then consume the rest of them without drawing. Returns the step the frames stopped at.

    ``env``, ``robot_policies`` and ``seed`` must be what ``frames`` will play: the race is played
    ahead on copies of them, before the first frame is drawn."""

    finish, n_steps = play_ahead(env, robot_policies, seed)
    plan = schedule(finish, n_steps, delay)
    end = len(plan)
    foot = legend(names, colour, env.level, env.goals_mode, env.lifelong)
    it = iter(frames)
    out.write(HIDE_CURSOR + CLEAR_SCREEN)
    try:
        for k, text in enumerate(it):
            pause, fast = plan[k - 1] if k else (0.0, False)
            if pause > 0:
                sleep(pause)
            draw(out, "\n".join([text, ">> fast forward" if fast else "", *foot]))
            if k >= end:
                break
        for _ in it:  # every place is known: the rest of the race, without frames
            pass
    finally:
        out.write(SHOW_CURSOR)
        out.flush()
    if end < n_steps:
        left = [
            f"{robot_glyph(i, len(names))} (robot_{i}) " + ("did not finish" if s is None else f"finished at step {s}")
            for i, s in enumerate(finish) if s is None or s > end
        ]  # fmt: skip
        out.write(f"\nevery place was known at step {end}, the race ran {n_steps} steps: {', '.join(left)}\n")
    return end
