"""Vector envs on the batch engine: env i plays exactly the episodes of a single env seeded ``seed + i``.

Differential tests against the references users would otherwise build: Gymnasium's
``SyncVectorEnv`` of ``BabyRobotEnv`` (next-step auto-reset), separate
``race_v0.parallel_env(finished="freeze")`` races, and SB3's ``DummyVecEnv`` (same-step auto-reset).
"""

from __future__ import annotations

import sys
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv
from gymnasium.vector.utils import batch_space

import babyrobot_marl
from babyrobot_marl import BabyRobotEnv, levels, race_v0
from babyrobot_marl.envs.vector import BabyRobotVectorEnv, RaceVectorEnv
from babyrobot_marl.policies import distances, shortest_path_actions

MODES = ("block", "bounce", "pass")
RACES = [
    ("race-2", 2, "level"),
    ("race-4", 4, "level"),
    ("race-corridor", 4, "level"),
    ("puddles", 3, "fill"),
    ("glass", 3, "fill"),
    ("mixed-8x8", 3, "random"),
]


# ---------------------------------------------------------------------------- helpers
class Driver:
    """Actions for robots seen as ``[x, y, ...]`` rows: shortest-path moves for some rows, random for others.

    Greedy rows reach exits (terminations); random rows wander (truncations); both skid on puddles.
    """

    def __init__(self, env, seed: int, greedy: float = 0.85):
        table = env.table  # a single env's or a vector env's compiled level
        self.best, self.width = shortest_path_actions(table), table.width
        self.rng, self.greedy = np.random.default_rng(seed), greedy

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        n = len(obs)
        # alternate rows: mostly greedy, mostly random
        p = np.where(np.arange(n) % 2 == 0, self.greedy, 1 - self.greedy)
        cells = obs[:, 1] * self.width + obs[:, 0]
        return np.where(self.rng.random(n) < p, self.best[cells], self.rng.integers(0, 5, n)).astype(np.int64)


def episode_limit(env) -> int:
    """Room for the greedy robots to finish (twice the longest shortest path) but not for random walks."""
    d = distances(env.table)
    return int(2 * d[np.isfinite(d)].max()) + 8


def masked(infos: dict, key: str, n: int) -> tuple[list[bool], list]:
    """A vector info's mask and its values where the mask is set (no key: nothing set)."""
    mask = infos.get(f"_{key}", np.zeros(n, dtype=bool))
    values = infos[key][mask] if mask.any() else []
    return mask.tolist(), [tuple(v) if isinstance(v, (tuple, np.ndarray)) else v for v in values]


def single_vector(level: str, n: int, **kwargs) -> SyncVectorEnv:
    return SyncVectorEnv([lambda: BabyRobotEnv(level=level, **kwargs)] * n)


def sb3():
    return pytest.importorskip("stable_baselines3", reason="needs the train extra (Stable-Baselines3)")


# ---------------------------------------------------------------------------- single robot: SyncVectorEnv
@pytest.mark.parametrize("start", [None, "random"])
@pytest.mark.parametrize("level", levels.names())
def test_vector_env_plays_the_episodes_of_a_sync_vector_env_of_single_envs(level, start):
    n = 4
    max_steps = episode_limit(BabyRobotEnv(level=level))
    ours = BabyRobotVectorEnv(n, level=level, start=start, max_steps=max_steps)
    ref = single_vector(level, n, start=start, max_steps=max_steps)
    start_cell = ours.level.free_cells()[-1]
    drive = Driver(ours, seed=1)
    terminated = truncated = 0
    total = max(260, 4 * max_steps)  # long enough for truncations between the resets below
    for t in range(total):
        if t == 0:
            got, want = ours.reset(seed=7), ref.reset(seed=7)
        elif t == total * 9 // 20:  # a later reset without a seed continues each env's generator
            got, want = ours.reset(), ref.reset()
        elif t == total * 14 // 20:  # options reach every env, as SyncVectorEnv passes them on
            got, want = ours.reset(options={"start": start_cell}), ref.reset(options={"start": start_cell})
        else:
            actions = drive(got[0])
            got, want = ours.step(actions), ref.step(actions)
            for k in range(1, 4):  # rewards, terminated, truncated
                assert got[k].dtype == want[k].dtype
                assert np.array_equal(got[k], want[k]), (t, k)
            terminated += int(got[2].sum())
            truncated += int(got[3].sum())
            for key in ("outcome", "intended"):
                assert masked(got[-1], key, n) == masked(want[-1], key, n), (t, key)
        assert np.array_equal(got[0], want[0]), t
        assert np.array_equal(got[-1]["cell"], np.array(list(want[-1]["cell"]))), t
    assert terminated > 0 and truncated > 0  # both kinds of auto-reset happened


