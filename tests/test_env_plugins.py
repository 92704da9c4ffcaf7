"""What RL libraries need from the envs (issue 14) and the env edges of issue 15: Python's TypeError
wording, stackable infos, lazy race generator, autoreset modes, encodings, reset options and seeds."""

from __future__ import annotations

import pickle

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import SyncVectorEnv

import babyrobot_marl
from babyrobot_marl import OUTCOME_NAMES, BabyRobotEnv, BabyRobotRaceEnv, race_v0
from babyrobot_marl.envs.encodings import Encoder
from babyrobot_marl.envs.vector import BabyRobotVectorEnv, RaceVectorEnv

ENVS = {
    "single": lambda **k: BabyRobotEnv(level="puddles", **k),
    "race": lambda **k: race_v0.parallel_env(level="race-4", n_robots=4, **k),
    "race-gym": lambda **k: BabyRobotRaceEnv(level="race-4", opponents=["random"] * 3, **k),
    "vector": lambda **k: BabyRobotVectorEnv(3, level="puddles", **k),
    "race-vector": lambda **k: RaceVectorEnv(2, level="race-4", n_robots=4, **k),
}
CLASS_NAMES = {"single": "BabyRobotEnv", "race": "RaceEnv", "race-gym": "BabyRobotRaceEnv", "vector": "BabyRobotVectorEnv",
               "race-vector": "RaceVectorEnv"}  # fmt: skip


def rollout(env, kind: str, steps: int = 60, seed: int = 0):
    """Reset then random steps; yields every info (per agent for the race)."""
    rng = np.random.default_rng(seed)
    _, info = env.reset(seed=seed)
    yield info
    for _ in range(steps):
        if kind == "race":
            if not env.agents:
                _, info = env.reset()
                yield info
                continue
            out = env.step({a: int(rng.integers(5)) for a in env.agents})
        elif kind in ("vector", "race-vector"):
            out = env.step(rng.integers(0, 5, env.num_envs))
        else:
            out = env.step(int(rng.integers(5)))
            if out[2] or out[3]:
                yield out[-1]
                _, info = env.reset()
                yield info
                continue
        yield out[-1]


# ------------------------------------------------------------------ 1. Python's TypeError wording
@pytest.mark.parametrize("kind", ENVS)
def test_unknown_keyword_is_pythons_type_error_then_the_known_arguments(kind):
    pattern = rf"^{CLASS_NAMES[kind]}\.__init__\(\) got an unexpected keyword argument 'frameskip'; arguments are .*obs_encoding"
    with pytest.raises(TypeError, match=pattern):
        ENVS[kind](frameskip=4)


def test_gymnasium_make_passes_the_type_error_torchrl_matches_on():
    with pytest.raises(TypeError, match="__init__\\(\\) got an unexpected keyword argument 'render_mde'"):
        gymnasium.make("babyrobot_marl/BabyRobot-v0", render_mde="ansi")


# ------------------------------------------------------------------ 2. stackable infos
@pytest.mark.parametrize("kind", ["single", "race", "race-gym"])
def test_infos_have_the_same_numeric_keys_at_reset_and_every_step(kind):
    env = ENVS[kind]()
    keys = None
    for info in rollout(env, kind, steps=150):
        for one in info.values() if kind == "race" else [info]:
            assert keys is None or set(one) == keys
            keys = set(one)
            assert isinstance(one["cell"], np.ndarray) and one["cell"].dtype == np.int64 and one["cell"].shape == (2,)
            assert type(one["outcome"]) is int and 0 <= one["outcome"] < len(OUTCOME_NAMES)
            for key in ("intended", "blocked", "finished"):
                if key in one:
                    assert type(one[key]) is bool
            if "rank" in one:
                assert type(one["rank"]) is int and (one["rank"] > 0) == one["finished"]
    assert keys == {"single": {"cell", "outcome", "intended"}, "race": {"cell", "outcome", "blocked", "finished", "rank"},
                    "race-gym": {"cell", "outcome", "blocked", "finished", "rank", "ranks"}}[kind]  # fmt: skip


