"""The keyboard game in a real pseudo-terminal: ``play --policy keys`` and ``race --human N``.

Each test starts ``python -m babyrobot_marl`` as the session leader of a new pty (as a terminal
or an ssh session would), types keys into it, reads the screen, and checks afterwards that the
terminal modes are what they were before (echo and line editing back on).
"""

from __future__ import annotations

import os
import re
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from babyrobot_marl import BabyRobotEnv
from babyrobot_marl.core.actions import Action
from babyrobot_marl.policies import ShortestPathPolicy

termios = pytest.importorskip("termios")
import fcntl  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
ARROWS = {Action.NORTH: "\x1b[A", Action.SOUTH: "\x1b[B", Action.EAST: "\x1b[C", Action.WEST: "\x1b[D"}
WASD = {Action.NORTH: "w", Action.SOUTH: "s", Action.EAST: "d", Action.WEST: "a"}
GUARD = 60.0  # seconds: a guard against a hung child, not a speed target
ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")


class PtyProgram:
    """``python -m babyrobot_marl ARGS`` on the slave side of a new pty, its controlling terminal."""

    def __init__(self, *args: str):
        self.master, self.slave = os.openpty()
        attrs = termios.tcgetattr(self.slave)
        attrs[3] |= termios.ECHO | termios.ICANON | termios.ISIG  # a fresh interactive terminal
        termios.tcsetattr(self.slave, termios.TCSANOW, attrs)
        self.modes_before = termios.tcgetattr(self.slave)
        env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""), "TERM": "xterm"}
        env.pop("NO_COLOR", None)
        slave = self.slave

        def become_terminal_session():  # in the child: a new session whose controlling terminal is the pty
            os.setsid()
            fcntl.ioctl(slave, termios.TIOCSCTTY, 0)
            # a shell starts a foreground job with Ctrl-C live; a test run in the background (nohup ... &)
            # would pass on SIGINT ignored, and Python keeps an ignored SIGINT ignored
            signal.signal(signal.SIGINT, signal.SIG_DFL)

        self.proc = subprocess.Popen(
            [sys.executable, "-m", "babyrobot_marl", *args], stdin=slave, stdout=slave, stderr=slave,
            preexec_fn=become_terminal_session, env=env, cwd=REPO,
        )  # fmt: skip
        self.output = b""

    def type(self, keys: str) -> None:
        os.write(self.master, keys.encode())

    def read_until(self, pattern: str, timeout: float = GUARD) -> str:
        """Read the screen until ``pattern`` (a regex) shows in the text with escape sequences removed."""
        deadline = time.monotonic() + timeout
        while not re.search(pattern, self.text):
            left = deadline - time.monotonic()
            if left <= 0 or (not self._read(min(left, 0.2)) and self.proc.poll() is not None and not self._read(0)):
                raise AssertionError(f"{pattern!r} never showed; the screen so far:\n{self.text[-2500:]}")
        return self.text

    def _read(self, timeout: float) -> bool:
        if not select.select([self.master], [], [], timeout)[0]:
            return False
        try:
            data = os.read(self.master, 65536)
        except OSError:  # EIO: the child closed its side
            return False
        self.output += data
        return bool(data)

    @property
    def text(self) -> str:
        return ANSI.sub("", self.output.decode(errors="replace"))

    def wait(self) -> int:
        deadline = time.monotonic() + GUARD
        while self.proc.poll() is None and time.monotonic() < deadline:
            self._read(0.1)
        while self._read(0.05):
            pass
        return self.proc.wait(timeout=5)

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        os.close(self.master)
        os.close(self.slave)

    def modes_restored(self) -> bool:
        return termios.tcgetattr(self.slave) == self.modes_before


@pytest.fixture
def program():
    started = []

    def start(*args: str) -> PtyProgram:
        p = PtyProgram(*args)
        started.append(p)
        return p

    yield start
    for p in started:
        p.close()


def shortest_moves(level: str) -> list[Action]:
    """The shortest path's moves from the level's start (a level without puddles or glass: no chance)."""
    env = BabyRobotEnv(level=level)
    policy = ShortestPathPolicy(env.table)
    obs, _ = env.reset(seed=0)
    moves = []
    while True:
        a = Action(policy(obs))
        moves.append(a)
        obs, _, terminated, truncated, _ = env.step(a)
        if terminated or truncated:
            assert terminated
            return moves


