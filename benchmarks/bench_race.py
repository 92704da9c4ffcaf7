"""Agent-steps per second of the race (PettingZoo ParallelEnv) beside multigrid's PettingZoo env.

    python benchmarks/bench_race.py            # a few seconds per round
    python benchmarks/bench_race.py --quick    # CI: one short round

Both envs run the same loop in the same process, interleaved round by round: 4 agents,
uniformly random actions drawn before timing, a reset whenever no agent is left. The peer is
``multigrid`` (pip package ``multigrid``, ``MultiGrid-Empty``) on an 8x8 grid with 4 agents,
through its own PettingZoo wrapper. Figures are medians over rounds; the ratio is per
agent-step (higher is better for babyrobot_marl). The first rows run the peer's grid: an
empty 8x8 level with the exit in a corner and random starts; the others, built-in levels
with walls, puddles and glass. Needs the ``bench`` extra for the peer.

Target: every ``block`` row at least ``TARGET`` times the peer's agent-steps per second (the
ratio printed last); the script exits with status 1 when a row misses it (no peer: no target).
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
EMPTY_8X8 = "\n".join(["+" + "-+" * 8] + ["|" + " " * 15 + "|", "+" + " +" * 8] * 7 + ["|" + " " * 14 + "E|", "+" + "-+" * 8])


def agent_step_time(env, actions: list[list[int]]) -> float:
    """Seconds per agent-step over the pre-drawn joint actions."""
    env.reset(seed=0)
    agent_steps = 0
    t0 = time.perf_counter()
    for row in actions:
        agents = env.agents
        if not agents:
            env.reset()
            agents = env.agents
        env.step({a: row[k] for k, a in enumerate(agents)})
        agent_steps += len(agents)
    return (time.perf_counter() - t0) / agent_steps


def multigrid_env(n_agents: int):
    from multigrid.envs import EmptyEnv
    from multigrid.pettingzoo import to_pettingzoo_env

    return to_pettingzoo_env(EmptyEnv, metadata={"name": "empty_v0"})(size=8, agents=n_agents, agent_start_pos=None)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="one short round (for CI)")
    parser.add_argument("--steps", type=int, default=20_000, help="joint steps per round")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args(argv)
    steps, rounds = (2_000, 1) if args.quick else (args.steps, args.rounds)
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
    rng = np.random.default_rng(0)
    times: dict[str, list[float]] = {name: [] for name in envs}
    built = {name: make() for name, make in envs.items()}
    for _ in range(rounds):
        for name, env in built.items():
            n_actions = int(env.action_space(env.possible_agents[0]).n)
            actions = rng.integers(0, min(n_actions, 5 if "babyrobot" in name else n_actions), (steps, n)).tolist()
            times[name].append(agent_step_time(env, actions))
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
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