@pytest.mark.parametrize("kind", ["vector", "race-vector"])
def test_vector_infos_are_numeric_arrays_with_every_mask_set_at_every_step(kind):
    env = ENVS[kind](max_steps=6) if kind == "vector" else ENVS[kind](max_cycles=6)
    infos = list(rollout(env, kind, steps=20))
    for info in infos:
        assert {k for k in info if not k.startswith("_")} == {k[1:] for k in info if k.startswith("_")}
        for key, value in info.items():
            assert value.dtype != object, key
            if key.startswith("_"):
                assert value.all(), key
    assert START in infos[0]["outcome"] and any(START in i["outcome"] for i in infos[1:])  # restarts say so


START = OUTCOME_NAMES.index("start")


def test_outcome_names_are_exported_and_start_finished_come_last():
    assert babyrobot_marl.OUTCOME_NAMES[:5] == ("moved", "stayed", "bumped", "skidded", "glass")
    assert OUTCOME_NAMES[5:] == ("start", "finished")


# ------------------------------------------------------------------ 3. the race's generator at the first reset
def test_copies_of_an_unreset_race_play_different_races_and_a_seed_repeats_them():
    ss = pytest.importorskip("supersuit")

    def observations(seed):
        race = race_v0.parallel_env(level="mixed-8x8", n_robots=3, start="random", finished="freeze")
        env = ss.pettingzoo_env_to_vec_env_v1(race)
        venv = ss.concat_vec_envs_v1(env, 3, num_cpus=0)  # clones the race with cloudpickle
        return venv.reset(seed=seed)[0].reshape(3, 3, -1)

    obs = observations(None)
    assert not np.array_equal(obs[0], obs[1]) and not np.array_equal(obs[1], obs[2])
    assert np.array_equal(observations(4), observations(4))


def test_a_race_pickled_before_its_first_reset_draws_its_own_generator():
    env = race_v0.parallel_env(level="mixed-8x8", n_robots=3, start="random")
    copies = [pickle.loads(pickle.dumps(env)) for _ in range(4)]
    starts = {str(c.reset()[1]) for c in copies}
    assert len(starts) > 1


# ------------------------------------------------------------------ 4. autoreset modes
@pytest.mark.parametrize("mode", ["next-step", "same-step", "disabled"])
def test_vector_env_matches_sync_vector_env_step_for_step_in_every_autoreset_mode(mode):
    from gymnasium.vector import AutoresetMode

    enum = {"next-step": AutoresetMode.NEXT_STEP, "same-step": AutoresetMode.SAME_STEP, "disabled": AutoresetMode.DISABLED}[mode]
    n, kw = 3, dict(level="puddles", max_steps=7)
    ours = BabyRobotVectorEnv(n, autoreset_mode=mode, **kw)
    ref = SyncVectorEnv([lambda: BabyRobotEnv(**kw)] * n, autoreset_mode=enum)
    assert ours.autoreset_mode == ref.autoreset_mode == ours.metadata["autoreset_mode"] == enum
    rng = np.random.default_rng(0)
    got, want = ours.reset(seed=5), ref.reset(seed=5)
    ended = 0
    for t in range(60):
        if mode == "disabled" and t and (got[2] | got[3]).any():
            mask = got[2] | got[3]
            got, want = ours.reset(options={"reset_mask": mask}), ref.reset(options={"reset_mask": mask.copy()})
            assert_same(got, want)
        actions = rng.integers(0, 5, n)
        got, want = ours.step(actions), ref.step(actions)
        assert_same(got, want)
        ended += int((got[2] | got[3]).sum())
    assert ended > 3


def assert_same(got, want):
    for a, b in zip(got[:-1], want[:-1]):
        assert a.dtype == b.dtype and np.array_equal(a, b)
    gi, wi = got[-1], want[-1]
    assert set(gi) == set(wi)
    for key in wi:
        if key == "final_obs":
            assert [None if o is None else o.tolist() for o in gi[key]] == [None if o is None else o.tolist() for o in wi[key]]
        elif key == "final_info":
            assert set(gi[key]) == set(wi[key])
            for k in wi[key]:
                assert np.array_equal(gi[key][k], wi[key][k]), k
        else:
            assert np.array_equal(gi[key], wi[key]), key