def test_reset_mask_restarts_only_the_masked_envs_like_sync_vector_env():
    n, level = 5, "puddles"
    ours, ref = BabyRobotVectorEnv(n, level=level, start="random"), single_vector(level, n, start="random")
    got, want = ours.reset(seed=3), ref.reset(seed=3)
    drive = Driver(ours, seed=2)
    for _ in range(6):
        actions = drive(got[0])
        got, want = ours.step(actions), ref.step(actions)
    mask = np.array([True, False, True, False, False])
    got, want = ours.reset(seed=50, options={"reset_mask": mask}), ref.reset(seed=50, options={"reset_mask": mask.copy()})
    assert np.array_equal(got[0], want[0])
    assert masked(got[1], "cell", n)[0] == mask.tolist()
    for _ in range(30):
        actions = drive(got[0])
        got, want = ours.step(actions), ref.step(actions)
        for a, b in zip(got[:4], want[:4]):
            assert np.array_equal(a, b)


# ---------------------------------------------------------------------------- races: separate frozen races
def race_infos_row(info: dict) -> tuple:
    return (tuple(info["cell"].tolist()), info["outcome"], info["blocked"], info["finished"], info["rank"])


def vector_infos_row(infos: dict, k: int) -> tuple:
    rank = int(infos["rank"][k]) if "rank" in infos and infos["_rank"][k] else 0
    return (tuple(infos["cell"][k].tolist()), infos["outcome"][k], bool(infos["blocked"][k]), bool(infos["finished"][k]), rank)


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("level", "n_robots", "start"), RACES)
def test_race_vector_env_plays_the_races_of_separate_frozen_race_envs(level, n_robots, start, mode):
    _vector_plays_separate_races(dict(level=level, n_robots=n_robots, collisions=mode, start=start))


@pytest.mark.parametrize("mode", MODES[:2])
@pytest.mark.parametrize(
    "kwargs",
    [
        dict(level="race-4", n_robots=4),
        dict(level="mixed-8x8", n_robots=5, start="random", observe="local", view_radius=1),
        dict(level="race-corridor", n_robots=4, observe="nearest", k=2),
    ],
)
def test_race_vector_env_with_own_goals_plays_the_races_of_separate_frozen_race_envs(kwargs, mode):
    _vector_plays_separate_races(dict(goals="own", collisions=mode, **kwargs))


def _vector_plays_separate_races(kwargs):
    n_envs, seed, n_robots = 3, 11, kwargs["n_robots"]
    limit = episode_limit(race_v0.parallel_env(**{**kwargs, "goals": "exit"})) + 4  # own goals: the exits' scale
    ours = RaceVectorEnv(n_envs, max_cycles=limit, **kwargs)
    races = [race_v0.parallel_env(max_cycles=limit, finished="freeze", **kwargs) for _ in range(n_envs)]
    assert ours.num_envs == n_envs * n_robots
    obs, infos = ours.reset(seed=seed)
    for i, race in enumerate(races):
        o, inf = race.reset(seed=seed + i)
        for k, agent in enumerate(race.possible_agents):
            assert np.array_equal(obs[i * n_robots + k], o[agent])
            assert vector_infos_row(infos, i * n_robots + k) == race_infos_row(inf[agent])
    drive, restart = Driver(ours, seed=5), [False] * n_envs
    seen = {"terminated": 0, "truncated": 0, "blocked": 0, "ranked": 0}
    for _ in range(220):
        actions = drive(obs)
        obs, rewards, terms, truncs, infos = ours.step(actions)
        for i, race in enumerate(races):
            if restart[i]:  # next-step auto-reset: the race restarts, its actions ignored
                o, inf = race.reset()
                r = dict.fromkeys(race.possible_agents, 0.0)
                te = tr = dict.fromkeys(race.possible_agents, False)
                restart[i] = False
            else:
                o, r, te, tr, inf = race.step({a: int(actions[i * n_robots + k]) for k, a in enumerate(race.agents)})
                restart[i] = not race.agents
            for k, agent in enumerate(race.possible_agents):
                slot = i * n_robots + k
                assert np.array_equal(obs[slot], o[agent])
                assert (rewards[slot], terms[slot], truncs[slot]) == (r[agent], te[agent], tr[agent])
                assert vector_infos_row(infos, slot) == race_infos_row(inf[agent])
        seen["terminated"] += int(terms.sum())
        seen["truncated"] += int(truncs.sum())
        seen["blocked"] += int(infos["blocked"].sum())
        seen["ranked"] += int(infos["_rank"].sum())
    assert seen["terminated"] and seen["truncated"] and seen["ranked"]
    if kwargs["collisions"] != "pass":
        assert seen["blocked"]  # the collision rules were exercised