def test_arrow_keys_drive_the_robot_to_the_exit_and_q_restores_the_terminal(program):
    moves = shortest_moves("walls")
    assert len(moves) > 6
    p = program("play", "--level", "walls", "--policy", "keys", "--seed", "0")
    p.read_until("arrows/WASD move")
    assert "key: R you, +-| wall, S start, E exit" in p.text  # the symbols on the screen, explained
    for k, a in enumerate(moves):
        p.type(ARROWS[a])
        p.read_until(rf"step {k + 1}/")  # every key is answered with a frame before the next one
    p.read_until(rf"reached the exit in {len(moves)} steps")
    p.type("q")
    assert p.wait() == 0
    assert re.search(rf"policy keys, seed 0, episode 1: {len(moves)} steps, return \S+, reached the exit", p.text)
    assert p.modes_restored()


def test_wasd_bump_restart_and_a_second_episode(program):
    p = program("play", "--level", "default", "--policy", "keys", "--seed", "0")
    p.read_until("arrows/WASD move")
    p.type("w")  # north from the top-left start: the border
    p.read_until("NORTH -> bumped into a wall")
    p.type(" ")
    p.read_until("STAY -> stayed")
    p.type("x")
    p.read_until("that key does nothing here")
    p.type("r")
    p.read_until("episode 2")
    for a in (Action.EAST, Action.EAST, Action.SOUTH, Action.SOUTH):
        p.type(WASD[a])
    p.read_until("reached the exit in 4 steps, return -3")
    p.type("d")  # after the end: nothing moves, the game says how to go on
    p.read_until("the episode is over")
    p.type("q")
    assert p.wait() == 0
    assert "seed 0, episode 2: 4 steps, return -3.0, reached the exit" in p.text
    assert p.modes_restored()


def test_ctrl_c_ends_the_game_with_130_and_restores_the_terminal(program):
    p = program("play", "--level", "walls", "--policy", "keys", "--seed", "0")
    p.read_until("arrows/WASD move")
    assert "key: R you, +-| wall, S start, E exit" in p.text  # the symbols on the screen, explained
    p.type("d")
    p.read_until("step 1/")
    p.type("\x03")  # the terminal's interrupt key: SIGINT to the game
    assert p.wait() == 130
    assert p.modes_restored()


def test_sigterm_and_hangup_restore_the_terminal(program):
    for sig in (signal.SIGTERM, signal.SIGHUP):
        p = program("play", "--level", "walls", "--policy", "keys", "--seed", "0")
        p.read_until("arrows/WASD move")
        p.proc.send_signal(sig)
        assert p.wait() == 128 + sig
        assert p.modes_restored()


def test_without_a_terminal_it_says_so_and_exits_2():
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    for args in (["play", "--policy", "keys"], ["race", "--human", "0"]):
        proc = subprocess.run(
            [sys.executable, "-m", "babyrobot_marl", *args], input="d", capture_output=True, text=True, timeout=GUARD, env=env
        )
        assert proc.returncode == 2, proc
        assert "needs an interactive terminal" in proc.stderr and "Traceback" not in proc.stderr
        assert proc.stdout == ""


RACE_LEVEL = """
+-+-+-+-+-+-+
|0      |  1|
+ +-+-+ + + +
|      E    |
+-+-+-+-+-+-+
"""  # no puddle, no glass: robot_0's path home is the same whatever the seed
RACE_KEYS = [Action.SOUTH, Action.EAST, Action.EAST, Action.EAST]


def test_race_human_drives_robot_0_home_then_the_others_are_played_out(program, tmp_path):
    level = tmp_path / "corridor.txt"
    level.write_text(RACE_LEVEL)
    p = program("race", "--level", str(level), "--robots", "2", "--policies", "random", "--collisions", "pass",
                "--human", "0", "--seed", "3", "--delay", "0")  # fmt: skip
    p.read_until("you are A")
    p.read_until("key: +-| wall")
    for k, a in enumerate(RACE_KEYS):
        p.type(ARROWS[a])
        p.read_until(rf"step {k + 1}/")
    p.read_until("the race is over")
    p.type("q")
    assert p.wait() == 0
    row = re.search(r"^(\d+|-)\s+A robot_0\s+keys\s+(\d+)\s", p.text, re.M)
    assert row and row[1] == "1" and int(row[2]) == len(RACE_KEYS), p.text[-1500:]
    assert re.search(r"^(\d+|-)\s+B robot_1\s+random\s+\d+", p.text, re.M)
    assert p.modes_restored()


