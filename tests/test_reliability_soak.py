"""Long runs: a soak of random races on every built-in level, under every collision mode and
finished option, with the step invariants checked cheaply; and no memory growth across 10,000
resets of the single-robot env, the race and the race as a Gymnasium env.

The soak's size is ``SOAK_AGENT_STEPS`` agent-steps in all (an agent-step is one robot's action
in one race step), measured to take about a minute on a 2-core machine.
"""

from __future__ import annotations

import gc
import tracemalloc
from itertools import product

import numpy as np
import pytest

from babyrobot_marl import BabyRobotEnv, Rules, levels, race_v0
from babyrobot_marl.core.rules import COLLISION_MODES
from babyrobot_marl.envs.race_gym import BabyRobotRaceEnv
from babyrobot_marl.policies import ShortestPathPolicy
from tests.strategies import cell_reward, edge, free_cells

SOAK_AGENT_STEPS = 1_000_000
N_ROBOTS = 4
EXPLORE = 0.3  # each robot acts at random with this probability, else like the shortest-path robot
CONFIGS = list(product(levels.names(), COLLISION_MODES, ("remove", "freeze")))


def soak_one(name: str, mode: str, finished: str, budget: int, seed: int) -> dict[str, int]:
    """Random races until ``budget`` agent-steps have been taken; returns what happened."""
    level = levels.get(name)
    rules = Rules(exit_reward=1.0, collisions=mode)  # a non-zero exit reward: a parked robot's 0 is told apart
    n = min(N_ROBOTS, len(free_cells(level)))
    env = race_v0.parallel_env(level=name, n_robots=n, rules=rules, finished=finished, start="fill", max_cycles=150)
    width, height = level.width, level.height
    walls, blocked, exits = level.walls, level.blocked, level.exits
    glass_passes = rules.glass_pass_prob > 0
    reward_of = {(x, y): cell_reward(level, rules, (x, y)) for y in range(height) for x in range(width)}
    allowed = set(reward_of.values()) | {reward_of[c] + rules.win_bonus for c in exits} | {0.0}
    policy = ShortestPathPolicy(env.table)
    rng = np.random.default_rng(seed)
    agents_all = env.possible_agents
    stats = {"agent_steps": 0, "races": 0, "finished": 0, "blocked": 0}
    while stats["agent_steps"] < budget:
        obs, infos = env.reset(seed=seed if stats["races"] == 0 else None)
        stats["races"] += 1
        cells = {a: tuple(infos[a]["cell"].tolist()) for a in agents_all}
        parked: set[str] = set()
        t = 0
        while env.agents:
            explore = rng.random(len(env.agents)) < EXPLORE
            randoms = rng.integers(0, 5, size=len(env.agents))
            actions = {a: int(randoms[k]) if explore[k] else policy(obs[a]) for k, a in enumerate(env.agents)}
            obs, rewards, terms, truncs, infos = env.step(actions)
            t += 1
            stats["agent_steps"] += len(actions)
            assert t <= env.max_cycles
            racing_cells, moves = [], []
            for a, info in infos.items():
                c, before = tuple(info["cell"].tolist()), cells[a]
                assert 0 <= c[0] < width and 0 <= c[1] < height and c not in blocked, (name, a, c)
                assert obs[a][0] == c[0] and obs[a][1] == c[1]
                assert rewards[a] in allowed, (name, a, rewards[a])
                if a in parked:
                    assert c == before and rewards[a] == 0.0, (name, a)
                    continue
                d = abs(c[0] - before[0]) + abs(c[1] - before[1])
                assert d <= 1, (name, a, before, c)
                if d:
                    e = edge(before, c)
                    assert e not in walls and (glass_passes or e not in level.glass), (name, a, e)
                if actions[a] == 0:
                    assert d == 0
                if info["blocked"]:
                    stats["blocked"] += 1
                racing_cells.append(c)
                if d:
                    moves.append((before, c))
                if info["finished"]:
                    assert c in exits
                    stats["finished"] += 1
                    parked.add(a)
                cells[a] = c
            if mode != "pass":
                assert len(set(racing_cells)) == len(racing_cells), (name, mode, racing_cells)
                swaps = {(b, a) for a, b in moves} & set(moves)
                assert not swaps, (name, mode, swaps)
            if finished == "remove":
                assert not parked & set(env.agents), "a finished robot came back"
        assert t <= env.max_cycles
    return stats


@pytest.mark.slow
def test_soak_random_races_on_every_builtin_level_keep_the_invariants():
    budget = SOAK_AGENT_STEPS // len(CONFIGS)
    totals = {"agent_steps": 0, "races": 0, "finished": 0, "blocked": 0}
    for k, (name, mode, finished) in enumerate(CONFIGS):
        stats = soak_one(name, mode, finished, budget, seed=1000 + k)
        for key, value in stats.items():
            totals[key] += value
        assert stats["finished"] > 0, (name, mode, finished)  # races really were run to their end
        if mode == "pass":
            assert stats["blocked"] == 0
    assert totals["agent_steps"] >= SOAK_AGENT_STEPS - len(CONFIGS) * N_ROBOTS
    assert totals["blocked"] > 0  # collisions really happened under block and bounce
    print(f"soak: {totals}")


# --------------------------------------------------------------------------------------- memory
RESETS = 10_000
TOLERANCE = 32 * 1024  # bytes: far below one leaked object per reset (10,000 resets)


def single_episode(env, k: int) -> None:
    env.reset(seed=k if k % 1000 == 0 else None)
    for a in (2, 3, 2):
        _, _, terminated, truncated, _ = env.step(a)
        if terminated or truncated:
            break


def race_episode(env, k: int) -> None:
    env.reset(seed=k if k % 1000 == 0 else None)
    for a in (2, 3, 2):
        if not env.agents:
            break
        env.step(dict.fromkeys(env.agents, a))


ENVS = {
    "single": (lambda: BabyRobotEnv("mixed-8x8", start="random"), single_episode),
    "race": (lambda: race_v0.parallel_env(level="race-4", n_robots=4, start="random", finished="freeze"), race_episode),
    "race-gym": (lambda: BabyRobotRaceEnv(level="race-2", opponents=["random"]), single_episode),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(ENVS))
def test_no_memory_growth_across_10000_resets(name):
    factory, episode = ENVS[name]
    env = factory()
    for k in range(200):  # warm-up: caches, lazily built tables
        episode(env, k)
    tracemalloc.start()
    try:
        for k in range(200):
            episode(env, k)
        gc.collect()
        before = tracemalloc.get_traced_memory()[0]
        for k in range(RESETS):
            episode(env, k)
        gc.collect()
        after = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    assert after - before < TOLERANCE, f"{name}: traced memory grew by {after - before} bytes over {RESETS} resets"
