"""The keyboard game in a terminal: ``babyrobot-marl play --policy keys`` and ``race --human N``.

The terminal is put in cbreak mode (keys arrive one by one, unechoed; Ctrl-C still interrupts)
and always given back as it was: on quit, on an error, on Ctrl-C (SIGINT), on SIGTERM and on a
hang-up (SIGHUP, an ssh connection dropped). Ctrl-Z gives it back too and takes it again on
``fg``. Plain ANSI sequences only (cursor home, clear to end of line), so it works in any
terminal and over ssh. POSIX only (termios).
"""

from __future__ import annotations

import contextlib
import os
import select
import signal
import sys
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from ..core.checks import check_int
from ..envs.keys import HELP, QUIT, RESTART, Command, decode
from ..envs.race import RaceEnv
from ..envs.single import BabyRobotEnv
from ..render.ansi import frame, symbols
from .game import RaceGame, SingleGame
from .screen import CLEAR_SCREEN, HIDE_CURSOR, SHOW_CURSOR, draw
from .watch import schedule, settled_step

WATCH_ONE = "give --policy shortest"  # play's advice without a terminal
ESC_WAIT = 0.05  # seconds to wait for the rest of an escape sequence cut between two reads
SIGNAL_SLICE = 0.5  # seconds: how long a wait for a key goes before Python looks at its signals


def require_terminal(stdin: Any, stdout: Any, what: str, instead: str) -> int:
    """The file descriptor of ``stdin`` if both ends are a terminal, else a ValueError saying so and what to do
    ``instead`` to watch scripted robots."""
    try:
        ok = stdin.isatty() and stdout.isatty()
        fd = stdin.fileno()
    except (AttributeError, ValueError, OSError):
        ok = False
    if not ok:
        raise ValueError(
            f"{what}: the keyboard game needs an interactive terminal, and stdin or stdout is not one "
            f"(run it in a terminal; to watch scripted robots, {instead})"
        )
    try:
        import termios  # noqa: F401  (POSIX only)
    except ImportError:
        raise ValueError(f"{what}: the keyboard game needs a POSIX terminal (termios)") from None
    return fd


class Keyboard:
    """Keys from a terminal in cbreak mode; ``with Keyboard(fd, out) as kb:`` restores it on any exit."""

    def __init__(self, fd: int, out: TextIO):
        self.fd, self.out = fd, out
        self._saved: list | None = None
        self._handlers: dict[int, Any] = {}
        self._pending = ""
        self.redraw: Callable[[], None] | None = None  # called after Ctrl-Z and fg: the screen is the shell's

    def __enter__(self) -> Keyboard:
        import termios

        self._saved = termios.tcgetattr(self.fd)
        for sig in (signal.SIGTERM, signal.SIGHUP):
            self._handlers[sig] = signal.signal(sig, _exit_on_signal)
        if hasattr(signal, "SIGTSTP"):
            self._handlers[signal.SIGTSTP] = signal.signal(signal.SIGTSTP, self._suspend)
        try:
            self._take()
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        try:
            self._give_back()
        finally:
            for sig, handler in self._handlers.items():
                signal.signal(sig, handler)
            self._handlers.clear()

    def _take(self) -> None:
        import tty

        tty.setcbreak(self.fd)
        self.out.write(HIDE_CURSOR + CLEAR_SCREEN)
        self.out.flush()

    def _give_back(self) -> None:
        import termios

        with contextlib.suppress(OSError, ValueError):  # the terminal may be gone (SIGHUP)
            self.out.write(SHOW_CURSOR)
            self.out.flush()
        if self._saved is not None:
            with contextlib.suppress(OSError, termios.error):
                termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)

    def _suspend(self, signum: int, _frame: object) -> None:
        """Ctrl-Z: give the terminal back, stop, and take it again when continued."""
        self._give_back()
        signal.signal(signal.SIGTSTP, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTSTP)  # stops here until SIGCONT
        signal.signal(signal.SIGTSTP, self._suspend)
        self._take()
        if self.redraw is not None:
            self.redraw()

    def read(self, timeout: float | None = None) -> list[Command | None]:
        """The keys pressed, waiting up to ``timeout`` seconds (None: until one is pressed); [] if none."""
        if not self._ready(timeout):
            return []
        data = os.read(self.fd, 1024)
        if not data:  # end of input: the terminal is gone
            return [QUIT]
        commands, self._pending = decode(self._pending + data.decode("utf-8", errors="replace"))
        while self._pending and self._ready(ESC_WAIT):  # an escape sequence cut in two
            more = os.read(self.fd, 1024)
            if not more:
                break
            got, self._pending = decode(self._pending + more.decode("utf-8", errors="replace"))
            commands += got
        if self._pending:  # a lone ESC (or a sequence never completed): a key with no meaning here
            commands.append(None)
            self._pending = ""
        return commands

    def _ready(self, timeout: float | None) -> bool:
        # Waiting without end is done in slices: a signal taken by another thread (numpy's may run)
        # does not wake this select, and Python runs its handler (Ctrl-C) only when select returns.
        while True:
            wait = SIGNAL_SLICE if timeout is None else timeout
            try:
                if select.select([self.fd], [], [], wait)[0]:
                    return True
            except InterruptedError:  # a signal (Ctrl-Z and fg): wait again
                continue
            if timeout is not None:
                return False


def _exit_on_signal(signum: int, _frame: object) -> None:
    raise SystemExit(128 + signum)  # unwinds through every finally: the terminal is restored