def test_race_human_must_name_a_robot_of_the_race():
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.run(
        [sys.executable, "-m", "babyrobot_marl", "race", "--robots", "2", "--level", "race-2", "--human", "2"],
        capture_output=True, text=True, timeout=GUARD, env=env,
    )  # fmt: skip
    assert proc.returncode == 2 and "--human: must be a robot number in 0..1" in proc.stderr


# ------------------------------------------------------------------------ in a shell with job control (tmux)
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")


class Tmux:
    """A bash in a detached tmux session on a private server socket: keys in, the screen out."""

    def __init__(self, name: str):
        self.base = ["tmux", "-L", name]
        env = f"PYTHONPATH={REPO}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"
        subprocess.run([*self.base, "-f", "/dev/null", "new-session", "-d", "-s", "t", "-x", "100", "-y", "40",
                        f"env {env} TERM=xterm bash --norc --noprofile"], check=True, timeout=GUARD)  # fmt: skip

    def keys(self, *keys: str) -> None:
        subprocess.run([*self.base, "send-keys", "-t", "t", *keys], check=True, timeout=GUARD)

    def screen(self) -> str:
        return subprocess.run([*self.base, "capture-pane", "-p", "-t", "t"], capture_output=True, text=True, timeout=GUARD).stdout

    def wait_for(self, pattern: str) -> str:
        deadline = time.monotonic() + GUARD
        while not re.search(pattern, text := self.screen()):
            if time.monotonic() > deadline:
                raise AssertionError(f"{pattern!r} never showed; the screen:\n{text}")
            time.sleep(0.1)
        return text

    def close(self) -> None:
        subprocess.run([*self.base, "kill-server"], capture_output=True, timeout=GUARD)


@pytest.fixture
def tmux():
    import shutil

    if shutil.which("tmux") is None:
        if IN_CI:
            pytest.fail("CI=true and tmux is missing (.ci/play.sh installs it)")
        pytest.skip("tmux not installed (apt-get install tmux; .ci/play.sh does it in CI)")
    t = Tmux(f"babyrobot-test-{os.getpid()}")
    yield t
    t.close()


def test_in_a_shell_ctrl_z_gives_the_terminal_back_and_fg_resumes_the_game(tmux):
    modes = "stty -a | tr ' ;' '\\n\\n' | grep -x -e icanon -e -icanon -e echo -e -echo | tr '\\n' ' '; echo '<'MODES'>'"
    tmux.keys(f"cd {REPO} && {sys.executable} -m babyrobot_marl play --level walls --policy keys --seed 0", "Enter")
    tmux.wait_for("arrows/WASD move")
    tmux.keys("Right")
    tmux.wait_for("step 1/")
    tmux.keys("C-z")
    tmux.wait_for(r"Stopped")
    tmux.keys(modes, "Enter")
    assert "icanon echo <MODES>" in tmux.wait_for("<MODES>")  # the shell has its terminal back as it was
    tmux.keys("clear; fg", "Enter")
    tmux.wait_for(r"step 1/.*\n.*arrows/WASD move")  # redrawn on the cleared screen at once, before any key
    tmux.keys("Right")
    tmux.wait_for("step 2/100  return -2  last: EAST -> moved")
    tmux.keys("q")
    tmux.wait_for("policy keys, seed 0, episode 1: 2 steps")
    tmux.keys("clear; " + modes, "Enter")
    assert "icanon echo <MODES>" in tmux.wait_for("<MODES>")


class _WokenError(Exception):
    pass


def test_a_signal_taken_by_another_thread_still_reaches_a_game_waiting_for_a_key():
    # Linux may hand Ctrl-C's SIGINT to any thread (numpy's, say); that does not wake the main
    # thread's select, so a game waiting for a key without end would never run its handler.
    import io
    import threading

    from babyrobot_marl.play.terminal import Keyboard

    def woken(*_: object) -> None:
        raise _WokenError

    master, slave = os.openpty()
    previous = signal.signal(signal.SIGUSR1, woken)

    guard = threading.Event()

    def elsewhere():
        time.sleep(0.3)  # let the main thread wait in select first
        signal.pthread_kill(threading.get_ident(), signal.SIGUSR1)
        time.sleep(GUARD)
        guard.set()
        os.write(master, b" \n")  # a guard: the key that ends an unending wait

    threading.Thread(target=elsewhere, daemon=True).start()
    try:
        with pytest.raises(_WokenError):
            Keyboard(slave, io.StringIO()).read(None)
        assert not guard.is_set(), "the handler ran only when a key came"
    finally:
        signal.signal(signal.SIGUSR1, previous)
        os.close(slave)
