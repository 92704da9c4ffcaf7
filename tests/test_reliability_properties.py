"""Property-based reliability tests: random levels (1x1 to 32x32: random grids and decorated mazes),
random rules, robot counts, start modes, collision modes, finished options and action sequences.

Every step is checked against oracles written from DESIGN.md (``tests/strategies.py``), not from
the compiled tables: robots stay on the grid, out of blocked cells, cross no wall (glass only when
glass passes), move at most one cell, never share a cell or swap under block/bounce; finished robots
never act again; rewards are exactly the cell's reward (plus the win bonus for first finishers, 0
for parked robots); episodes end by max_cycles / max_steps at the latest; observations lie in
their spaces. Levels on which the robots cannot be placed must raise a ValueError naming
n_robots / level instead.

Run with ``--hypothesis-show-statistics`` to see how many examples each property ran.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from babyrobot_marl import BabyRobotEnv, race_v0
from babyrobot_marl.core.outcomes import OUTCOME_NAMES
from babyrobot_marl.envs.race_gym import BabyRobotRaceEnv
from babyrobot_marl.policies import ShortestPathPolicy
from tests.strategies import (
    ACTION_TOKENS,
    DELTAS,
    SEEDS,
    SHORTEST,
    cell_reward,
    check_move,
    check_outcome,
    free_cells,
    grid_levels,
    rules,
)

HEALTH = [HealthCheck.too_slow, HealthCheck.data_too_large]


def examples(n: int) -> settings:
    """Sized so that this file runs in about 20-40 s on a 2-core machine."""
    return settings(max_examples=n, deadline=None, suppress_health_check=HEALTH)


FINISHED = ("remove", "freeze")
START_MODES = ("level", "fill", "random")


def max_cycles_for(level, draw_value):
    """Explicit short horizons, or the default (only on small levels, where it is short)."""
    if draw_value is None and level.n_cells > 64:
        return 60
    return draw_value


def size_bucket(level) -> str:
    side = max(level.width, level.height)
    return "1" if side == 1 else "2-4" if side <= 4 else "5-12" if side <= 12 else "13-32"


def pick(token: int, policy: ShortestPathPolicy, obs) -> int:
    return policy(obs) if token == SHORTEST else token


# --------------------------------------------------------------------------------------- race (parallel)
def race_fits(level, n_robots: int, start: str) -> bool:
    if start == "level":
        return n_robots <= len(level.starts)
    return n_robots <= len(free_cells(level))


def check_race_episode(env, level, rules_, tokens, finished, first_reset_seed, policy):
    """One race from reset to its end, every step checked; returns the number of steps."""
    n = env.n_robots
    agents_all = [f"robot_{i}" for i in range(n)]
    assert env.possible_agents == agents_all
    obs, infos = env.reset(seed=first_reset_seed)
    assert env.agents == agents_all and set(obs) == set(infos) == set(agents_all)
    cells = [tuple(infos[a]["cell"].tolist()) for a in agents_all]
    for i, a in enumerate(agents_all):
        assert env.observation_space(a).contains(obs[a]), (a, obs[a])
        assert tuple(obs[a][:2]) == cells[i]
        assert cells[i] in free_cells(level) or cells[i] in level.starts
        assert infos[a]["finished"] is False
    if env.start == "level":
        assert cells == list(level.starts[:n])
    if rules_.collisions != "pass":
        assert len(set(cells)) == n, f"robots share a start cell: {cells}"
    racing = [True] * n
    removed: set[str] = set()
    anyone_finished = False
    n_finished = 0
    returns = [0.0] * n
    blocked_steps = [0] * n
    t = 0
    while env.agents:
        assert t < env.max_cycles, "the race went on past max_cycles"
        reported = list(env.agents)
        if finished == "remove":
            assert reported == [a for i, a in enumerate(agents_all) if racing[i]]
            assert not removed & set(reported), "a removed agent came back"
        else:
            assert reported == agents_all, "freeze must keep every agent until the race ends"
        actions = {}
        for a in reported:
            i = int(a.split("_")[1])
            actions[a] = pick(tokens[(t * n + i) % len(tokens)], policy, obs[a])
        obs, rews, terms, truncs, infos = env.step(actions)
        t += 1
        assert set(obs) == set(rews) == set(terms) == set(truncs) == set(infos) == set(reported)
        new_cells = list(cells)
        for a in reported:
            i = int(a.split("_")[1])
            new_cells[i] = tuple(infos[a]["cell"].tolist())
            assert tuple(obs[a][:2]) == new_cells[i], "own [x, y] differs from info['cell']"
            assert env.observation_space(a).contains(obs[a]), (a, obs[a])
            assert isinstance(rews[a], float)
        finishing = []
        for i, a in enumerate(agents_all):
            if a not in reported or not racing[i]:
                continue
            info = infos[a]
            check_move(level, rules_, cells[i], new_cells[i], actions[a])
            if info["blocked"]:
                assert rules_.collisions != "pass", "blocked by another robot under 'pass'"
                assert new_cells[i] == cells[i], "a robot blocked by another must stay"
            if not info["blocked"]:  # what its own move gave (a robot stopped by another stays)
                check_outcome(level, rules_, cells[i], new_cells[i], actions[a], OUTCOME_NAMES[info["outcome"]])
                if OUTCOME_NAMES[info["outcome"]] == "moved":
                    dx, dy = DELTAS[actions[a]]
                    assert new_cells[i] == (cells[i][0] + dx, cells[i][1] + dy)
            if new_cells[i] in level.exits:
                finishing.append(i)
            assert info["finished"] == (new_cells[i] in level.exits)
        racing_now = [r and i not in finishing for i, r in enumerate(racing)]
        over = t >= env.max_cycles or not any(racing_now)
        if rules_.collisions != "pass":
            live = [i for i in range(n) if racing[i]]
            finals = [new_cells[i] for i in live]
            assert len(set(finals)) == len(finals), f"robots share a cell under {rules_.collisions}: {finals}"
            for i in live:
                for j in live:
                    if i < j:
                        assert not (new_cells[i] == cells[j] and new_cells[j] == cells[i] and cells[i] != cells[j]), "swap"
        for i, a in enumerate(agents_all):
            if a not in reported:
                continue
            if racing[i]:
                expected = cell_reward(level, rules_, new_cells[i])
                if i in finishing and not anyone_finished:
                    expected += rules_.win_bonus
                assert rews[a] == pytest.approx(expected, abs=1e-12), (a, new_cells[i], rews[a], expected)
                if i in finishing:
                    assert terms[a] == (finished == "remove" or over)
                    assert truncs[a] is False
                    assert infos[a]["rank"] == n_finished + 1, "robots finishing in one step share the next rank"
                else:
                    assert terms[a] is False
                    assert truncs[a] == over
            else:  # parked (freeze): never moves, never earns, terminated only when the race ends
                assert finished == "freeze"
                assert new_cells[i] == cells[i] and new_cells[i] in level.exits
                assert rews[a] == 0.0
                assert terms[a] == over and truncs[a] is False
                assert infos[a]["finished"] is True
        # the other robots' [x, y, finished], next robot first (race_v0 docstring)
        flags = [0 if r else 1 for r in racing_now]
        for a in reported:
            i = int(a.split("_")[1])
            others = [[*new_cells[(i + k) % n], flags[(i + k) % n]] for k in range(1, n)]
            assert obs[a][2:].reshape(-1, 3).tolist() == others
        state = env.state()
        assert env.state_space.contains(state), state
        assert state.reshape(-1, 3).tolist() == [[*new_cells[i], flags[i]] for i in range(n)]
        if finishing:
            event("race: a robot finished")
        if any(infos[a]["blocked"] for a in reported):
            event("race: a robot was blocked by another")
        anyone_finished = anyone_finished or bool(finishing)
        n_finished += len(finishing)
        for a in reported:
            i = int(a.split("_")[1])
            returns[i] += rews[a]
            blocked_steps[i] += bool(infos[a]["blocked"])
        assert env.returns == pytest.approx(returns)
        assert env.collisions_count == blocked_steps
        assert sorted(r for r in env.ranks if r) == sorted(env.ranks[i] for i in range(n) if not racing_now[i])
        if finished == "remove":
            removed |= {agents_all[i] for i in finishing}
            if removed and env.agents:
                gone = sorted(removed)[0]
                # a removed robot's action is checked (then ignored, as PettingZoo's conversions do)
                with pytest.raises(ValueError, match=gone):
                    env.step({**dict.fromkeys(env.agents, 0), gone: 9})
        cells, racing = new_cells, racing_now
        if over:
            assert env.agents == [], "the race should be over"
    assert t <= env.max_cycles
    assert env.elapsed_steps == t
    return t


@examples(1000)
@given(
    level=grid_levels(),
    rules_=rules(),
    n_robots=st.one_of(st.integers(1, 4), st.integers(1, 12)),
    start=st.sampled_from(START_MODES),
    finished=st.sampled_from(FINISHED),
    max_cycles=st.one_of(st.none(), st.integers(1, 60)),
    seed=SEEDS,
    tokens=ACTION_TOKENS,
)
def test_race_robots_obey_the_map_the_collision_rules_and_the_reward_rules(
    level, rules_, n_robots, start, finished, max_cycles, seed, tokens
):
    max_cycles = max_cycles_for(level, max_cycles)
    kwargs = {
        "level": level,
        "n_robots": n_robots,
        "start": start,
        "finished": finished,
        "rules": rules_,
        "max_cycles": max_cycles,
    }
    event(f"level side {size_bucket(level)}")
    if not race_fits(level, n_robots, start):
        event("robots do not fit: ValueError")
        with pytest.raises(ValueError, match="n_robots") as info:
            race_v0.parallel_env(**kwargs)
        assert "level" in str(info.value)
        return
    env = race_v0.parallel_env(**kwargs)
    assert env.max_cycles == (max(100, 4 * level.n_cells) if max_cycles is None else max_cycles)
    policy = ShortestPathPolicy(env.table)
    check_race_episode(env, level, rules_, tokens, finished, seed, policy)
    # a second race on the same env, without a seed: the same rules hold after a reset
    check_race_episode(env, level, rules_, tokens[::-1], finished, None, policy)


# --------------------------------------------------------------------------------------- single robot
def single_fits(level, start) -> bool:
    if start == "random" or not level.starts:
        return bool(free_cells(level))
    return True


@examples(800)
@given(
    level=grid_levels(),
    rules_=rules(collisions="block"),
    start=st.sampled_from([None, "random"]),
    max_steps=st.one_of(st.none(), st.integers(1, 80)),
    seed=SEEDS,
    tokens=ACTION_TOKENS,
    episodes=st.integers(1, 3),
)
def test_single_robot_obeys_the_map_and_the_reward_rules(level, rules_, start, max_steps, seed, tokens, episodes):
    max_steps = max_cycles_for(level, max_steps)
    event(f"level side {size_bucket(level)}")
    if not single_fits(level, start):
        event("robot does not fit: ValueError")
        with pytest.raises(ValueError, match="level"):
            BabyRobotEnv(level=level, rules=rules_, start=start, max_steps=max_steps)
        return
    env = BabyRobotEnv(level=level, rules=rules_, start=start, max_steps=max_steps)
    assert env.max_steps == (max(100, 4 * level.n_cells) if max_steps is None else max_steps)
    policy = ShortestPathPolicy(env.table)
    free = free_cells(level)
    k = 0
    for episode in range(episodes):
        obs, info = env.reset(seed=seed if episode == 0 else None)
        cell = tuple(info["cell"].tolist())
        assert env.observation_space.contains(obs) and tuple(obs) == cell
        if start == "random" or not level.starts:
            assert cell in free
        else:
            assert cell == level.starts[0]
        for t in range(1, env.max_steps + 1):
            action = pick(tokens[k % len(tokens)], policy, obs)
            k += 1
            obs, reward, terminated, truncated, info = env.step(action)
            new = tuple(info["cell"].tolist())
            assert env.observation_space.contains(obs) and tuple(obs) == new
            check_move(level, rules_, cell, new, action)
            assert isinstance(reward, float)
            assert reward == cell_reward(level, rules_, new)
            assert terminated == (new in level.exits)
            assert truncated == (not terminated and t == env.max_steps)
            assert info["intended"] == (OUTCOME_NAMES[info["outcome"]] in ("moved", "stayed"))
            check_outcome(level, rules_, cell, new, action, OUTCOME_NAMES[info["outcome"]])
            if OUTCOME_NAMES[info["outcome"]] == "moved":
                assert new == (cell[0] + DELTAS[action][0], cell[1] + DELTAS[action][1])
            cell = new
            if terminated:
                event("single: reached an exit")
            if terminated or truncated:
                break
        else:
            pytest.fail("the episode went on past max_steps")
        assert env.elapsed_steps == t <= env.max_steps
        with pytest.raises(RuntimeError):
            env.step(0)


# --------------------------------------------------------------------------------------- race as a Gymnasium env
@examples(600)
@given(
    level=grid_levels(max_side=16),
    rules_=rules(),
    opponents=st.lists(st.sampled_from(["random", "shortest"]), max_size=4),
    start=st.sampled_from(START_MODES),
    max_cycles=st.integers(1, 60),
    seed=SEEDS,
    tokens=ACTION_TOKENS,
)
def test_race_gym_learner_and_opponents_obey_the_map_and_the_rewards(level, rules_, opponents, start, max_cycles, seed, tokens):
    n = 1 + len(opponents)
    kwargs = {"level": level, "opponents": opponents, "start": start, "rules": rules_, "max_cycles": max_cycles}
    event(f"level side {size_bucket(level)}")
    if not race_fits(level, n, start):
        event("robots do not fit: ValueError")
        with pytest.raises(ValueError, match="n_robots") as info:
            BabyRobotRaceEnv(**kwargs)
        assert "level" in str(info.value)
        return
    env = BabyRobotRaceEnv(**kwargs)
    policy = ShortestPathPolicy(env.race.table)
    for episode in range(2):
        obs, info = env.reset(seed=seed if episode == 0 else None)
        assert env.observation_space.contains(obs)
        cells = [tuple(obs[:2])] + [tuple(o[:2]) for o in obs[2:].reshape(-1, 3)]
        done = [0] * n
        for t in range(1, max_cycles + 1):
            action = pick(tokens[t % len(tokens)], policy, obs)
            obs, reward, terminated, truncated, info = env.step(action)
            assert env.observation_space.contains(obs)
            others = obs[2:].reshape(-1, 3)
            new = [tuple(obs[:2])] + [tuple(o[:2]) for o in others]
            new_done = [0] + [int(o[2]) for o in others]
            assert new[0] == tuple(info["cell"].tolist())
            check_move(level, rules_, cells[0], new[0], action)
            for j in range(1, n):
                if done[j]:
                    assert new_done[j] == 1 and new[j] == cells[j], "a parked opponent moved"
                else:
                    check_move(level, rules_, cells[j], new[j], None)
                    assert new_done[j] == (new[j] in level.exits)
            if rules_.collisions != "pass":
                live = [new[j] for j in range(n) if not done[j]]
                assert len(set(live)) == len(live), f"robots share a cell: {live}"
            expected = cell_reward(level, rules_, new[0])
            if new[0] in level.exits and not any(done):
                expected += rules_.win_bonus
            assert reward == pytest.approx(expected, abs=1e-12)
            assert terminated == (new[0] in level.exits)
            assert truncated == (not terminated and t == max_cycles)
            assert info["ranks"][0] == (info.get("rank", 0))
            if terminated:
                event("race gym: the learner finished")
            cells, done = new, [0] + new_done[1:]
            if terminated or truncated:
                break
        else:
            pytest.fail("the episode went on past max_cycles")
        with pytest.raises(RuntimeError):
            env.step(0)


# --------------------------------------------------------------------------------------- AEC = parallel
@examples(300)
@given(
    level=grid_levels(max_side=10),
    rules_=rules(),
    n_robots=st.integers(1, 4),
    finished=st.sampled_from(FINISHED),
    seed=SEEDS,
    tokens=st.lists(st.integers(0, 4), min_size=1, max_size=40),
)
def test_aec_race_pays_the_same_returns_as_the_parallel_race(level, rules_, n_robots, finished, seed, tokens):
    if not race_fits(level, n_robots, "fill"):
        return
    kwargs = {"level": level, "n_robots": n_robots, "start": "fill", "finished": finished, "rules": rules_, "max_cycles": 30}

    def token(step: int, agent: str) -> int:
        return tokens[(step + int(agent.split("_")[1])) % len(tokens)]

    par = race_v0.parallel_env(**kwargs)
    par.reset(seed=seed)
    par_returns = dict.fromkeys(par.possible_agents, 0.0)
    while par.agents:
        step = par.elapsed_steps
        _, rews, _, _, _ = par.step({a: token(step, a) for a in par.agents})
        for a, r in rews.items():
            par_returns[a] += r
    aec = race_v0.env(**kwargs)
    aec.reset(seed=seed)
    race = aec.unwrapped
    aec_returns = dict.fromkeys(aec.possible_agents, 0.0)
    for agent in aec.agent_iter():
        _, reward, term, trunc, _ = aec.last()
        aec_returns[agent] += reward
        aec.step(None if term or trunc else token(race.elapsed_steps, agent))
    assert aec_returns == pytest.approx(par_returns)
    assert race.elapsed_steps == par.elapsed_steps
    assert race.robot_cells == par.robot_cells


# --------------------------------------------------------------------------------------- batch = separate envs
@examples(300)
@given(
    level=grid_levels(max_side=16),
    rules_=rules(),
    n_robots=st.integers(1, 6),
    start=st.sampled_from(START_MODES),
    seed=SEEDS,
    tokens=st.lists(st.integers(0, 4), min_size=1, max_size=40),
)
def test_batch_engine_plays_the_same_races_as_separate_envs_on_random_levels(level, rules_, n_robots, start, seed, tokens):
    """core.batch claims bit-identity with race_v0 (finished="freeze") for the same seeds and actions."""
    if not race_fits(level, n_robots, start):
        return
    n_envs = 3
    kwargs = {"level": level, "n_robots": n_robots, "start": start, "finished": "freeze", "rules": rules_, "max_cycles": 25}
    envs = [race_v0.parallel_env(**kwargs) for _ in range(n_envs)]
    first = envs[0]
    batch = first.batch(n_envs)
    batch.seed([seed + i for i in range(n_envs)])
    batch.reset_envs(range(n_envs))
    for i, env in enumerate(envs):
        env.reset(seed=seed + i)
    for t in range(60):
        actions = np.array([[tokens[(t * 7 + i * 3 + k) % len(tokens)] for k in range(n_robots)] for i in range(n_envs)])
        rewards, _, blocked, _, over = batch.step(actions)
        obs = batch.observations()
        for i, env in enumerate(envs):
            o, r, _, _, info = env.step({a: int(actions[i, k]) for k, a in enumerate(env.agents)})
            for k, agent in enumerate(env.possible_agents):
                assert r[agent] == rewards[i, k]
                assert np.array_equal(o[agent], obs[i, k])
                assert info[agent]["blocked"] == blocked[i, k]
            assert (not env.agents) == over[i]
            if not env.agents:
                env.reset()
        done = np.flatnonzero(over)
        if done.size:
            batch.reset_envs(done)