def test_race_slots_of_one_race_end_together_and_parked_robots_get_zero():
    env = RaceVectorEnv(1, level="race-corridor", n_robots=4, collisions="pass", max_cycles=200, win_bonus=10.0)
    obs, _ = env.reset(seed=0)
    best, w = shortest_path_actions(env.table), env.level.width
    parked = np.zeros(env.num_envs, dtype=bool)
    parked_rewards, parked_before_end = [], 0
    for _ in range(200):
        obs, rewards, terms, truncs, infos = env.step(best[obs[:, 1] * w + obs[:, 0]])
        done = terms | truncs
        assert done.all() or not done.any()  # all slots of the race together
        parked_rewards += rewards[parked].tolist()  # robots that had finished before this step
        if done.any():
            break
        parked = infos["finished"].copy()
        parked_before_end = max(parked_before_end, int(parked.sum()))
    assert terms.all() and 0 < parked_before_end < env.num_envs
    assert parked_rewards and set(parked_rewards) == {0.0}


# ---------------------------------------------------------------------------- Gymnasium registration and checks
def test_make_vec_builds_the_batch_vector_env_with_the_given_arguments():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # e.g. a missing autoreset_mode warns in make_vec
        env = gymnasium.make_vec(
            "babyrobot_marl/BabyRobot-v0",
            num_envs=3,
            vectorization_mode="vector_entry_point",
            level="glass",
            max_steps=7,
            glass_pass_prob=1.0,
        )
    assert isinstance(env, BabyRobotVectorEnv)
    assert (env.num_envs, env.max_steps, env.rules.glass_pass_prob, env.level.name) == (3, 7, 1.0, "glass")
    assert env.spec is not None and env.spec.id == "babyrobot_marl/BabyRobot-v0"
    assert env.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert isinstance(gymnasium.make_vec("babyrobot_marl/BabyRobot-v0", num_envs=2), BabyRobotVectorEnv)  # the default
    assert isinstance(gymnasium.make_vec("babyrobot_marl/BabyRobot-v0", num_envs=2, vectorization_mode="sync"), SyncVectorEnv)


@pytest.mark.parametrize("kind", ["single", "race"])
def test_spaces_contain_every_observation_and_arrays_have_gymnasium_dtypes(kind):
    if kind == "single":
        env = BabyRobotVectorEnv(4, level="maze-8x8", start="random", max_steps=15)
        single_obs = gymnasium.spaces.MultiDiscrete([8, 8])
    else:
        env = RaceVectorEnv(3, level="race-4", n_robots=4, max_cycles=15)
        single_obs = gymnasium.spaces.MultiDiscrete([7, 7] + [7, 7, 2] * 3)
    n = env.num_envs
    assert env.single_observation_space == single_obs
    assert env.single_action_space == gymnasium.spaces.Discrete(5)
    assert env.observation_space == batch_space(single_obs, n)
    assert env.action_space == batch_space(gymnasium.spaces.Discrete(5), n)
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    assert obs in env.observation_space and obs.dtype == np.int64
    previous = []
    for _ in range(40):
        obs, rewards, terms, truncs, infos = env.step(env.action_space.sample())
        assert obs in env.observation_space and obs.dtype == env.observation_space.dtype
        assert rewards.shape == terms.shape == truncs.shape == (n,)
        assert (rewards.dtype, terms.dtype, truncs.dtype) == (np.float64, np.bool_, np.bool_)
        assert not (terms & truncs).any()
        previous.append((obs, obs.copy()))
    assert all(np.array_equal(a, b) for a, b in previous)  # returned arrays are never reused