def test_disabled_autoreset_refuses_to_step_an_ended_env_until_reset():
    env = BabyRobotVectorEnv(2, level="default", max_steps=2, autoreset_mode="disabled")
    env.reset(seed=0)
    env.step(np.zeros(2, dtype=np.int64))
    env.step(np.zeros(2, dtype=np.int64))
    with pytest.raises(RuntimeError, match="reset_mask"):
        env.step(np.zeros(2, dtype=np.int64))
    env.reset(options={"reset_mask": np.array([True, True])})
    env.step(np.zeros(2, dtype=np.int64))


def test_bad_autoreset_mode_is_a_value_error_naming_the_modes():
    with pytest.raises(ValueError, match="autoreset_mode: must be an AutoresetMode or one of 'next-step'"):
        BabyRobotVectorEnv(2, autoreset_mode="sometimes")


# ------------------------------------------------------------------ 5. finished="remove" and the race's ends
def test_a_race_before_its_first_reset_is_a_clear_error_for_step_set_cells_and_state():
    env = race_v0.parallel_env()
    for call in (lambda: env.step({}), lambda: env.set_cells([(0, 0), (1, 0)]), env.state):
        with pytest.raises(RuntimeError, match="reset"):
            call()


# ------------------------------------------------------------------ 6. sb3_vec_env pickles
def test_sb3_vec_env_pickles_with_the_standard_pickle_and_continues_identically():
    pytest.importorskip("stable_baselines3")
    vec = babyrobot_marl.sb3_vec_env(level="race-4", n_envs=2, n_robots=4)
    vec.seed(3)
    vec.reset()
    clone = pickle.loads(pickle.dumps(vec))
    for _ in range(20):
        a = np.random.default_rng(1).integers(0, 5, 8)
        o1, r1, d1, _ = vec.step(a)
        o2, r2, d2, _ = clone.step(a)
        assert np.array_equal(o1, o2) and np.array_equal(r1, r2) and np.array_equal(d1, d2)


# ------------------------------------------------------------------ 7. encodings
def test_encoder_onehot_and_box_of_any_multidiscrete():
    enc = Encoder([3, 2, 4], "onehot")
    assert enc(np.array([2, 0, 3])).tolist() == [0, 0, 1, 1, 0, 0, 0, 0, 1]
    assert enc(np.array([[0, 1, 0], [1, 1, 1]])).shape == (2, 9)
    box = Encoder([3, 2, 4], "box")
    assert box(np.array([2, 0, 3])).dtype == np.float32 and box.space.high.tolist() == [2, 1, 3]
    with pytest.raises(ValueError, match="obs_encoding: must be one of 'multidiscrete', 'box', 'onehot'"):
        Encoder([3], "one-hot")


@pytest.mark.parametrize("encoding", ["box", "onehot"])
@pytest.mark.parametrize("kind", ENVS)
def test_every_env_encodes_observations_inside_its_float32_box(kind, encoding):
    env, plain = ENVS[kind](obs_encoding=encoding), ENVS[kind]()
    obs, _ = env.reset(seed=2)
    ref, _ = plain.reset(seed=2)
    rows = list(obs.values()) if kind == "race" else [obs]
    refs = list(ref.values()) if kind == "race" else [ref]
    space = env.observation_space(env.possible_agents[0]) if kind == "race" else env.observation_space
    assert isinstance(space, gymnasium.spaces.Box) and space.dtype == np.float32
    for o, r in zip(rows, refs):
        assert o in space
        nvec = (plain.observation_space(plain.possible_agents[0]) if kind == "race" else plain.single_observation_space
                if kind.endswith("vector") else plain.observation_space).nvec  # fmt: skip
        assert np.array_equal(o, Encoder(nvec, encoding)(r))
    if kind == "race":
        assert env.state() in env.state_space and env.state_space.dtype == np.float32


# ------------------------------------------------------------------ issue 15: reset options and seeds
RACES = ["race", "race-gym", "race-vector"]


