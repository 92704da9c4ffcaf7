"""Agent-steps per second of the race (PettingZoo ParallelEnv) beside multigrid's PettingZoo env.

    python benchmarks/bench_race.py            # a few seconds per round
    python benchmarks/bench_race.py --quick    # CI: short rounds (9 of 4,000 joint steps)

Part 1, the race as users of a 4-robot race run it: an open 8x8 level with the
level's own four corner starts and the exit inside, ``max_cycles=200``, random actions, each
robot leaving at the exit and the race reset when all are gone; agent-steps are counted over
the agents present at each step (late in a race the fixed cost of a step is shared by fewer
robots). The peer: multigrid's ``Empty`` through its PettingZoo wrapper, 8x8, 4 agents, random
starts, ``max_steps=200``, ``success_termination_mode="all"`` (each agent leaves at the goal).
After an untimed warm-up the two take turns every ``CHUNK`` joint steps (who goes first
alternates), timed in CPU time of this process (``time.process_time``: both are single-threaded
Python, and other jobs on a busy machine stretch wall time, not CPU time); each round's ratio is measured in that round, the
target (``CORNERS_TARGET``) is judged on the median of the rounds' ratios, and the spread
printed is over the rounds. Exit status 1 below it.

Part 2 (wall time): both envs run the same loop in the same process, interleaved round by round: 4 agents,
uniformly random actions drawn before timing, a reset whenever no agent is left. The peer is
``multigrid`` (pip package ``multigrid``, ``MultiGrid-Empty``) on an 8x8 grid with 4 agents,
through its own PettingZoo wrapper. Figures are medians over rounds; the ratio is per
agent-step (higher is better for babyrobot_marl). The first rows run the peer's grid: an
empty 8x8 level with the exit in a corner and random starts; the others, built-in levels
with walls, puddles and glass. Needs the ``bench`` extra for the peer.

Target: every ``block`` row at least ``TARGET`` times the peer's agent-steps per second (the
ratio printed last); the script exits with status 1 when a row or part 1 misses its target (no
peer: no target).
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import sys
import time
from collections.abc import Callable

import numpy as np

from babyrobot_marl import race_v0

# The peer's grid: 8x8 open floor, the exit in the bottom-right corner, random starts.
TARGET = 2.0  # x multigrid, for the block rows: the lowest ratio seen over repeated runs on a shared 2-core machine was 2.06
CORNERS_TARGET = 3.0  # x multigrid, part 1's floor (aim: 5x)
CHUNK = 200  # joint steps per turn in part 1
# Part 1's level: open 8x8 floor, the four starts in the corners, the exit inside.
CORNERS_8X8 = "\n".join(
    ["+" + "-+" * 8, "|0" + " " * 13 + "1|"]
    + ["+" + " +" * 8, "|" + " " * 15 + "|"] * 2
    + ["+" + " +" * 8, "|" + " " * 6 + "E" + " " * 8 + "|"]
    + ["+" + " +" * 8, "|" + " " * 15 + "|"] * 3
    + ["+" + " +" * 8, "|3" + " " * 13 + "2|", "+" + "-+" * 8]
)
EMPTY_8X8 = "\n".join(["+" + "-+" * 8] + ["|" + " " * 15 + "|", "+" + " +" * 8] * 7 + ["|" + " " * 14 + "E|", "+" + "-+" * 8])


class Stepper:
    """Steps one env through pre-drawn joint actions, a chunk at a time (so that two envs can take
    turns every few hundred steps), resetting it when no agent is left; counts the agents present
    at each step and the ``clock`` time spent stepping. ``act_all``: an action for every possible
    agent (multigrid indexes one for each, present or not)."""

    def __init__(self, env, actions: list[list[int]], act_all: bool = False, clock: Callable[[], float] = time.perf_counter):
        self.env, self.actions, self.act_all, self.clock = env, actions, act_all, clock
        self.done = self.agent_steps = 0
        self.seconds = 0.0
        env.reset(seed=0)

    def run(self, steps: int) -> None:
        env, everyone, act_all, agent_steps = self.env, self.env.possible_agents, self.act_all, 0
        rows = self.actions[self.done : self.done + steps]
        t0 = self.clock()
        for row in rows:
            agents = env.agents
            if not agents:
                env.reset()
                agents = env.agents
            env.step({a: row[k] for k, a in enumerate(everyone if act_all else agents)})
            agent_steps += len(agents)
        self.seconds += self.clock() - t0
        self.done += len(rows)
        self.agent_steps += agent_steps

    @property
    def per_agent_step(self) -> float:
        return self.seconds / self.agent_steps


def agent_step_time(
    env, actions: list[list[int]], act_all: bool = False, clock: Callable[[], float] = time.perf_counter
) -> float:
    """Seconds per agent-step over the pre-drawn joint actions, counting the agents present at each step."""
    stepper = Stepper(env, actions, act_all, clock)
    stepper.run(len(actions))
    return stepper.per_agent_step


def taking_turns(ours: Stepper, peer: Stepper, steps: int, chunk: int = CHUNK) -> tuple[float, float]:
    """CPU seconds per agent-step of each, the two stepping in turns of ``chunk`` joint steps (who goes
    first alternates): a slow spell of a busy machine hits both alike."""
    for k, start in enumerate(range(0, steps, chunk)):
        turn = min(chunk, steps - start)
        for stepper in (ours, peer) if k % 2 == 0 else (peer, ours):
            stepper.run(turn)
    return ours.per_agent_step, peer.per_agent_step


def multigrid_env(n_agents: int, **kwargs):
    from multigrid.envs import EmptyEnv
    from multigrid.pettingzoo import to_pettingzoo_env

    return to_pettingzoo_env(EmptyEnv, metadata={"name": "empty_v0"})(size=8, agents=n_agents, agent_start_pos=None, **kwargs)


def random_actions(env, rng: np.random.Generator, steps: int, n: int, babyrobot: bool) -> list[list[int]]:
    n_actions = int(env.action_space(env.possible_agents[0]).n)
    return rng.integers(0, min(n_actions, 5 if babyrobot else n_actions), (steps, n)).tolist()


def corners(steps: int, rounds: int, rng: np.random.Generator) -> float | None:
    """Part 1: the issue-28 race beside multigrid, taking turns; the median of the rounds' ratios (None: no peer)."""
    n = 4
    ours = race_v0.parallel_env(level=CORNERS_8X8, n_robots=n, max_cycles=200)
    print("1. open 8x8, the level's four corner starts, max_cycles=200, robots leaving at the exit, 4 robots, random actions")
    if importlib.util.find_spec("multigrid") is None:
        runs = [agent_step_time(ours, random_actions(ours, rng, steps, n, True), clock=time.process_time) for _ in range(rounds)]
        t = statistics.median(runs)
        print(f"babyrobot {t * 1e6:.2f} us/agent-step; multigrid is not installed (pip install -e '.[bench]'): no peer")
        return None
    peer = multigrid_env(n, max_steps=200, success_termination_mode="all")
    for env, b in ((ours, True), (peer, False)):  # a warm-up, not counted (caches, lazy imports)
        Stepper(env, random_actions(env, rng, 1_000, n, b), not b).run(1_000)
    ratios, ours_t, peer_t = [], [], []
    for _ in range(rounds):
        a = Stepper(ours, random_actions(ours, rng, steps, n, True), False, time.process_time)
        b = Stepper(peer, random_actions(peer, rng, steps, n, False), True, time.process_time)
        t, p = taking_turns(a, b, steps)
        ours_t.append(t)
        peer_t.append(p)
        ratios.append(p / t)
    ratio = statistics.median(ratios)
    print(f"{'env (CPU time)':32s} {'us/agent-step':>14s} {'agent-steps/s':>14s} {'vs multigrid':>13s}")
    t, p = statistics.median(ours_t), statistics.median(peer_t)
    spread = f"(rounds: {min(ratios):.2f}-{max(ratios):.2f}x)"
    print(f"{'babyrobot corners-8x8 block':32s} {t * 1e6:14.2f} {1 / t:14,.0f} {ratio:12.2f}x  {spread}")
    print(f"{'multigrid Empty-8x8 (peer)':32s} {p * 1e6:14.2f} {1 / p:14,.0f}")
    ok = ratio >= CORNERS_TARGET
    print(f"target: at least {CORNERS_TARGET:.1f}x multigrid (median of {rounds} rounds' ratios): {'met' if ok else 'MISSED'}\n")
    return ratio


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="short rounds for CI: the figures printed, the targets not judged")
    parser.add_argument("--steps", type=int, default=20_000, help="joint steps per round")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args(argv)
    steps, rounds = (4_000, 9) if args.quick else (args.steps, args.rounds)
    rng = np.random.default_rng(0)
    corner_ratio = corners(steps, rounds, rng)
    print("2. 8x8 levels, random starts or the level's, 4 robots (the peer with multigrid's defaults: the first agent")
    print("   at the goal ends its episode), wall time")
    n = 4
    envs: dict[str, Callable[[], object]] = {
        "babyrobot empty 8x8 block": lambda: race_v0.parallel_env(level=EMPTY_8X8, n_robots=n, start="random"),
        "babyrobot empty 8x8 pass": lambda: race_v0.parallel_env(level=EMPTY_8X8, n_robots=n, start="random", collisions="pass"),
        "babyrobot race-4 block": lambda: race_v0.parallel_env(level="race-4", n_robots=n),
        "babyrobot race-4 pass": lambda: race_v0.parallel_env(level="race-4", n_robots=n, collisions="pass"),
        "babyrobot maze-8x8 block": lambda: race_v0.parallel_env(level="maze-8x8", n_robots=n, start="random"),
    }
    if importlib.util.find_spec("multigrid") is not None:
        envs["multigrid Empty-8x8 (peer)"] = lambda: multigrid_env(n)
    times: dict[str, list[float]] = {name: [] for name in envs}
    built = {name: make() for name, make in envs.items()}
    for _ in range(rounds):
        for name, env in built.items():
            times[name].append(agent_step_time(env, random_actions(env, rng, steps, n, "babyrobot" in name)))
    peer = "multigrid Empty-8x8 (peer)"
    peer_t = statistics.median(times[peer]) if peer in times and times[peer] else None
    print(f"{'env (4 agents, random actions)':32s} {'us/agent-step':>14s} {'agent-steps/s':>14s} {'vs multigrid':>13s}")
    for name, ts in times.items():
        t = statistics.median(ts)
        ratio = f"{peer_t / t:12.2f}x" if peer_t else "   (no peer)"
        print(f"{name:32s} {t * 1e6:14.2f} {1 / t:14,.0f} {ratio}")
    if peer_t is None:
        print("multigrid is not installed (pip install -e '.[bench]'): no peer figure, no target")
        return 0
    worst = min(peer_t / statistics.median(ts) for name, ts in times.items() if name.endswith("block"))
    ok = worst >= TARGET
    print(f"target: every block row at least {TARGET:.1f}x multigrid; lowest {worst:.2f}x: {'met' if ok else 'MISSED'}")
    if args.quick:  # short rounds on a possibly busy machine: the figures are printed, not judged
        print("(--quick: a smoke run, too short to judge; the targets are judged without --quick)")
        return 0
    return 0 if ok and corner_ratio is not None and corner_ratio >= CORNERS_TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