def test_gymnasium_episode_statistics_wrapper_sees_the_single_env_returns():
    from gymnasium.wrappers.vector import RecordEpisodeStatistics

    n, level = 3, "puddles"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ours = RecordEpisodeStatistics(BabyRobotVectorEnv(n, level=level, max_steps=20))
    ref = RecordEpisodeStatistics(single_vector(level, n, max_steps=20))
    got, want = ours.reset(seed=4), ref.reset(seed=4)
    drive, episodes = Driver(ours.unwrapped, seed=9), 0
    for _ in range(80):
        actions = drive(got[0])
        got, want = ours.step(actions), ref.step(actions)
        assert np.array_equal(got[-1].get("_episode", np.zeros(n, bool)), want[-1].get("_episode", np.zeros(n, bool)))
        if "episode" in want[-1]:
            mask = want[-1]["_episode"]
            assert np.array_equal(got[-1]["episode"]["r"][mask], want[-1]["episode"]["r"][mask])
            assert np.array_equal(got[-1]["episode"]["l"][mask], want[-1]["episode"]["l"][mask])
            episodes += int(mask.sum())
    assert episodes > n


def test_reset_with_an_int_seed_gives_env_i_seed_plus_i():
    a, b = BabyRobotVectorEnv(4, level="mixed-8x8", start="random"), BabyRobotVectorEnv(4, level="mixed-8x8", start="random")
    assert np.array_equal(a.reset(seed=30)[0], b.reset(seed=[30, 31, 32, 33])[0])
    single = [BabyRobotEnv(level="mixed-8x8", start="random").reset(seed=30 + i)[0] for i in range(4)]
    assert np.array_equal(a.reset(seed=30)[0], np.array(single))


@pytest.mark.parametrize("seed", [[1, 2], -1, "0", [0, 1, 2, -3], [0, 1, 2, 1.5]])
def test_bad_seeds_are_rejected_naming_the_seed(seed):
    env = BabyRobotVectorEnv(4)
    with pytest.raises(ValueError, match="seed"):
        env.reset(seed=seed)


def test_a_race_reset_mask_must_cover_whole_races():
    env = RaceVectorEnv(2, n_robots=2)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="reset_mask"):
        env.reset(options={"reset_mask": np.array([True, False, False, False])})
    obs, infos = env.reset(options={"reset_mask": np.array([False, False, True, True])})
    assert infos["_cell"].tolist() == [False, False, True, True]


def positions(e, kind):
    """The single env's robots where they stand (a finished robot: not drawn)."""
    if kind == "single":
        return [e.robot_cell]
    u = e.unwrapped
    return [cell if racing else None for cell, racing in zip(u.robot_cells, u._racing)]


@pytest.mark.parametrize("kind", ["single", "race"])
def test_rgb_frames_are_the_single_envs_pictures_of_the_same_positions(kind):
    """The batch keeps no step history: its frames draw each robot where it stands (no poses,
    no legend), as the single env's renderer draws those positions."""
    style = dict(render_mode="rgb_array", cell_size=8)
    if kind == "single":
        ours = BabyRobotVectorEnv(2, level="glass", start="random", **style)
        refs = [BabyRobotEnv(level="glass", start="random", **style) for _ in range(2)]
    else:
        ours = RaceVectorEnv(2, level="race-4", n_robots=4, **style)
        refs = [race_v0.parallel_env(level="race-4", n_robots=4, finished="freeze", **style) for _ in range(2)]
    obs, _ = ours.reset(seed=2)
    for i, e in enumerate(refs):
        e.reset(seed=2 + i)
    r = ours.n_robots
    drive = Driver(ours, seed=0, greedy=1.0)
    for _ in range(8):  # the greedy race-4 robots finish (and leave the picture) within 8 steps
        actions = drive(obs)
        obs = ours.step(actions)[0]
        for i, e in enumerate(refs):
            a = actions[i * r : (i + 1) * r]
            e.step(int(a[0])) if kind == "single" else e.step({ag: int(a[k]) for k, ag in enumerate(e.agents)})
        frames = ours.render()
        assert len(frames) == len(refs)
        for f, e in zip(frames, refs):
            assert f.dtype == np.uint8 and np.array_equal(f, e.unwrapped.rgb_renderer.frame(positions(e, kind)))