# ------------------------------------------------------------------------ one robot
def single_screen(game: SingleGame, title: str, colour: bool) -> str:
    status = "\n".join([*game.status(), HELP, symbols(game.env.level, "R you")])
    return f"{title}\n" + frame(game.env.level, game.robots, status, colour=colour)


def play_keys(env: BabyRobotEnv, seed: int, name: str, colour: bool, out: TextIO = sys.stdout, stdin: Any = None) -> int:
    """``babyrobot-marl play --policy keys``: drive the robot until ``q``; then the last episode's summary."""
    fd = require_terminal(stdin or sys.stdin, out, "--policy keys", WATCH_ONE)
    game = SingleGame(env, seed)
    with Keyboard(fd, out) as kb:
        title = lambda: f"Baby Robot on {name}, seed {seed}, episode {game.episode}"  # noqa: E731
        kb.redraw = lambda: draw(out, single_screen(game, title(), colour))
        kb.redraw()
        while True:
            commands = kb.read()
            if QUIT in commands:
                commands = commands[: commands.index(QUIT)]
                for cmd in commands:
                    game.command(cmd)
                break
            for cmd in commands:
                game.command(cmd)
            kb.redraw()
        kb.redraw()
    out.write(f"\nlevel {name}, policy keys, seed {seed}, episode {game.episode}: {game.summary()}\n")
    return 0


# ------------------------------------------------------------------------ a race
def race_screen(game: RaceGame, title: str, colour: bool, extra: Sequence[str] = ()) -> str:
    hint = "arrows/WASD move, space stay, r restart, q quit" if game.driven_racing else "r restart, q quit"
    status = "\n".join([*game.status(), *extra, hint, symbols(game.env.level)])
    return f"{title}\n" + frame(game.env.level, game.robots, status, colour=colour)


def race_keys(
    env: RaceEnv,
    robot_policies: Sequence[Callable | None],
    human: int,
    seed: int,
    results: Sequence[Any],
    delay: float,
    colour: bool,
    out: TextIO = sys.stdout,
    stdin: Any = None,
    human_flag: bool = True,
) -> int:
    """``babyrobot-marl race --human N``: robot N waits for your key each step, the others follow their
    policies. Once you finish (or the race ends) the rest is played out, paced as ``race`` paces it,
    until every place is known. ``results`` (rank, steps, ret, collisions per robot) are filled in."""
    n = env.n_robots
    wording = "{name}: must be a robot number in 0..{hi} (robot_0 ... robot_{hi}), got {value}"
    human = check_int(human, "--human", 0, n - 1, message=wording)
    what = "race --human" if human_flag else "--policy keys"  # play --policy keys --goals own: robot_0 of a race
    fd = require_terminal(stdin or sys.stdin, out, what, "leave out --human" if human_flag else WATCH_ONE)
    pols = [None if i == human else p for i, p in enumerate(robot_policies)]
    game = RaceGame(env, pols, driven=human, seed=seed, switchable=False)
    glyph = game.glyph(human)
    title = lambda: f"race on {env.level.name or 'a level'}: you are {glyph} (robot_{human}), seed {seed}, race {game.episode}"  # noqa: E731
    with Keyboard(fd, out) as kb:
        kb.redraw = lambda: draw(out, race_screen(game, title(), colour))
        while True:
            kb.redraw()
            if not game.driven_racing and not game.over:
                if _play_out(game, kb, out, title(), delay, colour):
                    break  # q while the others ran
                continue
            commands = kb.read()
            if QUIT in commands:
                break
            for cmd in commands:
                game.command(cmd)
                if not game.driven_racing:
                    break  # you finished: the others run on by themselves, keys pressed meanwhile are dropped
    _fill_results(game, results)
    return 0


def _play_out(game: RaceGame, kb: Keyboard, out: TextIO, title: str, delay: float, colour: bool) -> bool:
    """Run the robots still racing on their policies, paced like ``race``, until every place is known
    (the rest is finished without frames). True if the player quit meanwhile."""
    import copy

    ahead = copy.deepcopy(game)  # the same race played ahead: when does each robot finish?
    while ahead.auto_step():
        pass
    start = game.steps
    finish = [None if s is None else s - start for s in ahead.finish_steps]
    finish = [None if s is not None and s <= 0 else s for s in finish]  # already finished: not in this stretch
    racing = game.racing  # not the parked robots of finished="freeze"
    plan = schedule([finish[i] for i in racing], ahead.steps - start, delay)
    for pause, fast in plan:
        keys = kb.read(timeout=pause)  # a key cuts the pause short: every key is answered at once
        if QUIT in keys:
            return True
        if RESTART in keys:
            game.restart()
            return False
        game.auto_step()
        draw(out, race_screen(game, title, colour, [">> fast forward" if fast else ""]))
    end = settled_step([finish[i] for i in racing], ahead.steps - start)
    while game.auto_step():  # every place is known: the rest without frames
        pass
    if end < ahead.steps - start:
        game.message = f"every place was known at step {start + end}; the race ran to step {game.steps}"
    return False


def _fill_results(game: RaceGame, results: Sequence[Any]) -> None:
    env = game.env
    for i, r in enumerate(results):
        r.rank = env.ranks[i]
        r.steps = game.finish_steps[i] if game.finish_steps[i] is not None else env.elapsed_steps
        r.ret = env.returns[i]
        r.collisions = env.collisions_count[i]

