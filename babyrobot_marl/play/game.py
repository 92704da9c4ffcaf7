"""A game over an env: one key, one step. Shared by the terminal and the notebook player.

``SingleGame`` drives the one robot of a ``BabyRobotEnv``; ``RaceGame`` drives one robot of a
``RaceEnv`` while the others follow their policies (``switch()`` hands the keys to the next
racing robot). Both answer every command at once and can always be restarted: a step after the
end does nothing but say how to go on.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from ..core.actions import Action
from ..core.checks import check_int
from ..core.level import Cell
from ..core.outcomes import OUTCOME_NAMES
from ..envs.keys import QUIT, RESTART, SWITCH, Command
from ..envs.race import RaceEnv
from ..envs.single import BabyRobotEnv
from ..render.ansi import robot_glyph

# What an outcome means, for someone who just pressed the key.
OUTCOME_TEXT = {
    "moved": "moved",
    "stayed": "stayed",
    "bumped": "bumped into a wall",
    "skidded": "skidded in the puddle",
    "glass": "the glass wall held",
    "finished": "finished",
}
OVER_HINT = "r: play again, q: quit"


def outcome_text(action: int, outcome: int | str) -> str:
    """``"EAST -> bumped into a wall"``; ``outcome`` is an info's code (``OUTCOME_NAMES``) or name."""
    code = outcome if isinstance(outcome, str) else int(outcome)  # numpy integers too
    name = OUTCOME_NAMES[code] if isinstance(code, int) and 0 <= code < len(OUTCOME_NAMES) else str(code)
    return f"{Action(action).name} -> {OUTCOME_TEXT.get(name, name)}"


class SingleGame:
    """One robot, one step per move. ``seed`` seeds the first episode; restarts go on from it."""

    over_hint = OVER_HINT  # what to do when the episode is over (the notebook player says its own)

    def __init__(self, env: BabyRobotEnv, seed: int | None = None):
        if not isinstance(env, BabyRobotEnv):
            raise TypeError(f"env: expected a BabyRobotEnv, got {type(env).__name__}")
        self.env, self.seed = env, seed
        self.episode = 0
        self.restart()

    def restart(self) -> None:
        self.env.reset(seed=self.seed if self.episode == 0 else None)
        self.episode += 1
        self.steps, self.ret = 0, 0.0
        self.last, self.message = "", ""
        self.terminated = self.truncated = False

    @property
    def over(self) -> bool:
        return self.terminated or self.truncated

    @property
    def robots(self) -> list[Cell | None]:
        return [self.env.robot_cell]

    def command(self, cmd: Command | None) -> bool:
        """Apply one command; True if it changed the game (QUIT is the caller's business)."""
        if cmd == RESTART:
            self.restart()
            return True
        if isinstance(cmd, Action):
            return self.act(cmd)
        if cmd in (SWITCH, QUIT):
            return False
        self.message = "that key does nothing here"
        return False

    def act(self, action: int) -> bool:
        if self.over:
            self.message = f"the episode is over: {self.over_hint}"
            return False
        _, reward, self.terminated, self.truncated, info = self.env.step(int(action))
        self.steps += 1
        self.ret += reward
        self.last = outcome_text(action, info["outcome"])
        self.message = ""
        return True

    def status(self) -> list[str]:
        lines = [f"step {self.steps}/{self.env.max_steps}  return {self.ret:g}" + (f"  last: {self.last}" if self.last else "")]
        if self.terminated:
            lines.append(f"reached the exit in {self.steps} steps, return {self.ret:g}. {self.over_hint}")
        elif self.truncated:
            lines.append(f"out of steps: truncated after {self.env.max_steps}. {self.over_hint}")
        if self.message:
            lines.append(self.message)
        return lines

    def summary(self) -> str:
        outcome = (
            "reached the exit" if self.terminated
            else f"did not reach the exit (truncated after {self.env.max_steps} steps)" if self.truncated
            else "stopped before the end"
        )  # fmt: skip
        return f"{self.steps} steps, return {self.ret!r}, {outcome}"