def test_ansi_frames_are_text_and_human_mode_is_refused():
    env = BabyRobotVectorEnv(2, render_mode="ansi")
    env.reset(seed=0)
    frames = env.render()
    assert len(frames) == 2 and all(isinstance(f, str) and "step 0/" in f for f in frames)
    with pytest.raises(ValueError, match="render_mode"):
        BabyRobotVectorEnv(2, render_mode="human")


# ---------------------------------------------------------------------------- bad actions
BAD_ACTIONS = [
    ("too many", lambda n: np.zeros(n + 1, dtype=np.int64)),
    ("column", lambda n: np.zeros((n, 1), dtype=np.int64)),
    ("floats", lambda n: np.zeros(n)),
    ("bools", lambda n: np.ones(n, dtype=bool)),
    ("five", lambda n: np.full(n, 5)),
    ("negative", lambda n: np.r_[np.zeros(n - 1, dtype=np.int64), -1]),
    ("scalar", lambda n: 1),
    ("none", lambda n: None),
    ("strings", lambda n: ["1"] * n),
]


def make_env(kind: str):
    if kind == "single":
        return BabyRobotVectorEnv(3, level="puddles", start="random", max_steps=4)
    if kind == "race":
        return RaceVectorEnv(2, level="race-4", n_robots=4, max_cycles=4)
    return babyrobot_marl.sb3_vec_env(level="puddles", n_envs=3, start="random", max_steps=4)


def reset(env, seed: int):
    if hasattr(env, "step_async"):  # SB3
        env.seed(seed)
        return env.reset()
    return env.reset(seed=seed)[0]


@pytest.mark.parametrize("kind", ["single", "race", "sb3"])
@pytest.mark.parametrize(("name", "bad"), BAD_ACTIONS, ids=[b[0] for b in BAD_ACTIONS])
def test_bad_actions_raise_naming_actions_and_change_nothing(kind, name, bad):
    if kind == "sb3":
        sb3()
    env, twin = make_env(kind), make_env(kind)
    obs, twin_obs = reset(env, 1), reset(twin, 1)
    assert np.array_equal(obs, twin_obs)
    drive = Driver(env.venv_gym if kind == "sb3" else env, seed=0)
    for t in range(10):  # crosses auto-resets (max 4 steps): a bad action right after a reset too
        with pytest.raises(ValueError, match="actions"):
            env.step(bad(env.num_envs))
        actions = drive(obs)
        got, want = env.step(actions), twin.step(actions)
        for a, b in zip(got[:-1], want[:-1]):
            assert np.array_equal(a, b), t
        obs = got[0]


@pytest.mark.parametrize("kind", ["single", "race"])
def test_stepping_before_reset_is_an_error(kind):
    env = make_env(kind)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(env.num_envs, dtype=np.int64))


# ---------------------------------------------------------------------------- Stable-Baselines3
@pytest.mark.parametrize(("level", "start"), [("puddles", None), ("glass", "random"), ("maze-8x8", "random")])
def test_sb3_vec_env_matches_dummy_vec_env_of_single_envs(level, start):
    sb3()
    from stable_baselines3.common.vec_env import DummyVecEnv

    n = 4
    limit = episode_limit(BabyRobotEnv(level=level))
    ours = babyrobot_marl.sb3_vec_env(level=level, n_envs=n, start=start, max_steps=limit)
    ref = DummyVecEnv([lambda: BabyRobotEnv(level=level, start=start, max_steps=limit)] * n)
    assert ours.seed(21) == ref.seed(21) == [21, 22, 23, 24]
    obs, want_obs = ours.reset(), ref.reset()
    assert np.array_equal(obs, want_obs)
    drive = Driver(ours.venv_gym, seed=4)
    kinds = set()
    for _ in range(200):
        actions = drive(obs)
        obs, rewards, dones, infos = ours.step(actions)
        want_obs, want_rewards, want_dones, want_infos = ref.step(actions)
        assert np.array_equal(obs, want_obs)
        assert rewards.dtype == want_rewards.dtype and np.array_equal(rewards, want_rewards)
        assert np.array_equal(dones, want_dones)
        for info, want in zip(infos, want_infos):
            assert info["TimeLimit.truncated"] == want["TimeLimit.truncated"]
            assert ("terminal_observation" in info) == ("terminal_observation" in want)
            if "terminal_observation" in want:
                assert np.array_equal(info["terminal_observation"], want["terminal_observation"])
                kinds.add(info["TimeLimit.truncated"])
    assert kinds == {True, False}  # both truncated and terminated episodes were checked