@pytest.mark.parametrize("kind", RACES)
def test_race_reset_option_starts_places_every_robot(kind):
    env = ENVS[kind]()
    starts = [(0, 1), (1, 1), (2, 1), (3, 1)]
    obs, _ = env.reset(seed=0, options={"starts": starts})
    first = obs["robot_0"] if kind == "race" else obs if kind == "race-gym" else obs[0]
    assert tuple(first[:2].tolist()) == starts[0]
    if kind == "race":
        assert [tuple(o[:2].tolist()) for o in obs.values()] == starts


@pytest.mark.parametrize("kind", RACES)
@pytest.mark.parametrize("starts", [[(0, 1)] * 4, [(0, 1), (1, 1), (2, 1)], [(0, 1), (1, 1), (2, 1), (99, 0)], "abc"])
def test_bad_starts_are_a_value_error_naming_the_option_and_change_nothing(kind, starts):
    env = ENVS[kind]()
    env.reset(seed=1)
    before = pickle.dumps(env)
    with pytest.raises(ValueError, match=r'options\["starts"\].*distinct open cells'):
        env.reset(options={"starts": starts})
    assert pickle.dumps(env) == before


@pytest.mark.parametrize("kind", ENVS)
def test_unknown_reset_option_is_a_user_warning_naming_the_known_ones(kind):
    env = ENVS[kind]()
    with pytest.warns(UserWarning, match="unknown option 'begin' ignored; known options are '"):
        env.reset(options={"begin": (0, 0)})


@pytest.mark.parametrize("kind", ENVS)
@pytest.mark.parametrize("seed", [True, -1, 1.5, "3"])
def test_bad_seeds_are_a_value_error_naming_seed(kind, seed):
    with pytest.raises(ValueError, match="seed"):
        ENVS[kind]().reset(seed=seed)


@pytest.mark.parametrize("kind", ENVS)
def test_numpy_integer_seeds_are_seeds(kind):
    a, b = ENVS[kind](), ENVS[kind]()
    assert str(a.reset(seed=np.int64(5))[0]) == str(b.reset(seed=5)[0])


def test_readme_pettingzoo_make_line_builds_the_race_and_race_v0_is_an_attribute():
    pettingzoo = pytest.importorskip("pettingzoo")
    env = pettingzoo.make("parallel", "babyrobot_marl/Race-v0", level="race-4", n_robots=3)
    assert env.possible_agents == ["robot_0", "robot_1", "robot_2"]
    assert babyrobot_marl.race_v0.parallel_env is race_v0.parallel_env


@pytest.mark.parametrize("encoding", ["box", "onehot"])
def test_gymnasium_env_checker_passes_on_the_encoded_envs(encoding):
    from gymnasium.utils.env_checker import check_env

    check_env(BabyRobotEnv(level="puddles", obs_encoding=encoding), skip_render_check=True)
    check_env(BabyRobotRaceEnv(level="race-4", opponents=["random"] * 3, obs_encoding=encoding), skip_render_check=True)


@pytest.mark.parametrize("observe", [dict(observe="local", view_radius=1), dict(observe="nearest", k=2)])
def test_observation_modes_get_the_encodings_too(observe):
    plain = race_v0.parallel_env(level="race-4", n_robots=4, **observe)
    env = race_v0.parallel_env(level="race-4", n_robots=4, obs_encoding="onehot", **observe)
    obs, _ = env.reset(seed=3)
    ref, _ = plain.reset(seed=3)
    space = env.observation_space("robot_0")
    assert space.shape == (int(plain.observation_space("robot_0").nvec.sum()),)
    for agent in env.agents:
        assert obs[agent] in space
        assert np.array_equal(obs[agent], Encoder(plain.observation_space(agent).nvec, "onehot")(ref[agent]))


def test_starts_option_on_drawn_levels_is_checked_on_the_level_drawn():
    env = race_v0.parallel_env(level="maze-5x5-*", n_robots=2, start="random")
    obs, _ = env.reset(seed=0, options={"starts": [(0, 0), (1, 0)]})
    assert [tuple(o[:2].tolist()) for o in obs.values()] == [(0, 0), (1, 0)]