class RaceGame:
    """Drive robot ``driven`` of a race; the others follow ``policies[i](obs)``.

    ``policies[driven]`` may be None when the keys never leave that robot (``switchable=False``).
    With ``switchable``, ``switch()`` (TAB) hands the keys to the next racing robot, and they move
    on by themselves when the driven robot finishes.
    """

    over_hint = OVER_HINT  # what to do when the race is over (the notebook player says its own)

    def __init__(
        self,
        env: RaceEnv,
        policies: Sequence[Callable | None],
        driven: int = 0,
        seed: int | None = None,
        switchable: bool = True,
    ):
        if not isinstance(env, RaceEnv):
            raise TypeError(f"env: expected a RaceEnv (race_v0.parallel_env(...).unwrapped), got {type(env).__name__}")
        n = env.n_robots
        if len(policies) != n:
            raise ValueError(f"policies: expected one per robot ({n}), got {len(policies)}")
        driven = check_int(driven, "driven", 0, n - 1, message="{name}: must be a robot number in 0..{hi}, got {value}")
        missing = [i for i, p in enumerate(policies) if p is None and (switchable or i != driven)]
        if missing:
            raise ValueError(
                f"policies: robot {missing[0]} has no policy; only the driven robot of a game without switching may lack one"
            )
        self.env, self.policies, self.seed, self.switchable = env, list(policies), seed, switchable
        self.labels: Callable[[int], str] | None = None  # how a robot is named: terminal letters by default
        self.first_driven = self.driven = driven
        self.episode = 0
        self.restart()

    def restart(self) -> None:
        self.obs, _ = self.env.reset(seed=self.seed if self.episode == 0 else None)
        self.episode += 1
        self.driven = self.first_driven
        self.finish_steps: list[int | None] = [None] * self.env.n_robots
        self.last, self.message = "", ""

    # ------------------------------------------------------------------ state
    @property
    def over(self) -> bool:
        return not self.env.agents

    @property
    def steps(self) -> int:
        return self.env.elapsed_steps

    @property
    def racing(self) -> list[int]:
        """The robots still racing: not finished (with ``finished="freeze"`` a finished robot stays
        in ``agents``, parked, until the race ends: the keys never go to it)."""
        if self.over:
            return []
        return [i for i, rank in enumerate(self.env.ranks) if not rank]

    @property
    def driven_racing(self) -> bool:
        return not self.over and not self.env.ranks[self.driven]

    @property
    def robots(self) -> list[Cell | None]:
        """Each robot's cell, None once it has finished (off the board)."""
        return [None if r else c for c, r in zip(self.env.robot_cells, self.env.ranks)]

    def glyph(self, i: int) -> str:
        """A robot's short name: its letter in a text frame (A, B, ...), or ``labels(i)`` if set."""
        return self.labels(i) if self.labels is not None else robot_glyph(i, self.env.n_robots)

    # ------------------------------------------------------------------ commands
    def command(self, cmd: Command | None) -> bool:
        if cmd == RESTART:
            self.restart()
            return True
        if cmd == SWITCH:
            return self.switch()
        if isinstance(cmd, Action):
            return self.act(cmd)
        if cmd != QUIT:
            self.message = "that key does nothing here"
        return False

    def switch(self) -> bool:
        """Drive the next racing robot (robot order, wrapping round)."""
        if not self.switchable:
            self.message = "this race drives one robot only"
            return False
        racing = self.racing
        if not racing:
            self.message = f"the race is over: {self.over_hint}"
            return False
        n = self.env.n_robots
        self.driven = next(i for k in range(1, n + 1) if (i := (self.driven + k) % n) in racing)
        self.last = ""  # the last move was another robot's
        self.message = f"you now drive {self.glyph(self.driven)} (robot_{self.driven})"
        return True

    def act(self, action: int) -> bool:
        """One race step: the driven robot does ``action`` (if it is still racing), the others their policy."""
        if self.over:
            self.message = f"the race is over: {self.over_hint}"
            return False
        self._step({self.driven: int(action)} if self.driven_racing else {})
        if self.driven_racing:
            self.last = outcome_text(action, self._infos[f"robot_{self.driven}"]["outcome"])
        self.message = ""
        if self.switchable and not self.driven_racing and not self.over:
            self.switch()  # the keys move on by themselves: nothing the player does leaves them idle
        return True

    def auto_step(self) -> bool:
        """One step with every racing robot on its policy (the driven one too, if it has one)."""
        if self.over:
            return False
        self._step({})
        return True

    def _step(self, given: dict[int, int]) -> None:
        actions = {}
        ranks = self.env.ranks
        for a in self.env.agents:
            i = self.env.possible_agents.index(a)
            if ranks[i]:  # parked (finished="freeze"): its action is ignored, and it may have no policy
                actions[a] = 0
            else:
                actions[a] = given[i] if i in given else int(self.policies[i](self.obs[a]))
        self.obs, _, _, _, self._infos = self.env.step(actions)
        for a, info in self._infos.items():
            i = self.env.possible_agents.index(a)
            if info.get("rank") and self.finish_steps[i] is None:
                self.finish_steps[i] = self.env.elapsed_steps

    # ------------------------------------------------------------------ text
    def status(self) -> list[str]:
        env = self.env
        rets = "  ".join(f"{self.glyph(i)} {r:g}" for i, r in enumerate(env.returns))
        you = f"you: {self.glyph(self.driven)} (robot_{self.driven})"
        lines = [f"step {env.elapsed_steps}/{env.max_cycles}  {you}" + (f"  last: {self.last}" if self.last else ""),
                 f"returns: {rets}"]  # fmt: skip
        lines += self._goal_lines()
        done = [(r, i) for i, r in enumerate(env.ranks) if r]
        if done:
            lines.append("finished: " + "  ".join(f"{self.glyph(i)} {ordinal(r)}" for r, i in sorted(done)))
        if self.over:
            lines.append(f"the race is over. {self.over_hint}")
        if self.message:
            lines.append(self.message)
        return lines


    def _goal_lines(self) -> list[str]:
        """Own goals: your robot's target, and under lifelong the targets each robot has reached."""
        env = self.env
        if env.goals is None:
            return []
        lines = [f"your target: {env.goals[env.possible_agents[self.driven]]}"] if self.driven_racing else []
        if env.lifelong:
            lines.append("targets reached: " + "  ".join(f"{self.glyph(i)} {k}" for i, k in enumerate(env.goals_reached)))
        return lines


def ordinal(k: int) -> str:
    """1st, 2nd, 3rd, 4th, ... 11th, 21st."""
    return f"{k}{'th' if 10 <= k % 100 <= 20 else {1: 'st', 2: 'nd', 3: 'rd'}.get(k % 10, 'th')}"