@pytest.mark.parametrize("mode", MODES)
def test_sb3_race_vec_env_resets_whole_races_in_the_same_step(mode):
    sb3()
    n_envs, n_robots, seed = 3, 4, 8
    limit = 14
    env = babyrobot_marl.sb3_vec_env(level="race-4", n_envs=n_envs, n_robots=n_robots, collisions=mode, max_cycles=limit)
    races = [
        race_v0.parallel_env(level="race-4", n_robots=n_robots, collisions=mode, max_cycles=limit, finished="freeze")
        for _ in range(n_envs)
    ]
    assert env.num_envs == n_envs * n_robots
    assert env.seed(seed) == [seed + k // n_robots for k in range(env.num_envs)]
    obs = env.reset()
    for i, race in enumerate(races):
        o, _ = race.reset(seed=seed + i)
        assert np.array_equal(obs[i * n_robots : (i + 1) * n_robots], np.array([o[a] for a in race.possible_agents]))
    drive, kinds = Driver(env.venv_gym, seed=3), set()
    for _ in range(60):
        actions = drive(obs)
        obs, rewards, dones, infos = env.step(actions)
        for i, race in enumerate(races):
            o, r, te, tr, _ = race.step({a: int(actions[i * n_robots + k]) for k, a in enumerate(race.agents)})
            ended = not race.agents
            if ended:
                o_next, _ = race.reset()
            for k, agent in enumerate(race.possible_agents):
                slot = i * n_robots + k
                assert rewards[slot] == r[agent] and dones[slot] == ended
                assert infos[slot]["TimeLimit.truncated"] == tr[agent]
                if ended:
                    assert np.array_equal(infos[slot]["terminal_observation"], o[agent])
                    assert np.array_equal(obs[slot], o_next[agent])
                    kinds.add(tr[agent])
                else:
                    assert "terminal_observation" not in infos[slot]
                    assert np.array_equal(obs[slot], o[agent])
    assert kinds == {True, False}


def test_sb3_seed_makes_the_next_reset_and_episode_reproducible():
    sb3()
    env = babyrobot_marl.sb3_vec_env(level="glass", n_envs=3, start="random", max_steps=10)
    runs = []
    for _ in range(2):
        assert env.seed(99) == [99, 100, 101]
        obs, trace = env.reset(), []
        drive = Driver(env.venv_gym, seed=1)
        for _ in range(30):
            obs, rewards, dones, _ = env.step(drive(obs))
            trace.append((obs.copy(), rewards.copy(), dones.copy()))
        runs.append(trace)
    assert all(all(np.array_equal(a, b) for a, b in zip(x, y)) for x, y in zip(*runs))
    gym_env = BabyRobotVectorEnv(3, level="glass", start="random", max_steps=10)
    env.seed(5)
    assert np.array_equal(env.reset(), gym_env.reset(seed=5)[0])  # the same seeds as the Gymnasium vector env


@pytest.mark.parametrize("n_robots", [1, 3])
def test_vec_monitor_episode_returns_equal_the_single_env_returns(n_robots):
    sb3()
    from stable_baselines3.common.vec_env import VecCheckNan, VecMonitor

    n_envs, level, limit = 2, "puddles", 18
    if n_robots == 1:
        inner = babyrobot_marl.sb3_vec_env(level=level, n_envs=n_envs, max_steps=limit)
        singles = [BabyRobotEnv(level=level, max_steps=limit) for _ in range(n_envs)]
    else:
        kwargs = dict(level=level, n_robots=n_robots, start="fill", max_cycles=limit)
        inner = babyrobot_marl.sb3_vec_env(n_envs=n_envs, **kwargs)
        singles = [race_v0.parallel_env(finished="freeze", **kwargs) for _ in range(n_envs)]
    env = VecCheckNan(VecMonitor(inner), raise_exception=True)
    env.seed(40)
    obs = env.reset()
    for i, s in enumerate(singles):
        s.reset(seed=40 + i)
    got = [[] for _ in range(env.num_envs)]
    want = [[] for _ in range(env.num_envs)]
    running = np.zeros(env.num_envs)
    lengths = np.zeros(env.num_envs, dtype=int)
    drive = Driver(inner.venv_gym, seed=6)
    for _ in range(120):
        actions = drive(obs)
        obs, _, _, infos = env.step(actions)
        for k, info in enumerate(infos):
            if "episode" in info:
                got[k].append((float(info["episode"]["r"]), int(info["episode"]["l"])))
        for i, s in enumerate(singles):
            slots = range(i * n_robots, (i + 1) * n_robots)
            if n_robots == 1:
                _, r, te, tr, _ = s.step(int(actions[i]))
                rewards, ended = [r], te or tr
            else:
                _, r, _, _, _ = s.step({a: int(actions[i * n_robots + k]) for k, a in enumerate(s.agents)})
                rewards, ended = [r[a] for a in s.possible_agents], not s.agents
            for k, rew in zip(slots, rewards):
                running[k] += rew
                lengths[k] += 1
                if ended:
                    want[k].append((running[k], int(lengths[k])))
                    running[k], lengths[k] = 0.0, 0
            if ended:
                s.reset()
    assert got == want
    assert sum(map(len, want)) >= 2 * env.num_envs  # several episodes per slot


@pytest.mark.parametrize("n_robots", [1, 2])
def test_ppo_learns_on_the_sb3_vec_env(n_robots):
    sb3()
    from stable_baselines3 import PPO

    if n_robots == 1:
        env = babyrobot_marl.sb3_vec_env(level="default", n_envs=4, max_steps=20)
    else:
        env = babyrobot_marl.sb3_vec_env(level="race-2", n_envs=4, n_robots=n_robots, max_cycles=20)
    model = PPO("MlpPolicy", env, n_steps=64, batch_size=64, n_epochs=1, seed=0)
    model.learn(512)
    assert model.get_env() is env  # used as it is, not re-wrapped in a DummyVecEnv
    assert model.num_timesteps >= 512
    actions, _ = model.predict(env.reset(), deterministic=True)
    assert actions.shape == (env.num_envs,)


def test_sb3_vec_env_without_stable_baselines3_names_the_train_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "stable_baselines3", None)
    with pytest.raises(ImportError, match=r"babyrobot_marl\[train\]"):
        babyrobot_marl.sb3_vec_env(level="default", n_envs=2)


@pytest.mark.parametrize("n_robots", [1, 3])
@pytest.mark.parametrize("mode", ["disabled", "next-step", AutoresetMode.DISABLED, AutoresetMode.NEXT_STEP])
def test_sb3_vec_env_refuses_an_autoreset_mode_sb3_cannot_honour(mode, n_robots):
    pytest.importorskip("stable_baselines3")
    level = "race-4" if n_robots > 1 else "default"
    with pytest.raises(ValueError, match=r"^autoreset_mode: a Stable-Baselines3 VecEnv always resets.*'same-step'"):
        babyrobot_marl.sb3_vec_env(level=level, n_envs=2, n_robots=n_robots, autoreset_mode=mode)
    # the mode SB3 has is accepted, and is what the env does: an ended env is reset in that same step
    env = babyrobot_marl.sb3_vec_env(level="default", n_envs=2, autoreset_mode="same-step", max_steps=1)
    env.seed(0)
    first = env.reset()
    obs, _, dones, infos = env.step(np.zeros(2, dtype=np.int64))
    assert dones.all() and (obs == first).all() and all("terminal_observation" in i for i in infos)
